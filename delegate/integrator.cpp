// SPDX-License-Identifier: Apache-2.0
#include "delegate/integrator.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <new>
#include <tuple>
#include <type_traits>

#include "bsdf/frame.h"
#include "delegate/cameraConnection.h"
#include "delegate/causticScene.h"
#include "delegate/hd/token.h"
#include "delegate/lightSampling.h"
#include "delegate/rayOffset.h"
#include "delegate/shadingNormal.h"
#include "delegate/surfacePoint.h"

namespace principled::embree {
namespace {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInf = 1e30f;
constexpr int kMaxPassThrough = 64;  // transparent layers a path may cross
constexpr int kMaxCulledLayers = 4096;  // single-sided back faces a camera ray may pass

// Whether camera rays pass the back of this geometry (UsdGeomGprim doubleSided = 0); points
// and curves are closed tubes and spheres, seen from outside only.
bool culledFromBehind(const GeometryRecord& rec) {
    return !rec.doubleSided &&
           (rec.kind == GeometryRecord::Kind::Triangles || rec.kind == GeometryRecord::Kind::Sphere);
}

struct Frame {
    glm::vec3 t, b, n;
    explicit Frame(const glm::vec3& normal) : n(normal) {
        const bsdf::Frame f = bsdf::Frame::fromZ(normal);  // Duff et al. 2017
        t = f.x;
        b = f.y;
    }
    glm::vec3 toLocal(const glm::vec3& v) const {
        return {glm::dot(v, t), glm::dot(v, b), glm::dot(v, n)};
    }
    glm::vec3 toWorld(const glm::vec3& v) const { return v.x * t + v.y * b + v.z * n; }
};

// Veach 1997, "Robust Monte Carlo Methods for Light Transport Simulation", eq. 9.13 (beta 2).
float powerHeuristic(float a, float b) {
    float a2 = a * a, b2 = b * b;
    return a2 + b2 > 0.0f ? a2 / (a2 + b2) : 0.0f;
}

bool finite(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

float maxComponent(const glm::vec3& v) { return std::max({v.x, v.y, v.z}); }

// The probability that Russian roulette lets a path of throughput beta go on: min(1, sqrt(max
// component)), the rule of Cycles 3.4. A path whose throughput is >= 1 is never cut (a 0.95 cap
// killed 5 % of the bright paths at every bounce for nothing). The square root keeps dim paths
// longer than q = max(beta) did: on the sun-lit fig_specular0 that had 43 % of the pixel variance
// in light from the fourth path vertex on, which carries 0.25 % of the light; the square root cut
// the variance by 13 % for 1 % more rays, and on the closed Cornell box variance x time by 3 %
// (64 spp, 16 seeds; docs/performance.md section 5f).
float rouletteSurvival(const glm::vec3& beta) { return std::min(1.0f, std::sqrt(maxComponent(beta))); }

struct Hit {
    glm::vec3 p;   ///< world position
    glm::vec3 ng;  ///< geometric normal, facing the incoming ray
    glm::vec3 ns;  ///< shading normal, same hemisphere as ng
    const GeometryRecord* record;
    float t = 0.0f;   ///< distance along the (unit) ray
    bool backface = false;  ///< the ray hit the back of the surface (inside a closed object)
    const InstanceRecord* instance = nullptr;  ///< PointInstancer placement, else record's
    unsigned instId = RTC_INVALID_GEOMETRY_ID;  ///< Embree geomID of the top-level instance hit
    int element = 0;  ///< authored face (meshes), 0 for implicit surfaces
    unsigned triangle = 0;
    float u = 0.0f, v = 0.0f;  ///< barycentrics of corners 1 and 2
    float offset = 0.0f;  ///< how far ray origins leave the surface (offsetScale of p)
};


// Whether Embree accepts the ray: origin and direction components within its FLT_LARGE
// (1.844e18; its RayK::valid() asserts on larger ones), distances not NaN. A scene with points
// near 1e30 puts camera or bounce rays out there; such rays miss everything instead.
// The six magnitudes are compared as integers, one compare for their maximum: for floats >= 0
// the bit patterns order like the values (IEEE 754-2008, §5.10), and a NaN's lie above
// infinity's, so NaN components fail as `<=` makes them fail.
bool embreeRayValid(const glm::vec3& o, const glm::vec3& d, float tnear, float tfar) {
    constexpr uint32_t kLargeBits = std::bit_cast<uint32_t>(1.844e18f);
    uint32_t m = 0;
    for (float x : {o.x, o.y, o.z, d.x, d.y, d.z}) m = std::max(m, std::bit_cast<uint32_t>(x) & 0x7fffffffu);
    return m <= kLargeBits && tnear >= 0.0f && tnear <= tfar;
}

bool intersect(const SceneSnapshot& scene, const Ray& ray, Hit* hit) {
    if (!embreeRayValid(ray.origin, ray.direction, ray.tnear, ray.tfar)) return false;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRayHit rh;
    rh.ray.org_x = ray.origin.x, rh.ray.org_y = ray.origin.y, rh.ray.org_z = ray.origin.z;
    rh.ray.dir_x = ray.direction.x, rh.ray.dir_y = ray.direction.y, rh.ray.dir_z = ray.direction.z;
    rh.ray.tnear = ray.tnear;
    rh.ray.tfar = ray.tfar;
    rh.ray.time = 0.0f;
    rh.ray.mask = 0xffffffffu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene.scene, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    unsigned inst = rh.hit.instID[0];
    if (inst >= scene.geometryByInstance.size() || !scene.geometryByInstance[inst]) return false;
    const GeometryRecord& rec = *scene.geometryByInstance[inst];
    hit->record = &rec;
    hit->t = rh.ray.tfar;
    // PointInstancer instances share the prototype's record but have their own placement.
    const InstanceRecord* placed =
        inst < scene.instanceByInstance.size() ? scene.instanceByInstance[inst] : nullptr;
    hit->instance = placed;
    hit->instId = inst;
    const glm::mat3& normalToWorld = placed ? placed->normalToWorld : rec.normalToWorld;
    hit->p = ray.origin + rh.ray.tfar * ray.direction;
    const glm::mat4& objectToWorld = placed ? placed->objectToWorld : rec.objectToWorld;
    glm::vec3 ngObj, nsObj;
    bool smooth = false;  // nsObj interpolated from authored normals (else it is ngObj)
    if (rec.kind == GeometryRecord::Kind::Sphere) {
        glm::mat4 worldToObject = placed ? glm::inverse(placed->objectToWorld) : rec.worldToObject;
        glm::vec3 pObj = glm::vec3(worldToObject * glm::vec4(hit->p, 1.0f));
        ngObj = nsObj = pObj - rec.center;
        // Re-project onto the sphere (o + t d loses precision far from the origin).
        float l = glm::length(ngObj);
        if (l > 0.0f) hit->p = glm::vec3(objectToWorld * glm::vec4(rec.center + ngObj * (rec.radius / l), 1.0f));
    } else if (rec.kind == GeometryRecord::Kind::Points || rec.kind == GeometryRecord::Kind::Curves) {
        // Embree's sphere points and round curves: its geometric normal (object space for
        // instanced geometry) is the surface normal of the sphere or tube.
        hit->triangle = rh.hit.primID;
        hit->u = rh.hit.u;
        hit->v = rh.hit.v;
        hit->element = rh.hit.primID < rec.triangleFace.size() ? rec.triangleFace[rh.hit.primID] : 0;
        ngObj = nsObj = glm::vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
    } else {
        const glm::uvec3& t = rec.triangles[rh.hit.primID];
        hit->element = rec.triangleFace[rh.hit.primID];
        hit->triangle = rh.hit.primID;
        hit->u = rh.hit.u;
        hit->v = rh.hit.v;
        const glm::vec3 &p0 = rec.points[t.x], &p1 = rec.points[t.y], &p2 = rec.points[t.z];
        ngObj = glm::cross(p1 - p0, p2 - p0);
        // The hit point from the barycentrics: its error scales with the vertices' magnitude,
        // not with the ray's origin and distance.
        glm::vec3 pObj = (1.0f - rh.hit.u - rh.hit.v) * p0 + rh.hit.u * p1 + rh.hit.v * p2;
        hit->p = glm::vec3(objectToWorld * glm::vec4(pObj, 1.0f));
        if (!rec.cornerNormals.empty()) {
            float u = rh.hit.u, v = rh.hit.v;
            const glm::vec3* n = &rec.cornerNormals[3 * size_t(rh.hit.primID)];
            nsObj = (1.0f - u - v) * n[0] + u * n[1] + v * n[2];
            smooth = true;
        } else if (!rec.vertexNormals.empty()) {
            float u = rh.hit.u, v = rh.hit.v;
            const auto& n = rec.vertexNormals;
            nsObj = (1.0f - u - v) * n[t.x] + u * n[t.y] + v * n[t.z];
            smooth = true;
        }
    }
    glm::vec3 ng = normalToWorld * ngObj;
    float lg = glm::length(ng);
    if (!(lg > 0.0f) || !std::isfinite(lg)) {
        // The unnormalised cross product over- or underflows on triangles with edges beyond
        // ~4e9 units (a ground plane) or below ~1e-19: redone in double; only a triangle of
        // zero area (or a non-finite one) is missed.
        if (rec.kind != GeometryRecord::Kind::Triangles) return false;
        const glm::uvec3& t = rec.triangles[rh.hit.primID];
        const glm::dvec3 p0(rec.points[t.x]), p1(rec.points[t.y]), p2(rec.points[t.z]);
        const glm::dvec3 nd = glm::dmat3(normalToWorld) * glm::cross(p1 - p0, p2 - p0);
        const double l = glm::length(nd);
        if (!(l > 0.0) || !std::isfinite(l)) return false;
        ng = glm::vec3(nd / l);
        lg = 1.0f;
    }
    ng /= lg;
    glm::vec3 ns = ng;  // the same arithmetic on the same vector when not smooth
    if (smooth) {
        ns = normalToWorld * nsObj;
        float ls = glm::length(ns);
        ns = (ls > 0.0f && std::isfinite(ls)) ? ns / ls : ng;
    }
    // Shade both sides: face the normals toward the incoming ray (remembering whether the ray
    // arrived from behind, which solid transmissive materials need to know).
    hit->backface = glm::dot(ng, ray.direction) > 0.0f;
    if (hit->backface) ng = -ng;
    if (glm::dot(ns, ng) < 0.0f) ns = -ns;
    hit->ng = ng;
    hit->ns = ns;
    hit->offset = offsetScale(hit->p);  // once per hit, for all its rays
    return true;
}

bool occluded(const SceneSnapshot& scene, const glm::vec3& origin, const glm::vec3& dir,
              float tfar) {
    if (!embreeRayValid(origin, dir, 0.0f, tfar)) return true;  // no light through a broken ray
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay r;
    r.org_x = origin.x, r.org_y = origin.y, r.org_z = origin.z;
    r.dir_x = dir.x, r.dir_y = dir.y, r.dir_z = dir.z;
    r.tnear = 0.0f;
    r.tfar = tfar;
    r.time = 0.0f;
    r.mask = 0xffffffffu;
    r.id = 0;
    r.flags = 0;
    rtcOccluded1(scene.scene, &ctx, &r);
    return r.tfar < 0.0f;  // Embree sets tfar to -inf on a hit
}

// Offset a ray origin off the surface along the geometric normal, by Hit::offset (scaled to
// the position's magnitude, so large and small scenes both avoid self-intersection).
glm::vec3 offsetOrigin(const Hit& hit, const glm::vec3& dir) {
    return hit.p + (glm::dot(dir, hit.ng) >= 0.0f ? hit.offset : -hit.offset) * hit.ng;
}

// The mesh light that holds the emitting triangles of material `material` at a hit: among the
// lights of the hit's placed copy (instanced prototypes) or of its prim (consecutive, one per
// emitting material); null when none does.
const LightRecord* meshLightOf(const SceneSnapshot& scene, const GeometryRecord& rec, unsigned instId,
                               int material) {
    int first = rec.emissiveLight, count = rec.emissiveLightCount;
    if (instId < scene.instanceByInstance.size() && scene.instanceByInstance[instId]) {
        // A placed copy of an instanced prototype: its own lights, if it got any (budget).
        if (instId >= scene.instanceLights.size()) return nullptr;
        std::tie(first, count) = scene.instanceLights[instId];
    }
    const auto& lights = scene.lights;
    for (int i = first; i >= 0 && i < first + count && i < int(lights.size()); ++i)
        if (lights[size_t(i)].meshMaterial == material) return &lights[size_t(i)];
    return nullptr;
}

// Whether next-event estimation may use a light direction wi: above the geometric surface, or
// also below it when `through` (rough transmission), in which case wi must be on the same side
// of the shading surface as of the geometric one, relative to wo (the rule BSDF samples obey).
bool lightSideOk(const glm::vec3& wi, const glm::vec3& ng, const Frame& frame, const glm::vec3& woLocal,
                 bool through) {
    const float side = glm::dot(wi, ng);
    if (!through) return side > 0.0f;
    const bool transmitted = frame.toLocal(wi).z * woLocal.z < 0.0f;
    return side != 0.0f && (side > 0.0f) != transmitted;
}


// The tangent frame a normal map's x and y refer to, around n: x along dP/ds and y along
// dP/dt of the texture coordinates the map is read with (the primvar behind them, through
// UsdTransform2d's linear part; "st" when the program names none), from the triangle's edges
// and coordinate deltas. y takes dP/dt's side of n x x, so mirrored UV shells keep their
// map's green channel pointing along +t (the sign MikkTSpace stores per vertex). Any frame
// when the coordinates are missing or degenerate.
Frame tangentFrame(const Hit& hit, const glm::vec3& n, const shading::NormalMapUv* uv) {
    const GeometryRecord& rec = *hit.record;
    static const hd::Token kSt("st");  // interned once: Token() takes a global lock
    const PrimvarChannel* st = rec.primvar(uv ? uv->primvar : kSt);
    if (rec.kind == GeometryRecord::Kind::Triangles && st && !st->constant && st->components >= 2) {
        const glm::uvec3& t = rec.triangles[hit.triangle];
        glm::vec3 e1 = rec.points[t.y] - rec.points[t.x], e2 = rec.points[t.z] - rec.points[t.x];
        const float* uv0 = rec.cornerValue(*st, hit.triangle, 0);
        const float* uv1 = rec.cornerValue(*st, hit.triangle, 1);
        const float* uv2 = rec.cornerValue(*st, hit.triangle, 2);
        glm::vec2 d1(uv1[0] - uv0[0], uv1[1] - uv0[1]);
        glm::vec2 d2(uv2[0] - uv0[0], uv2[1] - uv0[1]);
        if (uv) d1 = uv->jacobian * d1, d2 = uv->jacobian * d2;  // into the texture's own (s, t)
        float det = d1.x * d2.y - d1.y * d2.x;
        if (std::abs(det) > 1e-12f && std::isfinite(det)) {
            const glm::mat3 toWorld(hit.instance ? hit.instance->objectToWorld : rec.objectToWorld);
            glm::vec3 dpds = toWorld * ((e1 * d2.y - e2 * d1.y) / det);
            glm::vec3 dpdt = toWorld * ((e2 * d1.x - e1 * d2.x) / det);
            glm::vec3 tw = dpds - n * glm::dot(n, dpds);
            float l = glm::length(tw);
            if (l > 1e-12f && std::isfinite(l)) {
                Frame f(n);
                f.t = tw / l;
                f.b = glm::cross(n, f.t);
                if (glm::dot(f.b, dpdt) < 0.0f) f.b = -f.b;  // a mirrored shell
                return f;
            }
        }
    }
    return Frame(n);
}

// A path meeting a surface whose opacity is below 1: whether it passes through, and the factor
// on its throughput either way. Presence mode and cutouts: it passes with probability
// 1 - presence, unweighted. Transparent mode (ShadedMaterial::keepsSpecular, the
// UsdPreviewSurface fallback): the surface both reflects, its specular lobes at full strength
// and the rest scaled by the opacity a (MaterialParams::diffuseScale), and lets 1 - a of the
// light through: passing is picked with probability q (below) and weighted (1 - a) / q,
// shading with 1 / (1 - q).
struct Crossing {
    bool pass = false;
    float weight = 1.0f;
    /// The camera ray's alpha (coverage) when it is shaded here: 1 in presence mode (it is
    /// shaded with probability a); a / (1 - q) in transparent mode, so that its expectation is
    /// a plus 1 - a of what lies behind (passing multiplies the alpha weight by `weight`).
    float alpha = 1.0f;
};
Crossing crossPartlyPresent(const shading::ShadedMaterial& mat, Sampler& sampler) {
    const float a = mat.presence();
    if (mat.keepsSpecular()) {
        // Passing is picked in proportion to what it carries (1 - a) against an estimate of
        // what the surface reflects (a of its diffuse, plus the specular: about 0.08 for a
        // dielectric, up to 1 for a metal), at most 0.95: at a = 0 a sheet of glass passes
        // 93 % of the paths with weight 1.08 (stacked cards stay cheap), not half with weight 2.
        const float specular = 0.08f + 0.92f * std::clamp(mat.params.metallic, 0.0f, 1.0f);
        const float q = std::min(0.95f, (1.0f - a) / (1.0f + specular));
        if (sampler.next1D() < q) return {true, (1.0f - a) / q, 1.0f};
        return {false, 1.0f / (1.0f - q), a / (1.0f - q)};
    }
    if (a <= 0.0f || sampler.next1D() >= a) return {true, 1.0f, 1.0f};
    return {};
}

// How much of the shadow rays a surface at this hit stops: its material's presence
// (UsdPreviewSurface opacity, or 0/1 with an opacityThreshold cutout).
float presenceAt(const SceneSnapshot& scene, const Hit& hit) {
    const int mi = hit.record->materialFor(hit.triangle);
    if (mi < 0 || mi >= int(scene.materials.size())) return 1.0f;
    const MaterialRecord& m = scene.materials[mi];
    if (!m.mayBePartlyPresent) return 1.0f;
    if (!m.program) return m.constant.presence();
    SurfacePoint context(*hit.record, hit.triangle, hit.u, hit.v, hit.instance);
    return m.program->presence(context);
}

// Visibility along a shadow ray: 0 when an opaque surface blocks it, else the product of
// (1 - presence) of the partly present surfaces it crosses. The camera path chooses to pass
// through such a surface with probability 1 - presence, so both estimate the same expected
// value; here the factor is exact, so cutout and partial-opacity shadows carry no extra noise.
// light: the light a shadow ray goes to (null: a ray to the camera); prims outside its
// shadow-link collection (delegate/sceneData.h) let it through.
float transmittance(const SceneSnapshot& scene, const glm::vec3& origin, const glm::vec3& dir,
                    float tfar, const LightRecord* light = nullptr) {
    const bool linked = light && light->shadowBit >= 0;
    if (!scene.anyPartlyPresent && !linked) return occluded(scene, origin, dir, tfar) ? 0.0f : 1.0f;
    if (!embreeRayValid(origin, dir, 0.0f, tfar)) return 0.0f;
    const bool bounded = tfar < kInf;
    const glm::vec3 end = origin + (bounded ? tfar : 0.0f) * dir;
    Ray r;
    r.origin = origin;
    r.direction = dir;
    r.tnear = 0.0f;
    r.tfar = tfar;
    float T = 1.0f;
    // Partly present layers count toward kMaxPassThrough (beyond it: blocked); prims a
    // shadow-linked light's shadows ignore count toward kMaxIgnoredLayers (beyond it: what is
    // left passes, as those prims would let it).
    constexpr int kMaxIgnoredLayers = 1024;
    int layers = 0, ignored = 0;
    for (;;) {
        Hit h;
        if (!intersect(scene, r, &h)) return T;
        if (linked && !light->shadowedBy(h.record->shadowLinks)) {
            if (++ignored > kMaxIgnoredLayers) return T;
        } else {
            if (++layers > kMaxPassThrough) return 0.0f;  // more layers than a path may cross
            T *= 1.0f - presenceAt(scene, h);
            if (!(T > 0.0f)) return 0.0f;
        }
        r.origin = offsetOrigin(h, dir);
        if (bounded) {
            r.tfar = glm::dot(end - r.origin, dir);
            if (!(r.tfar > 0.0f)) return T;
        }
    }
}


// The material at a hit: the bound one (evaluated here if textured; an untextured material's
// record and prebuilt BSDF are used as they are, with nothing written per hit), or
// UsdPreviewSurface defaults with displayColor.
struct HitMaterial {
    std::optional<shading::ShadedMaterial> store;
    const shading::ShadedMaterial* mat = nullptr;
    const bsdf::Bsdf* constantBsdf = nullptr;  // prebuilt for untextured materials
    int index = -1;                            // GeomSubset's or the prim's material
};

void materialAt(const SceneSnapshot& scene, const std::vector<std::optional<bsdf::Bsdf>>& constantBsdfs,
                const Hit& hit, const SurfacePoint& context, HitMaterial* out) {
    const GeometryRecord& rec = *hit.record;
    out->index = rec.materialFor(hit.triangle);
    if (out->index >= 0 && out->index < int(scene.materials.size()) && scene.materials[size_t(out->index)].hasSurface) {
        const MaterialRecord& m = scene.materials[size_t(out->index)];
        if (m.program) {
            out->mat = &out->store.emplace(m.program->evaluate(context));
        } else {
            out->mat = &m.constant;
            out->constantBsdf = &*constantBsdfs[size_t(out->index)];
        }
        return;
    }
    shading::ShadedMaterial& shaded = out->store.emplace();
    out->mat = &shaded;
    shaded.params.baseColor = rec.displayColor;
    float dc[3];
    static const hd::Token kDisplayColor("displayColor");  // interned once, not per hit
    if (context.primvar(kDisplayColor, 3, dc)) {
        // Authored NaN (clamp keeps it) reads as 0: a NaN colour dropped every sample of the prim.
        for (float& c : dc) c = std::isnan(c) ? 0.0f : std::clamp(c, 0.0f, 1.0f);
        shaded.params.baseColor = glm::vec3(dc[0], dc[1], dc[2]);
    }
    shaded.params.roughness = 0.5f;
    shaded.params.specular = 0.5f;
}

// The shading frame at a hit seen from wo (world, on the side the hit's normals face).
struct ShadingFrame {
    Frame frame;
    glm::vec3 woLocal;
    bool bumped;  // the shading normal is not the surface's own: diffuse lobes are bump-shadowed
};

ShadingFrame shadingFrame(const Hit& hit, const shading::ShadedMaterial& mat, const glm::vec3& wo,
                          bool bumpShadowing) {
    // Shading normals (interpolated or mapped) are tilted back toward the geometric normal
    // until the view's mirror direction clears the surface (validReflectionNormal): no black
    // rims, and grazing views shade like Cycles.
    glm::vec3 ns = validReflectionNormal(hit.ng, wo, hit.ns);
    // Solid dielectrics need the outward normal: inside the object the BSDF sees
    // wo.z < 0 and refracts with the inverse index of refraction.
    const bool solidTransmission = mat.params.specTrans > 0.0f && !mat.params.thin;
    if (mat.hasNormalMap && !(solidTransmission && hit.backface)) {
        // Mapped around the surface's own interpolated normal, then bent once (Cycles: the
        // Normal Map node uses the smooth normal; the closure applies the bending).
        Frame tf = tangentFrame(hit, hit.ns, mat.normalMapUv);
        glm::vec3 mapped = glm::normalize(tf.toWorld(mat.tangentNormal));
        if (std::isfinite(mapped.x)) ns = validReflectionNormal(hit.ng, wo, mapped);
    }
    if (solidTransmission && hit.backface) ns = -ns;
    Frame frame(ns);
    // A shading normal other than the surface's own (mapped or bent): its diffuse lobes are
    // shadowed by the surface (Bsdf::prepare with the smooth normal), as in Cycles.
    const bool bumped = bumpShadowing && ns != hit.ns && !(solidTransmission && hit.backface);
    return {frame, frame.toLocal(wo), bumped};
}

bsdf::Bsdf::View prepareView(const bsdf::Bsdf& bsdf, const ShadingFrame& sf, const Hit& hit) {
    return sf.bumped ? bsdf.prepare(sf.woLocal, sf.frame.toLocal(hit.ns)) : bsdf.prepare(sf.woLocal);
}

// The hit as a ray travelling along unit d would see it: normals faced toward that ray.
Hit seenAlong(const Hit& hit, const glm::vec3& d) {
    Hit h = hit;
    const glm::vec3 ng = hit.backface ? -hit.ng : hit.ng;  // as authored
    h.backface = glm::dot(ng, d) > 0.0f;
    h.ng = h.backface ? -ng : ng;
    h.ns = glm::dot(hit.ns, h.ng) < 0.0f ? -hit.ns : hit.ns;
    return h;
}

// Componentwise share of f that the sharp lobes carry (perLobe from the same evaluation);
// 0 where f is 0.
glm::vec3 lobeShare(const bsdf::LobeValues& perLobe, const glm::vec3& f, bsdf::LobeMask lobes) {
    glm::vec3 part(0.0f);
    for (int i = 0; i < bsdf::kLobeCount; ++i)
        if (lobes & (1u << i)) part += perLobe[size_t(i)];
    glm::vec3 share;
    for (int c = 0; c < 3; ++c) share[c] = f[c] > 0.0f ? std::clamp(part[c] / f[c], 0.0f, 1.0f) : 0.0f;
    return share;
}

bool anyPositive(const glm::vec3& v) { return v.x > 0.0f || v.y > 0.0f || v.z > 0.0f; }

// The lobe classes a light's diffuse / specular multipliers act on (UsdLux LightAPI).
constexpr bsdf::LobeMask kDiffuseClass = (1u << int(bsdf::Lobe::Diffuse)) | (1u << int(bsdf::Lobe::Sheen));

// f with each lobe scaled by the light's multiplier for its class; perLobe scaled in place.
glm::vec3 scaleLobes(bsdf::LobeValues* perLobe, float diffuseScale, float specularScale) {
    glm::vec3 f(0.0f);
    for (int i = 0; i < bsdf::kLobeCount; ++i) {
        (*perLobe)[size_t(i)] *= (kDiffuseClass & (1u << i)) ? diffuseScale : specularScale;
        f += (*perLobe)[size_t(i)];
    }
    return f;
}

}  // namespace

Integrator::Integrator(const SceneSnapshot& scene, const IntegratorSettings& settings)
    : _scene(scene), _settings(settings), _lightPick(scene, settings.spatialLightPick) {
    for (uint32_t i = 0; i < scene.lights.size(); ++i) {
        const LightRecord::Kind k = scene.lights[i].kind;
        if (isAreaLight(scene.lights[i]) && !scene.lights[i].point)  // rays never hit a point
            _areaLights.push_back(i);
        else if (k == LightRecord::Kind::Dome || k == LightRecord::Kind::Distant)
            _environmentLights.push_back(i);
    }
    if (_areaLights.size() > kLinearAreaLights) {
        std::vector<LightTree::Item> items;
        for (uint32_t i : _areaLights) {
            const LightRecord& l = scene.lights[i];
            const float r = lightBoundingRadius(l);
            if (std::isfinite(r) && r > 0.0f && finite(l.center))
                items.push_back({l.center, r * r, 1.0f, i});
            else
                _unboundedAreaLights.push_back(i);
        }
        _areaLightTree = LightTree(std::move(items), 1.0f);
    }
    for (const LightRecord& l : scene.lights) _lightsScaleLobes = _lightsScaleLobes || l.scalesLobes();
    _constantBsdfs.reserve(scene.materials.size());
    for (const MaterialRecord& m : scene.materials) {
        if (m.program)
            _constantBsdfs.emplace_back();
        else
            _constantBsdfs.emplace_back(std::in_place, m.constant.params, _settings.bsdf);
    }
}

bool Integrator::texturedEmission(const LightRecord& light, LightSample* ls) const {
    // The light's material at the sampled point of its triangle (textured emission).
    if (!light.mesh || ls->meshTriangle < 0 || light.meshMaterial < 0 ||
        light.meshMaterial >= int(_scene.materials.size()))
        return false;
    const MaterialRecord& m = _scene.materials[size_t(light.meshMaterial)];
    if (!m.program) return false;
    SurfacePoint point(*light.mesh, unsigned(ls->meshTriangle), ls->bary.x, ls->bary.y);
    // Emission x presence: a partly present emitter is hit (and emits) only that often.
    const glm::vec3 e = m.program->evaluate(point).emission * m.program->presence(point);
    if (!finite(e) || maxComponent(e) <= 0.0f) return false;
    ls->Li = e;
    return true;
}

PathSample Integrator::trace(const Ray& cameraRay, Sampler& sampler) const {
    PathSample out;
    out.lobes.fill(glm::vec3(0.0f));
    // Where light found after the first hit goes: before it, to emission seen directly; after a
    // delta sample (or without the lobe split), all to one lobe; after a rough sample, to each
    // lobe k in proportion f_k / f at the sampled direction (per channel). That split keeps each
    // lobe's AOV unbiased: E[f_k / p L] = integral of f_k L, whatever lobe the sample came from.
    int pathLobe = -1;
    bool pathSplit = false;
    bsdf::LobeValues pathShare;
    auto credit = [&](const glm::vec3& c) {
        if (pathSplit) {
            for (int i = 0; i < bsdf::kLobeCount; ++i) out.lobes[i] += c * pathShare[i];
        } else if (pathLobe < 0) {
            out.emission += c;
        } else {
            out.lobes[pathLobe] += c;
        }
    };
    const auto& lights = _scene.lights;
    glm::vec3 L(0.0f), beta(1.0f);
    Ray ray = cameraRay;
    bool prevDelta = true;     // the camera "lobe" is a delta: no MIS on direct hits
    float prevBsdfPdf = 0.0f;
    glm::vec3 prevNg(0.0f);
    // The light pick at the vertex the current ray left (for the MIS weights of lights it hits).
    glm::vec3 prevP(0.0f);
    float prevPickTotal = 0.0f;
    glm::vec3 prevPickNormal(0.0f);
    // The ray has passed through a partly present surface since prevP (camera rays aside): its
    // origin is no longer the vertex whose light sampling the MIS weights must match.
    bool passedThrough = false;
    int passThrough = 0;
    int culled = 0;  // single-sided back faces the camera ray passed
    // Caustic split (delegate/causticScene.h). Of a path x1..xk that ends on a caustic light,
    // light tracing (x1 connected to the camera) and photon merging (x2 on, when photons are
    // given) take the lobe labelings "x_m through a lobe that is not sharp, x_m+1..x_k through
    // sharp lobes"; the path tracer keeps the rest. causticOpen = sum over m <= j of
    // rest_m * prod_{m<i<=j} sharp_i, the chains still open after x_j (lobe shares of f at the
    // sampled directions); causticCovered = the share taken from the light the last sampled
    // direction reaches (causticOpen before that vertex times its sharp share).
    const CausticScene* caustic = causticsActive() ? _settings.caustics : nullptr;
    // MIS compensation needs both strategies and their MIS weights (delegate/sceneData.h).
    const bool compensate = _settings.misCompensation && _settings.mis && _settings.nee;
    const bool merging = caustic && _settings.photons && !_settings.photons->empty();
    glm::vec3 causticOpen(0.0f), causticCovered(0.0f);
    // With lights that scale lobe classes: the diffuse class's share of f at the direction the
    // current ray left its vertex (per channel; the specular classes hold the rest). A light
    // the ray reaches counts diffuseScale * share + specularScale * (1 - share) of its light.
    glm::vec3 prevDiffuseShare(0.0f);
    bool prevVertex = false;  // the ray left a surface (not the camera)
    uint64_t prevLightLinks = 0;  // GeometryRecord::lightLinks of that surface

    // Continues the ray beyond a surface it passes (culled, or not present): from just behind
    // it, with what is left of its range (a camera ray's clipping range was measured from the
    // camera: kept as it was, the near distance skipped whatever lay just behind the surface).
    auto passOn = [&](const Hit& at) {
        ray.origin = offsetOrigin(at, ray.direction);
        ray.tfar = std::max(0.0f, ray.tfar - at.t);
        ray.tnear = 0.0f;
    };

    float alphaWeight = 1.0f;  // the camera ray's coverage factor from transparent surfaces passed
    float shadeAlpha = 1.0f;   // the coverage of the surface it is shaded at
    // The geometric AOVs of the first surface the camera sees (a transparent-mode surface is
    // seen whether the ray passes it or not); distances from the camera, not from a surface
    // the ray passed.
    auto recordFirstHit = [&](const Hit& at, const shading::ShadedMaterial& m, int materialIndex,
                              const SurfacePoint& context) {
        FirstHit& f = out.first;
        f.hit = true;
        f.t = glm::dot(at.p - cameraRay.origin, cameraRay.direction);
        f.position = at.p;
        f.normal = at.ns;
        f.albedo = m.params.baseColor;
        f.primId = at.record->primId;
        f.instanceId = at.instance ? at.instance->instanceIndex : 0;
        f.elementId = at.element;
        f.materialId = materialIndex;
        for (size_t i = 0; i < std::min<size_t>(_settings.aovPrimvars.size(), f.primvars.size()); ++i) {
            float v[3] = {0.0f, 0.0f, 0.0f};
            context.primvar(_settings.aovPrimvars[i], 3, v);
            f.primvars[i] = glm::vec3(v[0], v[1], v[2]);
        }
    };

    for (int depth = 0;; ++depth) {
        Hit hit;
        ++out.rays;
        if (_settings.recorder) _settings.recorder->record(ray.origin, ray.direction, ray.tnear, ray.tfar, false);
        bool found = intersect(_scene, ray, &hit);
        // Emitters this ray reaches, MIS-weighted against the light sampling that would also
        // have found them. Without MIS, lights that NEE samples are counted only by NEE
        // (weight 0 here), except after a delta bounce, which NEE cannot follow; directions
        // NEE cannot produce (pdf 0, e.g. below the surface) always count fully.
        // A light that casts no shadows, or whose shadows only some prims cast, is NEE's alone
        // (it reaches through occluders, which a BSDF ray cannot), as every NEE-sampled light is
        // without MIS.
        auto addEmitter = [&](const glm::vec3& Le, float lightPdf, uint32_t li) {
            // Light linking: a light that does not light the surface the ray left adds nothing
            // there (NEE skips it too); the camera sees every light.
            if (prevVertex && !lights[li].lights(prevLightLinks)) return;
            float w = (prevDelta || lightPdf <= 0.0f || !_settings.nee) ? 1.0f
                      : (_settings.mis && !lights[li].neeOnly()) ? powerHeuristic(prevBsdfPdf, lightPdf)
                                                                   : 0.0f;
            glm::vec3 c = beta * Le * w;
            if (caustic && caustic->isCausticLight(li)) c *= glm::vec3(1.0f) - causticCovered;
            // Lobe multipliers: the light through the sampled vertex's diffuse and specular
            // classes. Leaving the first vertex with the lobe split on, each lobe's AOV takes its
            // own class's multiplier (the split is by that vertex's lobes).
            const bool scaled = prevVertex && lights[li].scalesLobes();
            const bool splitByClass = scaled && pathSplit && depth == 1;
            glm::vec3 unscaled = c;
            if (scaled)
                c *= lights[li].diffuseScale * prevDiffuseShare +
                     lights[li].specularScale * (glm::vec3(1.0f) - prevDiffuseShare);
            float clamp = 1.0f;
            if (depth > 0 && _settings.clampIndirect > 0.0f && maxComponent(c) > _settings.clampIndirect)
                clamp = _settings.clampIndirect / maxComponent(c);
            if (splitByClass) {
                for (int i = 0; i < bsdf::kLobeCount; ++i)
                    out.lobes[i] += unscaled * clamp * pathShare[i] *
                                    ((kDiffuseClass & (1u << i)) ? lights[li].diffuseScale : lights[li].specularScale);
                return;
            }
            credit(c * clamp);
        };
        float tHit = found ? hit.t : kInf;
        auto reachAreaLight = [&](uint32_t li) {
            const LightRecord& light = lights[li];
            if (depth == 0 && !(light.visibleToCamera && _settings.lightsVisible)) return;
            glm::vec3 Le;
            float pdf;
            if (intersectAreaLight(light, ray.origin, ray.direction, tHit, &Le, &pdf)) {
                // The density NEE had at prevP (the light lies beyond the surfaces crossed, so
                // the ray from prevP meets it at the same point).
                glm::vec3 LeFromVertex;
                if (passedThrough && !intersectAreaLight(light, prevP, ray.direction, kInf, &LeFromVertex, &pdf)) pdf = 0.0f;
                addEmitter(Le, pdf * _lightPick.probability(li, prevP, prevPickNormal, prevPickTotal), li);
            }
        };
        // Not every light: a scene may hold thousands of mesh lights (hit as geometry), and
        // many analytic ones are found through their tree.
        if (_areaLightTree.empty()) {
            for (uint32_t li : _areaLights) reachAreaLight(li);
        } else {
            _areaLightTree.forEachAlong(ray.origin, ray.direction, tHit, reachAreaLight);
            for (uint32_t li : _unboundedAreaLights) reachAreaLight(li);
        }
        if (!found) {
            for (uint32_t li : _environmentLights) {
                const LightRecord& light = lights[li];
                if (depth == 0 && (light.kind == LightRecord::Kind::Distant || !_settings.domeVisible)) continue;
                glm::vec3 Le;
                float pdf = 0.0f;  // not weighed after a delta bounce (the camera's included)
                // Compensation leaves part of a dome to BSDF rays, which a shadowless light's
                // occluders would block: such a light is sampled whole (NEE alone carries it).
                if (environmentRadiance(light, prevP, ray.direction, prevNg, &Le, prevDelta ? nullptr : &pdf,
                                        compensate && !light.neeOnly()))
                    addEmitter(Le, pdf * _lightPick.probability(li, prevP, prevPickNormal, prevPickTotal), li);
            }
            break;
        }

        const GeometryRecord& rec = *hit.record;
        // UsdGeomGprim doubleSided = 0 with backfaceCulling on: camera rays do not see the back
        // of a single-sided mesh or sphere (as Storm and usdrecord cull it); light transport
        // still uses both sides. Culled faces have their own budget (dense single-sided cards).
        if (depth == 0 && hit.backface && _settings.backfaceCulling && culledFromBehind(rec) &&
            culled < kMaxCulledLayers) {
            ++culled;
            passOn(hit);
            --depth;
            continue;
        }
        SurfacePoint context(*hit.record, hit.triangle, hit.u, hit.v, hit.instance);
        HitMaterial hm;
        materialAt(_scene, _constantBsdfs, hit, context, &hm);
        const shading::ShadedMaterial* mat = hm.mat;
        const int materialIndex = hm.index;
        // Partial presence (opacity, cutouts): a stochastic choice to pass through.
        float emissionScale = 1.0f;
        shadeAlpha = 1.0f;
        if (mat->presence() < 1.0f && passThrough < kMaxPassThrough) {
            const Crossing crossing = crossPartlyPresent(*mat, sampler);
            beta *= crossing.weight;
            if (crossing.pass) {
                if (depth == 0) {
                    alphaWeight *= crossing.weight;
                    if (mat->keepsSpecular() && !out.first.hit) recordFirstHit(hit, *mat, materialIndex, context);
                }
                ++passThrough;
                passOn(hit);
                passedThrough = passedThrough || depth > 0;  // camera rays need no MIS origin
                --depth;  // not a bounce
                continue;
            }
            // A transparent-mode surface emits as much as it is present (as light sampling,
            // texturedEmission, counts it).
            if (mat->keepsSpecular()) emissionScale = mat->presence();
            shadeAlpha = crossing.alpha;
        }
        if (mat->emission != glm::vec3(0.0f)) {
            // Emissive geometry that NEE samples (a mesh light) is MIS-weighted like any light.
            float lightPdf = 0.0f;
            const LightRecord* ml = meshLightOf(_scene, rec, hit.instId, materialIndex);
            if (ml) {
                const glm::vec3 from = passedThrough ? prevP : ray.origin;
                const float distance = passedThrough ? glm::length(hit.p - prevP) : hit.t;
                lightPdf = _lightPick.probability(uint32_t(ml - lights.data()), prevP, prevPickNormal, prevPickTotal) *
                           meshLightPdf(*ml, from, distance, glm::dot(ray.direction, hit.ng));
            }
            float w = (prevDelta || lightPdf <= 0.0f || !_settings.nee)
                          ? 1.0f
                          : (_settings.mis ? powerHeuristic(prevBsdfPdf, lightPdf) : 0.0f);
            glm::vec3 c = beta * mat->emission * (w * emissionScale);
            // A mesh light that light tracing starts paths from: its caustic share is theirs.
            if (caustic && ml && caustic->isCausticLight(uint32_t(ml - lights.data()))) c *= glm::vec3(1.0f) - causticCovered;
            if (depth > 0 && _settings.clampIndirect > 0.0f && maxComponent(c) > _settings.clampIndirect)
                c *= _settings.clampIndirect / maxComponent(c);
            credit(c);
        }
        if (depth == 0) {
            out.alpha = alphaWeight * shadeAlpha;
            if (!out.first.hit) recordFirstHit(hit, *mat, materialIndex, context);
        }

        glm::vec3 wo = -ray.direction;
        const ShadingFrame sf = shadingFrame(hit, *mat, wo, _settings.bumpShadowing);
        const Frame& frame = sf.frame;
        const glm::vec3& woLocal = sf.woLocal;
        // maxDepth = N: N bounces after the camera hit, Cycles' max_bounces convention (0 = direct
        // light only: NEE at the camera hit plus the emitter its BSDF ray reaches). `>=` here
        // made maxDepth 0 render emitters only and gave every path one bounce fewer than Cycles.
        if (depth > _settings.maxDepth) break;
        // Raw storage, not std::optional: its engaged-state bookkeeping zeroed 200 bytes per hit.
        static_assert(std::is_trivially_destructible_v<bsdf::Bsdf>);
        alignas(bsdf::Bsdf) std::byte builtStorage[sizeof(bsdf::Bsdf)];
        const bsdf::Bsdf& bsdf =
            hm.constantBsdf ? *hm.constantBsdf : *::new (builtStorage) bsdf::Bsdf(mat->params, _settings.bsdf);
        const bsdf::Bsdf::View view = prepareView(bsdf, sf, hit);  // shared by NEE and sampling
        // Caustic split: the lobes of this vertex light tracing counts as sharp (casters only).
        const bsdf::LobeMask sharp =
            caustic && caustic->isCaster(hit.instId) ? bsdf.sharpLobes(caustic->maxAlpha()) : 0u;
        // After the first hit, a light reached from here through a sharp lobe is partly light
        // tracing's: this vertex's sharp share of f is needed.
        const bool shareHere = sharp != 0 && anyPositive(causticOpen);

        // Caustic light after the first hit: the photons' density through the lobes that are not
        // sharp (Jensen 1996, eq. 12, with the adjoint shading-normal factor of the connection).
        if (merging && depth >= 1) {
            if (const bsdf::LobeMask rest = bsdf.lobes() & ~sharp) {
                const bsdf::Bsdf::View restView = bsdf.restrict(view, rest);
                glm::vec3 sum(0.0f);
                _settings.photons->query(hit.p, [&](const Photon& ph) {
                    if (depth + ph.sharpVertices > _settings.maxDepth) return;
                    if (std::abs(glm::dot(ph.normal, hit.ng)) < 0.9f) return;  // another surface
                    const glm::vec3 aLocal = frame.toLocal(ph.toLight);
                    const float cosG = glm::dot(ph.toLight, hit.ng);
                    const bool through = aLocal.z * woLocal.z < 0.0f;
                    if (cosG == 0.0f || (cosG > 0.0f) == through) return;
                    sum += bsdf.eval(restView, aLocal) * ph.power / std::abs(cosG);
                });
                const glm::vec3 c = beta * sum * _settings.photonScale;
                if (finite(c)) credit(c);
            }
        }

        // Next-event estimation: one light picked by power, or every light in turn when the scene
        // has few (SceneSnapshot::neeAllLights; their pick probabilities are then 1).
        const size_t neeCount = _scene.neeAllLights ? lights.size() : 1;
        // A rough transmission lobe sees lights on the far side too (a lamp inside frosted
        // glass): those samples go through the surface, on the side their shading-frame
        // direction says, as BSDF samples must (no leaks between the two normals).
        const bool neeThrough = bsdf.hasRoughTransmission();
        // The spatial pick's weights at this point (delegate/lightPick.h); a total that is not
        // positive and finite falls back to the global pick, here and in the MIS weights.
        float pickWeights[LightPick::kMaxLights];
        float pickTotal = 0.0f;
        // Lights wholly behind the surface cannot light it unless it transmits (NEE then samples
        // both sides): the pick leaves them out (delegate/lightPick.h).
        const glm::vec3 pickNormal = neeThrough ? glm::vec3(0.0f) : hit.ng;
        bool spatialPick = _lightPick.spatial() && _settings.nee && !bsdf.isDeltaOnly();
        if (spatialPick) {
            pickTotal = _lightPick.weigh(hit.p, pickNormal, pickWeights);
            spatialPick = pickTotal > 0.0f && std::isfinite(pickTotal);
            if (!spatialPick) pickTotal = 0.0f;
        }
        for (size_t nee = 0; nee < neeCount && _settings.nee && !lights.empty() && !bsdf.isDeltaOnly(); ++nee) {
            glm::vec2 u = sampler.next2D();  // dimensions (0, 1) of a fresh Sobol group
            float ul = sampler.next1D();      // dimension 2: the pick, stratified with u
            const size_t li = _scene.neeAllLights ? nee
                              : spatialPick       ? _lightPick.pick(hit.p, pickNormal, pickWeights, pickTotal, ul)
                                                  : _lightPick.globalPick(ul);
            if (!lights[li].lights(rec.lightLinks)) continue;  // light linking: not this prim's light
            const float lightPick = _lightPick.probability(uint32_t(li), hit.p, pickNormal, pickTotal);
            LightSample ls;
            if (sampleLight(lights[li], hit.p, hit.ng, u, &ls, compensate && !lights[li].neeOnly()) && ls.pdf > 0.0f &&
                lightSideOk(ls.wi, hit.ng, frame, woLocal, neeThrough) &&
                (!lights[li].texturedEmission || texturedEmission(lights[li], &ls))) {
                float bsdfPdf = 0.0f;
                bsdf::LobeValues perLobe;
                const bool split = depth == 0 && _settings.splitLobes;
                const bool share = shareHere && caustic->isCausticLight(li);
                const bool scaled = lights[li].scalesLobes();
                glm::vec3 f = bsdf.eval(view, frame.toLocal(ls.wi), &bsdfPdf, split || share || scaled ? &perLobe : nullptr);
                if (scaled) f = scaleLobes(&perLobe, lights[li].diffuseScale, lights[li].specularScale);
                if (share) f *= glm::vec3(1.0f) - causticOpen * lobeShare(perLobe, f, sharp);
                if (maxComponent(f) > 0.0f) {
                    const bool shadows = lights[li].castsShadows;
                    float visible = 1.0f;
                    if (shadows) {
                        ++out.rays;
                        glm::vec3 shadowOrigin = offsetOrigin(hit, ls.wi);
                        // Stop just short of a sampled point on an area light.
                        float tfar = ls.distance >= kInf ? kInf
                                                          : std::max(0.0f, glm::length(hit.p + ls.distance * ls.wi - shadowOrigin) * (1.0f - 1e-4f));
                        if (_settings.recorder) _settings.recorder->record(shadowOrigin, ls.wi, 0.0f, tfar, true);
                        visible = transmittance(_scene, shadowOrigin, ls.wi, tfar, &lights[li]);
                    }
                    if (visible > 0.0f) {
                        float w = (ls.delta || !_settings.mis || lights[li].neeOnly()) ? 1.0f
                                                                                    : powerHeuristic(ls.pdf * lightPick, bsdfPdf);
                        glm::vec3 scale = beta * ls.Li * (visible * w / (ls.pdf * lightPick));
                        glm::vec3 c = scale * f;
                        if (depth > 0 && _settings.clampIndirect > 0.0f && maxComponent(c) > _settings.clampIndirect)
                            c *= _settings.clampIndirect / maxComponent(c);
                        if (split) {
                            for (int i = 0; i < bsdf::kLobeCount; ++i) out.lobes[i] += scale * perLobe[i];
                        } else if (depth == 0) {
                            out.lobes[0] += c;  // not split: every lobe's share in one slot
                        } else {
                            credit(c);
                        }
                    }
                }
            }
        }

        // Continue the path by sampling the BSDF.
        glm::vec2 u = sampler.next2D();  // dimensions (0, 1) of a fresh Sobol group
        float ulobe = sampler.next1D();  // dimension 2: the lobe, stratified with u
        auto s = bsdf.sample(view, ulobe, u);
        if (!s || !(s->pdf > 0.0f)) break;
        glm::vec3 wi = frame.toWorld(s->wi);
        // Reject directions on the wrong side of the geometric surface (light leaks).
        bool transmit = s->wi.z * woLocal.z < 0.0f;  // opposite sides of the shading surface
        if ((glm::dot(wi, hit.ng) > 0.0f) == transmit) break;
        beta *= s->f / s->pdf;
        if (!finite(beta)) {
            out = PathSample();
            out.invalid = true;
            return out;
        }
        if (depth == 0) {
            pathLobe = _settings.splitLobes ? static_cast<int>(s->lobe) : 0;
            if (_settings.splitLobes && !s->delta) {
                bsdf::LobeValues perLobe;
                bsdf.eval(view, s->wi, nullptr, &perLobe);  // sums to s->f (the same evaluation)
                for (int i = 0; i < bsdf::kLobeCount; ++i)
                    for (int c = 0; c < 3; ++c)
                        pathShare[i][c] = s->f[c] > 0.0f ? std::clamp(perLobe[i][c] / s->f[c], 0.0f, 1.0f) : 0.0f;
                pathSplit = true;
            }
        }
        if (caustic && (depth == 0 || merging || anyPositive(causticOpen))) {
            // Lobe shares at the sampled direction: a delta sample goes through a sharp lobe of a
            // caster (delta lobes are sharp) or through neither class (not a caster).
            glm::vec3 sharpShare(0.0f), restShare(0.0f);
            if (s->delta) {
                sharpShare = glm::vec3(sharp != 0 ? 1.0f : 0.0f);
            } else if (sharp == 0) {
                restShare = glm::vec3(1.0f);
            } else {
                bsdf::LobeValues perLobe;
                const glm::vec3 f = bsdf.eval(view, s->wi, nullptr, &perLobe);
                sharpShare = lobeShare(perLobe, f, sharp);
                restShare = glm::vec3(1.0f) - sharpShare;
            }
            causticCovered = causticOpen * sharpShare;
            causticOpen = causticCovered + (depth == 0 || merging ? restShare : glm::vec3(0.0f));
        }
        if (_lightsScaleLobes) {
            // The diffuse class's share of f at the sampled direction (a delta lobe is specular).
            prevDiffuseShare = glm::vec3(0.0f);
            if (!s->delta) {
                bsdf::LobeValues perLobe;
                const glm::vec3 f = bsdf.eval(view, s->wi, nullptr, &perLobe);
                const glm::vec3 d = perLobe[size_t(bsdf::Lobe::Diffuse)] + perLobe[size_t(bsdf::Lobe::Sheen)];
                for (int c = 0; c < 3; ++c) prevDiffuseShare[c] = f[c] > 0.0f ? std::clamp(d[c] / f[c], 0.0f, 1.0f) : 0.0f;
            }
        }
        prevVertex = true;
        prevLightLinks = rec.lightLinks;
        // NEE samples the far side only for rough transmission (neeThrough): a direction
        // transmitted by anything else could not have come from it, so lights it reaches count
        // fully (treated like a delta bounce); otherwise they are MIS-weighted as reflections.
        prevDelta = s->delta || (transmit && !neeThrough);
        prevBsdfPdf = s->pdf;
        prevNg = hit.ng;
        prevP = hit.p;
        prevPickTotal = pickTotal;
        prevPickNormal = pickNormal;
        passedThrough = false;
        ray.origin = offsetOrigin(hit, wi);
        ray.direction = wi;
        ray.tnear = 0.0f;
        ray.tfar = kInf;

        // Russian roulette (Arvo & Kirk 1990): survive with probability q, reweight by 1/q.
        if (depth + 1 >= _settings.rouletteDepth) {
            const float q = rouletteSurvival(beta);
            if (sampler.next1D() >= q) break;
            beta /= q;
        }
    }
    L = out.emission;
    for (const auto& l : out.lobes) L += l;
    if (!finite(L)) {
        out = PathSample();
        out.invalid = true;
        return out;
    }
    out.radiance = L;
    return out;
}


bool Integrator::causticsActive() const {
    return _settings.caustics && _settings.caustics->active() && _settings.nee &&
           !(_settings.clampIndirect > 0.0f);
}

uint32_t Integrator::traceCausticPath(const EmittedRay& emitted, Sampler& sampler, const CameraConnector& camera,
                                      Splat* splats, int* count, Photon* photons, int* photonCount) const {
    *count = 0;
    *photonCount = 0;
    if (!causticsActive() || !camera.valid()) return 0;
    const CausticScene& caustic = *_settings.caustics;
    glm::vec3 beta = emitted.weight;  // the light the path carries (estimator weight)
    glm::vec3 scatter(1.0f);          // product of the scattering factors alone (roulette)
    Ray ray;
    ray.origin = emitted.origin;
    ray.direction = emitted.direction;
    uint32_t rays = 0;
    int sharpVertices = 0, passThrough = 0;
    for (int bounce = 0;; ++bounce) {
        Hit hit;
        ++rays;
        if (!intersect(_scene, ray, &hit)) break;
        SurfacePoint context(*hit.record, hit.triangle, hit.u, hit.v, hit.instance);
        HitMaterial hm;
        materialAt(_scene, _constantBsdfs, hit, context, &hm);
        const shading::ShadedMaterial& mat = *hm.mat;
        // Partial presence: the light passes through as the camera's paths do.
        if (mat.presence() < 1.0f && passThrough < kMaxPassThrough) {
            const Crossing crossing = crossPartlyPresent(mat, sampler);
            beta *= crossing.weight;
            if (crossing.pass) {
                ++passThrough;
                ray.origin = offsetOrigin(hit, ray.direction);
                --bounce;
                continue;
            }
        }
        alignas(bsdf::Bsdf) std::byte builtStorage[sizeof(bsdf::Bsdf)];
        const bsdf::Bsdf& bsdf =
            hm.constantBsdf ? *hm.constantBsdf : *::new (builtStorage) bsdf::Bsdf(mat.params, _settings.bsdf);
        const bsdf::LobeMask sharp = caustic.isCaster(hit.instId) ? bsdf.sharpLobes(caustic.maxAlpha()) : 0u;
        const glm::vec3 toLight = -ray.direction;

        // Connect to the camera through the lobes that are not sharp, once the light has been
        // through a sharp one (before that it is direct light: the path tracer's). The BSDF is
        // evaluated as the camera path sees it: wo toward the camera, wi toward the light.
        // A caustic photon for vertices after the camera paths' first hit (trace(), merging).
        if (sharpVertices > 0 && (bsdf.lobes() & ~sharp) != 0 && _settings.causticMerging &&
            *photonCount < kMaxCausticSplats && finite(beta))
            photons[(*photonCount)++] = Photon{hit.p, hit.ng, toLight, beta, sharpVertices};
        CameraConnection cc;
        const glm::vec2 uLens = sampler.next2D();
        if (sharpVertices > 0 && (bsdf.lobes() & ~sharp) != 0 && camera.connect(hit.p, uLens, &cc)) {
            const Hit seen = seenAlong(hit, -cc.toCamera);
            const GeometryRecord& rec = *hit.record;
            // Camera rays do not see the back of a single-sided mesh (trace(), depth 0).
            const bool culled = seen.backface && _settings.backfaceCulling && culledFromBehind(rec);
            const ShadingFrame sf = shadingFrame(seen, mat, cc.toCamera, _settings.bumpShadowing);
            const glm::vec3 wiLocal = sf.frame.toLocal(toLight);
            const bool transmit = wiLocal.z * sf.woLocal.z < 0.0f;
            const float cosLight = std::abs(glm::dot(seen.ng, toLight));
            // The side rule of trace()'s BSDF samples (no leaks between the two normals).
            if (!culled && (glm::dot(toLight, seen.ng) > 0.0f) != transmit && cosLight > 0.0f) {
                const bsdf::Bsdf::View view = bsdf.restrict(prepareView(bsdf, sf, seen), bsdf.lobes() & ~sharp);
                Splat sp;
                const glm::vec3 f = bsdf.eval(view, wiLocal, nullptr, _settings.splitLobes ? &sp.lobes : nullptr);
                if (anyPositive(f)) {
                    // Veach 1997, eq. 5.19 (adjoint shading normals) with the camera's importance:
                    // weight * f |ns.wi| / |ng.wi| * |ng.wo| * We G.
                    const float geo = std::abs(glm::dot(seen.ng, cc.toCamera)) / cosLight * cc.importance;
                    const glm::vec3 origin = offsetOrigin(seen, cc.toCamera);
                    const float tfar = glm::length(cc.lensPoint - origin) * (1.0f - 1e-4f);
                    ++rays;
                    if (_settings.recorder) _settings.recorder->record(origin, cc.toCamera, 0.0f, tfar, true);
                    const float visible = transmittance(_scene, origin, cc.toCamera, tfar);
                    if (visible > 0.0f && *count < kMaxCausticSplats) {
                        const glm::vec3 scale = beta * (geo * visible);
                        sp.x = cc.x;
                        sp.y = cc.y;
                        sp.value = scale * f;
                        if (_settings.splitLobes)
                            for (auto& l : sp.lobes) l *= scale;
                        if (finite(sp.value)) splats[(*count)++] = sp;
                    }
                }
            }
        }

        // Continue through the sharp lobes only, within the camera paths' bounce limit.
        if (sharp == 0 || sharpVertices + 1 > _settings.maxDepth) break;
        const ShadingFrame lf = shadingFrame(hit, mat, toLight, _settings.bumpShadowing);
        const bsdf::Bsdf::View lightView = bsdf.restrict(prepareView(bsdf, lf, hit), sharp);
        const glm::vec2 u = sampler.next2D();
        const float ulobe = sampler.next1D();
        auto s = bsdf.sample(lightView, ulobe, u);
        if (!s || !(s->pdf > 0.0f)) break;
        const glm::vec3 wi = lf.frame.toWorld(s->wi);  // onward, toward the camera's side
        const bool transmit = s->wi.z * lf.woLocal.z < 0.0f;
        if ((glm::dot(wi, hit.ng) > 0.0f) == transmit) break;
        const float cosIn = std::abs(glm::dot(hit.ng, toLight)), cosOut = std::abs(glm::dot(hit.ng, wi));
        if (!(cosIn > 0.0f)) break;
        glm::vec3 factor;
        if (s->delta) {
            // A mirror or smooth glass scatters alike both ways; the shading-normal term remains.
            factor = s->f / s->pdf * (cosOut / cosIn);
        } else {
            // The camera path's BSDF at this vertex (wo onward, wi toward the light), sharp lobes
            // only: the light path's density picked wi, the value must be the camera's.
            const Hit seen = seenAlong(hit, -wi);
            const ShadingFrame cf = shadingFrame(seen, mat, wi, _settings.bumpShadowing);
            const bsdf::Bsdf::View view = bsdf.restrict(prepareView(bsdf, cf, seen), sharp);
            const glm::vec3 f = bsdf.eval(view, cf.frame.toLocal(toLight));
            factor = f / s->pdf * (cosOut / cosIn);
        }
        if (!finite(factor) || !anyPositive(factor)) break;
        beta *= factor;
        scatter *= factor;
        ++sharpVertices;
        ray.origin = offsetOrigin(hit, wi);
        ray.direction = wi;
        ray.tnear = 0.0f;
        ray.tfar = kInf;
        // Russian roulette on the scattering alone (Arvo & Kirk 1990), as trace() does.
        if (bounce + 1 >= _settings.rouletteDepth) {
            const float q = rouletteSurvival(scatter);
            if (sampler.next1D() >= q) break;
            beta /= q;
            scatter /= q;
        }
    }
    return rays;
}

}  // namespace principled::embree
