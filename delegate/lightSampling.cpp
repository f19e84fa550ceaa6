// SPDX-License-Identifier: Apache-2.0
#include "delegate/lightSampling.h"

#include "delegate/sphericalTriangle.h"

#include "bsdf/frame.h"
#include "bsdf/warp.h"

#include <algorithm>
#include <cmath>

namespace principled::embree {
namespace {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInf = 1e30f;

// Tangents around a unit normal (Duff et al. 2017, via bsdf::Frame::fromZ).
void basis(const glm::vec3& n, glm::vec3* t, glm::vec3* b) {
    const bsdf::Frame f = bsdf::Frame::fromZ(n);
    *t = f.x;
    *b = f.y;
}

// A point uniform in area on a mesh light: a triangle by the area CDF (u.x reused inside the
// chosen cell), then a uniform point on it (Pharr et al. 2023, §6.5.4: b0 = 1 - sqrt(u0),
// b1 = v sqrt(u0)). Returns the triangle's index in meshWorld (-1: a degenerate one), the
// point and its barycentrics (b1, b2).
int meshAreaPoint(const LightRecord& l, const glm::vec2& u, glm::vec3* q, glm::vec2* bary) {
    const std::vector<MeshLightTriangle>& world = *l.meshWorld;
    const auto& cdf = *l.meshAreaCdf;
    size_t n = world.size();
    if (n == 0) return -1;
    size_t i = size_t(std::upper_bound(cdf.begin() + 1, cdf.end() - 1, u.x) - (cdf.begin() + 1));
    i = std::min(i, n - 1);
    float cell = cdf[i + 1] - cdf[i];
    float ux = cell > 0.0f ? std::clamp((u.x - cdf[i]) / cell, 0.0f, 1.0f) : 0.5f;
    const MeshLightTriangle& t = world[i];
    if (!(t.area > 0.0f)) return -1;
    float su = std::sqrt(ux);
    *q = (1.0f - su) * t.a + (u.y * su) * t.b + ((1.0f - u.y) * su) * t.c;
    *bary = glm::vec2(u.y * su, (1.0f - u.y) * su);
    return int(i);
}

// Area-measure pdf of a point on a surface converted to solid angle at distance dist.
float toSolidAngle(float areaPdf, float dist, float cosLight) {
    return cosLight > 1e-7f ? areaPdf * dist * dist / cosLight : 0.0f;
}

// The texel of an image that holds the point (u, v) of [0, 1]^2, v = 0 the top row: nearest
// texel, the lookup of both the dome and the rect light (their sampling distributions are
// piecewise constant over the same texels).
const glm::vec3& nearestTexel(const EnvironmentMap& img, float u, float v) {
    int x = std::clamp(int(u * img.width), 0, img.width - 1);
    int y = std::clamp(int(v * img.height), 0, img.height - 1);
    return img.texels[size_t(y) * img.width + x];
}

glm::vec3 envLookup(const LightRecord& l, const glm::vec3& dWorld) {
    glm::vec2 uv = directionToLatLong(l.domeWorldToLocal * dWorld);
    return nearestTexel(*l.environment, uv.x, uv.y) * l.radiance;
}

// A rect light's texture at rectangle coordinates (a, b) in [-1, 1]^2 along (axisU, axisV):
// texel (0, 0) (the image's top left) at (+X, +Y) and (1, 1) at (-X, -Y) (UsdLuxRectLight
// schema), so the image reads upright and unmirrored from the lit side. Nearest texel, as the
// dome's lookup.
glm::vec3 rectTexel(const LightRecord& l, float a, float b) {
    if (!l.rectTexture) return glm::vec3(1.0f);
    return nearestTexel(*l.rectTexture, 0.5f * (1.0f - a), 0.5f * (1.0f - b));
}

float envPdf(const LightRecord& l, const glm::vec3& dWorld, bool misCompensation) {
    const EnvironmentMap& env = *l.environment;
    glm::vec3 d = l.domeWorldToLocal * dWorld;
    glm::vec2 uv = directionToLatLong(d);
    float sinTheta = std::sqrt(std::max(0.0f, 1.0f - d.y * d.y));
    if (sinTheta <= 1e-6f) return 0.0f;
    // Pharr et al. 2023, PBR 4th ed. §12.5.2: p(w) = p(u,v) / (2 pi^2 sin theta).
    return env.sampling(misCompensation).pdf(uv) / (2.0f * kPi * kPi * sinTheta);
}

// The share of a dome's samples drawn through portals at points that receive through them: half
// for a constant dome; a quarter for a textured one, whose own distribution finds a sun in the
// window that uniform portal sampling would miss (bench/hdri_scene.py rooms, performance.md 5g:
// 0.5 made the sunlit room's variance 61 % higher than without the portal, 0.25 9 %).
float portalShare(const LightRecord& l) { return l.environment && l.environment->latLong ? 0.25f : 0.5f; }

// The dome's own density for direction d (its map, or cosine about ng for a constant dome).
float domeOwnPdf(const LightRecord& l, const glm::vec3& d, const glm::vec3& ng, bool misCompensation) {
    if (l.environment && l.environment->latLong) return envPdf(l, d, misCompensation);
    return std::max(0.0f, glm::dot(ng, d)) / kPi;
}

// The dome's density for d at p: its own, or the portal mixture where p receives through one.
float domeMixturePdf(const LightRecord& l, const glm::vec3& p, const glm::vec3& d, const glm::vec3& ng,
                     bool misCompensation) {
    const float own = domeOwnPdf(l, d, ng, misCompensation);
    if (!l.portals || !(l.portals->weight(p) > 0.0f)) return own;
    const float q = portalShare(l);
    return q * l.portals->pdf(p, d) + (1.0f - q) * own;
}

// Ray-sphere, nearest t > 1e-4 (Pharr et al. 2023, §6.2.2, the numerically careful quadratic).
bool raySphere(const glm::vec3& o, const glm::vec3& d, const glm::vec3& c, float r, float* t) {
    glm::vec3 oc = o - c;
    float b = glm::dot(oc, d);
    glm::vec3 perp = oc - b * d;
    float disc = r * r - glm::dot(perp, perp);
    if (disc < 0.0f) return false;
    float sq = std::sqrt(disc);
    float q = -b + (b < 0.0f ? sq : -sq);
    float t0 = glm::dot(oc, oc) - r * r;  // c in the quadratic
    float ta = q, tb = q != 0.0f ? t0 / q : ta;
    float t1 = std::min(ta, tb), t2 = std::max(ta, tb);
    float eps = 1e-4f * std::max(1.0f, r);
    if (t1 > eps) *t = t1;
    else if (t2 > eps) *t = t2;
    else return false;
    return true;
}

// Mesh lights of at most this many triangles are sampled by solid angle (each triangle picked
// in proportion to the solid angle it subtends, then a uniform direction inside it: the
// directions are uniform over everything the light covers, pdf 1 / total solid angle). Larger
// meshes keep area sampling (picking by solid angle would cost a pass over every triangle).
constexpr size_t kSolidAngleMaxTriangles = 8;
// Below this total solid angle (a far or edge-on light) the spherical construction loses
// precision and area sampling is as good (the 1/r^2 factor is nearly constant over the light);
// above it a point is almost enclosed. The same test decides sampleLight() and the MIS pdf.
constexpr float kMinSolidAngle = 1e-3f, kMaxSolidAngle = 6.2f;
// Solid-angle sampling only within this many bounding radii of the light's centre. Measured
// (branch lights): with 64 Owen-scrambled Sobol samples the area estimator's relative standard
// deviation beyond 2 radii is <= 2 % at every elevation tried (15-90 degrees), and the Cornell
// box's error against a 2048-spp reference is the same at 2 and 4 radii (full paths and direct
// light only) while 2 costs 6.5 % less CPU; at 1 radius the direct-light error rises.
constexpr float kNearRadii = 2.0f;

// The spherical triangles of a small mesh light's triangles seen from p and their total solid
// angle; returns 0 when the light is sampled by area from p instead.
float meshSphericalTriangles(const LightRecord& l, const glm::vec3& p, SphericalTriangle* tris) {
    const std::vector<MeshLightTriangle>& world = *l.meshWorld;
    size_t n = world.size();
    if (n > kSolidAngleMaxTriangles) return 0.0f;
    // Far from the light (beyond kNearRadii bounding radii) 1/r^2 and the cosine barely vary
    // over it, area sampling is nearly as good and costs no trigonometry: one distance test.
    glm::vec3 toC = p - l.center;
    if (glm::dot(toC, toC) > kNearRadii * kNearRadii * l.radius * l.radius) return 0.0f;
    float total = 0.0f;
    for (size_t i = 0; i < n; ++i) {
        makeSphericalTriangle(p, world[i].a, world[i].b, world[i].c, &tris[i]);
        total += tris[i].solidAngle;
    }
    return (total >= kMinSolidAngle && total <= kMaxSolidAngle) ? total : 0.0f;
}

}  // namespace

float meshLightPdf(const LightRecord& l, const glm::vec3& origin, float distance, float cosLight) {
    SphericalTriangle tris[kSolidAngleMaxTriangles];
    float total = l.solidAngleSampling ? meshSphericalTriangles(l, origin, tris) : 0.0f;
    if (total > 0.0f) return 1.0f / total;
    return toSolidAngle(1.0f / l.area, distance, std::abs(cosLight));
}

bool isAreaLight(const LightRecord& l) {
    return l.kind == LightRecord::Kind::Sphere || l.kind == LightRecord::Kind::Rect ||
           l.kind == LightRecord::Kind::Disk || l.kind == LightRecord::Kind::Cylinder;
}

glm::vec2 directionToLatLong(const glm::vec3& d) {
    float u = 0.5f - std::atan2(d.x, d.z) / (2.0f * kPi);
    float v = std::acos(std::clamp(d.y, -1.0f, 1.0f)) / kPi;
    u -= std::floor(u);
    return {u, std::clamp(v, 0.0f, 1.0f)};
}

glm::vec3 latLongToDirection(const glm::vec2& uv) {
    float phi = (0.5f - uv.x) * 2.0f * kPi;  // atan2(x, z)
    float theta = uv.y * kPi;
    float s = std::sin(theta);
    return {s * std::sin(phi), std::cos(theta), s * std::cos(phi)};
}

namespace {
// Barycentrics (of corners b and c) of a point q on triangle t's plane, clamped into the
// triangle: Ericson 2005, "Real-Time Collision Detection", section 3.4 (Cramer's rule).
glm::vec2 barycentrics(const glm::vec3& q, const MeshLightTriangle& t) {
    const glm::vec3 e1 = t.b - t.a, e2 = t.c - t.a, d = q - t.a;
    const float d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
    const float d1 = glm::dot(d, e1), d2 = glm::dot(d, e2);
    const float det = d11 * d22 - d12 * d12;
    if (!(det > 0.0f)) return glm::vec2(1.0f / 3.0f);
    float v = std::clamp((d22 * d1 - d12 * d2) / det, 0.0f, 1.0f);
    float w = std::clamp((d11 * d2 - d12 * d1) / det, 0.0f, 1.0f);
    if (v + w > 1.0f) {
        const float s = v + w;
        v /= s, w /= s;
    }
    return {v, w};
}

bool sampleUnshaped(const LightRecord& l, const glm::vec3& p, const glm::vec3& ng, const glm::vec2& u,
                    LightSample* out, bool misCompensation) {
    *out = LightSample();
    switch (l.kind) {
        case LightRecord::Kind::Distant: {
            if (l.cosHalfAngle >= 1.0f) {
                out->wi = -l.direction;
                out->Li = l.irradiance;
                out->pdf = 1.0f;
                out->delta = true;
                return true;
            }
            // Uniform in the disc's cone: pdf = 1 / (2 pi (1 - cos)).
            glm::vec3 t, b, n = -l.direction;
            basis(n, &t, &b);
            // 1 - cos as its own number: near 1 the cosine itself keeps few digits.
            const float om = u.x * l.oneMinusCosHalfAngle;
            float c = 1.0f - om;
            float s = std::sqrt(std::max(0.0f, om * (2.0f - om))), phi = 2.0f * kPi * u.y;
            out->wi = s * std::cos(phi) * t + s * std::sin(phi) * b + c * n;
            out->Li = l.radiance;
            out->pdf = 1.0f / (2.0f * kPi * l.oneMinusCosHalfAngle);
            return true;
        }
        case LightRecord::Kind::Dome: {
            // With portals p receives the sky through, a mixture: directions through a portal
            // (portalShare() of the samples) or the dome's own; the pdf is the mixture's.
            glm::vec2 v = u;
            bool throughPortal = false;
            const bool portals = l.portals && l.portals->weight(p) > 0.0f;
            if (portals) {
                const float q = portalShare(l);
                throughPortal = u.x < q;
                v.x = throughPortal ? u.x / q : (u.x - q) / (1.0f - q);
                v.x = std::min(v.x, 0.99999994f);
                if (throughPortal) {
                    float portalPdf;
                    if (!l.portals->sample(p, v, &out->wi, &portalPdf)) return false;
                    out->Li = l.environment && l.environment->latLong ? envLookup(l, out->wi) : l.radiance;
                    out->pdf = domeMixturePdf(l, p, out->wi, ng, misCompensation);
                    return out->pdf > 0.0f;
                }
            }
            if (l.environment && l.environment->latLong) {
                const EnvironmentMap& env = *l.environment;
                float mapPdf = 0.0f;
                glm::vec2 uv = env.sampling(misCompensation).sample(v, &mapPdf);
                glm::vec3 dLocal = latLongToDirection(uv);
                float sinTheta = std::sqrt(std::max(0.0f, 1.0f - dLocal.y * dLocal.y));
                if (sinTheta <= 1e-6f || mapPdf <= 0.0f) return false;
                out->wi = glm::normalize(l.domeLocalToWorld * dLocal);
                out->Li = envLookup(l, out->wi);
                out->pdf = portals ? domeMixturePdf(l, p, out->wi, ng, misCompensation)
                                   : mapPdf / (2.0f * kPi * kPi * sinTheta);
                return out->pdf > 0.0f;
            }
            // Constant dome: cosine-weighted about the geometric normal (pdf cos/pi).
            glm::vec3 t, b;
            basis(ng, &t, &b);
            float r = std::sqrt(v.x), phi = 2.0f * kPi * v.y;
            float z = std::sqrt(std::max(0.0f, 1.0f - v.x));
            out->wi = r * std::cos(phi) * t + r * std::sin(phi) * b + z * ng;
            out->Li = l.radiance;
            out->pdf = portals ? domeMixturePdf(l, p, out->wi, ng, misCompensation) : z / kPi;
            return out->pdf > 0.0f;
        }
        case LightRecord::Kind::Sphere: {
            glm::vec3 toC = l.center - p;
            float d2 = glm::dot(toC, toC);
            if (l.point) {
                // A point: irradiance I / d^2 along the one direction (a delta light).
                const float dist = std::sqrt(d2);
                if (!(dist > 0.0f) || !std::isfinite(dist)) return false;
                out->wi = toC / dist;
                out->distance = dist;
                out->Li = l.radiance / d2;
                out->pdf = 1.0f;
                out->delta = true;
                return true;
            }
            if (d2 <= l.radius * l.radius) return false;  // inside the light
            float dist = std::sqrt(d2);
            // Uniform in the cone the sphere subtends (Pharr et al. 2023, §6.2.4).
            float sinMax2 = l.radius * l.radius / d2;
            float cosMax = std::sqrt(std::max(0.0f, 1.0f - sinMax2));
            glm::vec3 n = toC / dist, t, b;
            basis(n, &t, &b);
            float c = 1.0f - u.x * (1.0f - cosMax);
            float s = std::sqrt(std::max(0.0f, 1.0f - c * c)), phi = 2.0f * kPi * u.y;
            out->wi = s * std::cos(phi) * t + s * std::sin(phi) * b + c * n;
            float th = 0.0f;
            if (!raySphere(p, out->wi, l.center, l.radius, &th)) th = dist - l.radius;
            out->distance = th;
            out->Li = l.radiance;
            out->pdf = 1.0f / (2.0f * kPi * std::max(1.0f - cosMax, 1e-9f));
            return true;
        }
        case LightRecord::Kind::Rect:
        case LightRecord::Kind::Disk: {
            glm::vec3 q;
            glm::vec3 texel(1.0f);
            if (l.kind == LightRecord::Kind::Rect) {
                const float a = 2.0f * u.x - 1.0f, b = 2.0f * u.y - 1.0f;
                q = l.center + a * l.axisU + b * l.axisV;
                texel = rectTexel(l, a, b);
            } else {
                glm::vec3 normal;
                lightSurfacePoint(l, u, &q, &normal);
            }
            glm::vec3 toQ = q - p;
            float dist = glm::length(toQ);
            if (!(dist > 0.0f)) return false;
            out->wi = toQ / dist;
            float cosL = -glm::dot(out->wi, l.normal);
            if (cosL <= 0.0f) return false;  // one-sided: p is behind the emitter
            out->pdf = toSolidAngle(1.0f / l.area, dist, cosL);
            out->distance = dist;
            out->Li = l.radiance * texel;
            return out->pdf > 0.0f;
        }
        case LightRecord::Kind::Mesh: {
            const std::vector<MeshLightTriangle>& world = *l.meshWorld;
            SphericalTriangle tris[kSolidAngleMaxTriangles];
            if (float total = l.solidAngleSampling ? meshSphericalTriangles(l, p, tris) : 0.0f; total > 0.0f) {
                // Triangle i with probability omega_i / total (u.x reused inside the cell), then
                // a uniform direction in its spherical triangle: pdf = 1 / total.
                size_t n = world.size(), i = 0;
                float target = u.x * total, acc = 0.0f;
                while (i + 1 < n && acc + tris[i].solidAngle <= target) acc += tris[i++].solidAngle;
                float omega = tris[i].solidAngle;
                float ux = omega > 0.0f ? std::clamp((target - acc) / omega, 0.0f, 1.0f) : 0.5f;
                glm::vec3 wi;
                if (!sampleSphericalTriangle(tris[i], glm::vec2(ux, u.y), &wi)) return false;
                const MeshLightTriangle& t = world[i];
                float denom = glm::dot(wi, t.normal);
                if (denom == 0.0f) return false;
                float dist = glm::dot(t.a - p, t.normal) / denom;  // the triangle's plane along wi
                if (!(dist > 0.0f) || !std::isfinite(dist)) return false;
                out->wi = wi;
                out->pdf = 1.0f / total;
                out->distance = dist;
                out->Li = l.radiance;
                out->meshTriangle = int((*l.meshTriangles)[i]);
                out->bary = barycentrics(p + dist * wi, t);
                return true;
            }
            glm::vec3 q;
            glm::vec2 bary;
            const int i = meshAreaPoint(l, u, &q, &bary);
            if (i < 0) return false;
            const MeshLightTriangle& t = world[size_t(i)];
            glm::vec3 toQ = q - p;
            float dist = glm::length(toQ);
            if (!(dist > 0.0f)) return false;
            out->wi = toQ / dist;
            float cosL = std::abs(glm::dot(out->wi, t.normal));
            out->pdf = toSolidAngle(1.0f / l.area, dist, cosL);
            out->distance = dist;
            out->Li = l.radiance;
            out->meshTriangle = int((*l.meshTriangles)[size_t(i)]);
            out->bary = bary;
            return out->pdf > 0.0f;
        }
        case LightRecord::Kind::Cylinder: {
            glm::vec3 q, radial;
            lightSurfacePoint(l, u, &q, &radial);
            glm::vec3 toQ = q - p;
            float dist = glm::length(toQ);
            if (!(dist > 0.0f)) return false;
            out->wi = toQ / dist;
            float cosL = -glm::dot(out->wi, radial);
            if (cosL <= 0.0f) return false;
            out->pdf = toSolidAngle(1.0f / l.area, dist, cosL);
            out->distance = dist;
            out->Li = l.radiance;
            return out->pdf > 0.0f;
        }
    }
    return false;
}

}  // namespace

bool sampleLight(const LightRecord& l, const glm::vec3& p, const glm::vec3& ng, const glm::vec2& u,
                 LightSample* out, bool misCompensation) {
    if (!sampleUnshaped(l, p, ng, u, out, misCompensation)) return false;
    if (l.shaping.enabled) {
        // The emission direction is from the sampled point toward p: -wi (the pdf is unchanged).
        out->Li *= shapingFactor(l.shaping, -out->wi);
        if (out->Li == glm::vec3(0.0f)) return false;
    }
    return true;
}

namespace {
bool intersectUnshaped(const LightRecord& l, const glm::vec3& o, const glm::vec3& d, float tmax,
                       glm::vec3* Le, float* pdf) {
    switch (l.kind) {
        case LightRecord::Kind::Sphere: {
            float t;
            if (l.point) return false;  // rays never hit a point
            if (!raySphere(o, d, l.center, l.radius, &t) || t >= tmax) return false;
            glm::vec3 toC = l.center - o;
            float d2 = glm::dot(toC, toC);
            if (d2 <= l.radius * l.radius) return false;
            float cosMax = std::sqrt(std::max(0.0f, 1.0f - l.radius * l.radius / d2));
            *Le = l.radiance;
            *pdf = 1.0f / (2.0f * kPi * std::max(1.0f - cosMax, 1e-9f));
            return true;
        }
        case LightRecord::Kind::Rect:
        case LightRecord::Kind::Disk: {
            float denom = glm::dot(d, l.normal);
            if (denom >= 0.0f) return false;  // seen from behind (or edge-on): no emission
            float t = glm::dot(l.center - o, l.normal) / denom;
            if (!(t > 1e-6f) || t >= tmax) return false;
            glm::vec3 q = o + t * d - l.center;
            float a = glm::dot(q, l.axisU) / glm::dot(l.axisU, l.axisU);
            float b = glm::dot(q, l.axisV) / glm::dot(l.axisV, l.axisV);
            bool inside = l.kind == LightRecord::Kind::Rect ? (std::abs(a) <= 1.0f && std::abs(b) <= 1.0f)
                                                            : (a * a + b * b <= 1.0f);
            if (!inside) return false;
            *Le = l.kind == LightRecord::Kind::Rect ? l.radiance * rectTexel(l, a, b) : l.radiance;
            *pdf = toSolidAngle(1.0f / l.area, t, -denom);
            return true;
        }
        case LightRecord::Kind::Cylinder: {
            glm::vec3 axis = glm::normalize(l.axisU);
            float halfLen = glm::length(l.axisU);
            glm::vec3 oc = o - l.center;
            glm::vec3 dp = d - glm::dot(d, axis) * axis, op = oc - glm::dot(oc, axis) * axis;
            float A = glm::dot(dp, dp), B = 2.0f * glm::dot(dp, op), C = glm::dot(op, op) - l.radius * l.radius;
            float disc = B * B - 4.0f * A * C;
            if (A <= 0.0f || disc < 0.0f) return false;
            float sq = std::sqrt(disc);
            for (float t : {(-B - sq) / (2.0f * A), (-B + sq) / (2.0f * A)}) {
                if (!(t > 1e-4f) || t >= tmax) continue;
                glm::vec3 q = oc + t * d;
                float h = glm::dot(q, axis);
                if (std::abs(h) > halfLen) continue;
                glm::vec3 radial = glm::normalize(q - h * axis);
                float cosL = -glm::dot(d, radial);
                if (cosL <= 0.0f) return false;  // the inside does not emit
                *Le = l.radiance;
                *pdf = toSolidAngle(1.0f / l.area, t, cosL);
                return true;
            }
            return false;
        }
        default: return false;
    }
}

}  // namespace

float lightBoundingRadius(const LightRecord& l) {
    // A rect or disk placed by a shearing transform (a non-uniform scale above a rotation) has
    // axes that are not perpendicular to each other or to its normal; the region the exact
    // intersection accepts is then not held by these spheres: unbounded.
    auto sheared = [&l]() {
        const glm::vec3 u = glm::normalize(l.axisU), v = glm::normalize(l.axisV);
        const float tolerance = 1e-4f;
        return !(std::abs(glm::dot(u, v)) <= tolerance && std::abs(glm::dot(u, l.normal)) <= tolerance &&
                 std::abs(glm::dot(v, l.normal)) <= tolerance);
    };
    switch (l.kind) {
        case LightRecord::Kind::Sphere:
        case LightRecord::Kind::Mesh:
            return l.radius;
        case LightRecord::Kind::Rect:  // axisU, axisV: half extents
            if (sheared()) return INFINITY;
            return std::sqrt(glm::dot(l.axisU, l.axisU) + glm::dot(l.axisV, l.axisV));
        case LightRecord::Kind::Disk:
            if (sheared()) return INFINITY;
            return std::max(glm::length(l.axisU), glm::length(l.axisV));
        case LightRecord::Kind::Cylinder:  // axisU: half the length
            return std::sqrt(glm::dot(l.axisU, l.axisU) + l.radius * l.radius);
        default:
            return 0.0f;
    }
}

bool lightSurfacePoint(const LightRecord& l, const glm::vec2& u, glm::vec3* p, glm::vec3* n) {
    switch (l.kind) {
        case LightRecord::Kind::Sphere: {
            const float z = 1.0f - 2.0f * u.x, r = std::sqrt(std::max(0.0f, 1.0f - z * z));
            const float phi = 2.0f * kPi * u.y;
            *n = glm::vec3(r * std::cos(phi), r * std::sin(phi), z);
            *p = l.center + l.radius * *n;
            return true;
        }
        case LightRecord::Kind::Rect:
            *p = l.center + (2.0f * u.x - 1.0f) * l.axisU + (2.0f * u.y - 1.0f) * l.axisV;
            *n = l.normal;
            return true;
        case LightRecord::Kind::Disk: {
            const glm::vec2 d = bsdf::squareToConcentricDisk(u);
            *p = l.center + d.x * l.axisU + d.y * l.axisV;
            *n = l.normal;
            return true;
        }
        case LightRecord::Kind::Mesh: {
            // Two-sided: n is the triangle's normal; the caller takes either side.
            glm::vec2 bary;
            const int i = l.meshWorld ? meshAreaPoint(l, u, p, &bary) : -1;
            if (i < 0) return false;
            *n = (*l.meshWorld)[size_t(i)].normal;
            return true;
        }
        case LightRecord::Kind::Cylinder: {
            // Uniform on the side surface: axisU is half the length along the axis; the
            // circle is spanned by two radius vectors perpendicular to it.
            const glm::vec3 axis = glm::normalize(l.axisU);
            glm::vec3 t, b;
            basis(axis, &t, &b);
            const float phi = 2.0f * kPi * u.y;
            *n = std::cos(phi) * t + std::sin(phi) * b;
            *p = l.center + (2.0f * u.x - 1.0f) * l.axisU + l.radius * *n;
            return true;
        }
        default: return false;
    }
}

glm::vec3 emittedRadiance(const LightRecord& l, const glm::vec3& q, const glm::vec3& d) {
    glm::vec3 Le = l.radiance;
    if (l.kind == LightRecord::Kind::Rect) {
        const glm::vec3 r = q - l.center;
        Le *= rectTexel(l, glm::dot(r, l.axisU) / glm::dot(l.axisU, l.axisU),
                        glm::dot(r, l.axisV) / glm::dot(l.axisV, l.axisV));
    }
    if (l.shaping.enabled) Le *= shapingFactor(l.shaping, d);
    return Le;
}

bool intersectAreaLight(const LightRecord& l, const glm::vec3& o, const glm::vec3& d, float tmax,
                        glm::vec3* Le, float* pdf) {
    if (!intersectUnshaped(l, o, d, tmax, Le, pdf)) return false;
    if (l.shaping.enabled) *Le *= shapingFactor(l.shaping, -d);
    return true;
}

bool environmentRadiance(const LightRecord& l, const glm::vec3& origin, const glm::vec3& d, const glm::vec3& ng,
                         glm::vec3* Le, float* pdf, bool misCompensation) {
    if (l.kind == LightRecord::Kind::Dome) {
        *Le = l.environment && l.environment->latLong ? envLookup(l, d) : l.radiance;
        if (pdf) *pdf = domeMixturePdf(l, origin, d, ng, misCompensation);
        return true;
    }
    // Inside the sun's cone: 1 - cos(angle to its axis) = |d + direction|^2 / 2 for unit vectors,
    // compared with 1 - cos(half angle) itself (the cosines agree to only ~1e-7 near 1).
    const glm::vec3 off = d + l.direction;
    if (l.kind == LightRecord::Kind::Distant && l.cosHalfAngle < 1.0f &&
        0.5f * glm::dot(off, off) <= l.oneMinusCosHalfAngle) {
        *Le = l.radiance;
        if (pdf) *pdf = 1.0f / (2.0f * kPi * l.oneMinusCosHalfAngle);
        return true;
    }
    return false;
}

}  // namespace principled::embree
