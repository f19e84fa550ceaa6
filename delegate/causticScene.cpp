// SPDX-License-Identifier: Apache-2.0
#include "delegate/causticScene.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>
#include <unordered_map>

#include "bsdf/bsdf.h"
#include "bsdf/frame.h"
#include "bsdf/warp.h"
#include "delegate/lightSampling.h"
#include "delegate/rayOffset.h"
#include "delegate/surfacePoint.h"

namespace principled::embree {
namespace {

constexpr float kPi = 3.14159265358979323846f;
constexpr int kProbes = 16;  // points a textured material is probed at

float luminance(const glm::vec3& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

void basis(const glm::vec3& n, glm::vec3* t, glm::vec3* b) {
    const bsdf::Frame f = bsdf::Frame::fromZ(n);
    *t = f.x;
    *b = f.y;
}

// 1 - cos(theta_max) of the cone a sphere of radius r subtends at distance^2 d2 > r^2, without
// the cancellation of 1 - sqrt(1 - s) for small s = r^2 / d2.
float oneMinusCosMax(float r, float d2) {
    const float s = r * r / d2;
    return s / (1.0f + std::sqrt(std::max(0.0f, 1.0f - s)));
}

// Uniform direction in the cone about unit axis n with 1 - cos(theta_max) = omc (Pharr et al.
// 2023, PBR 4th ed., §A.5.4).
glm::vec3 sampleCone(const glm::vec3& n, float omc, const glm::vec2& u) {
    glm::vec3 t, b;
    basis(n, &t, &b);
    const float om = u.x * omc;  // 1 - cos as its own number (precise near the axis)
    const float c = 1.0f - om;
    const float s = std::sqrt(std::max(0.0f, om * (2.0f - om))), phi = 2.0f * kPi * u.y;
    return glm::normalize(s * std::cos(phi) * t + s * std::sin(phi) * b + c * n);
}

bool isCausticLightKind(LightRecord::Kind k) {
    return k == LightRecord::Kind::Distant || k == LightRecord::Kind::Sphere || k == LightRecord::Kind::Rect ||
           k == LightRecord::Kind::Disk || k == LightRecord::Kind::Cylinder || k == LightRecord::Kind::Mesh;
}

struct Box {
    glm::vec3 lo{1e30f}, hi{-1e30f};
    void grow(const glm::vec3& p) { lo = glm::min(lo, p), hi = glm::max(hi, p); }
    void grow(const Box& b) { lo = glm::min(lo, b.lo), hi = glm::max(hi, b.hi); }
    bool valid() const { return lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z; }
    CausticTarget sphere() const { return {0.5f * (lo + hi), 0.5f * glm::length(hi - lo)}; }
};

Box objectBounds(const GeometryRecord& rec) {
    Box b;
    if (rec.kind == GeometryRecord::Kind::Sphere) {
        b.grow(rec.center - glm::vec3(rec.radius));
        b.grow(rec.center + glm::vec3(rec.radius));
    } else {
        for (const glm::vec3& p : rec.points) b.grow(p);
    }
    return b;
}

Box transformed(const Box& b, const glm::mat4& m) {
    Box w;
    for (int i = 0; i < 8; ++i) {
        glm::vec3 c((i & 1) ? b.hi.x : b.lo.x, (i & 2) ? b.hi.y : b.lo.y, (i & 4) ? b.hi.z : b.lo.z);
        w.grow(glm::vec3(m * glm::vec4(c, 1.0f)));
    }
    return w;
}

}  // namespace

CausticScene::CausticScene(const SceneSnapshot& scene, const bsdf::Options& options, float maxRoughness) {
    if (!(maxRoughness > 0.0f) || !scene.scene) return;
    _maxAlpha = std::min(maxRoughness, 1.0f) * std::min(maxRoughness, 1.0f);
    _lightFlag.assign(scene.lights.size(), 0);
    bool anyLight = false;
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        const LightRecord& l = scene.lights[i];
        const glm::vec3 power = l.kind == LightRecord::Kind::Distant ? l.irradiance + l.radiance : l.radiance;
        // A textured mesh light's radiance is only an estimate of its mean: path tracing keeps it.
        const bool meshOk = l.kind != LightRecord::Kind::Mesh || (!l.texturedEmission && l.meshWorld && l.meshAreaCdf);
        // A light without shadows reaches through occluders, which its light paths cannot, a
        // linked light lights some prims only, lobe multipliers act at the vertex that sees the
        // light: path tracing keeps their caustics.
        if (isCausticLightKind(l.kind) && meshOk && !l.neeOnly() && l.linkBit < 0 && !l.point && !l.scalesLobes() && luminance(power) > 0.0f && std::isfinite(luminance(power)) &&
            (l.kind == LightRecord::Kind::Distant || l.area > 0.0f)) {
            _lightFlag[i] = 1;
            anyLight = true;
        }
    }
    if (!anyLight) return;

    // Which materials have a sharp lobe: constant ones once, textured ones per prim at probes.
    std::vector<int8_t> constantSharp(scene.materials.size(), -1);
    auto sharpAt = [&](const GeometryRecord& rec, int mi) {
        if (mi < 0 || mi >= int(scene.materials.size())) return false;  // displayColor: roughness 0.5
        const MaterialRecord& m = scene.materials[size_t(mi)];
        if (!m.program) {
            int8_t& s = constantSharp[size_t(mi)];
            if (s < 0) s = bsdf::Bsdf(m.constant.params, options).sharpLobes(_maxAlpha) != 0;
            return s > 0;
        }
        const size_t n = rec.kind == GeometryRecord::Kind::Sphere ? 1 : rec.triangles.size();
        int probed = 0;
        for (size_t k = 0; k < n && probed < kProbes; k += std::max<size_t>(1, n / kProbes)) {
            if (rec.materialFor(unsigned(k)) != mi) continue;
            ++probed;
            SurfacePoint point(rec, unsigned(k), 1.0f / 3.0f, 1.0f / 3.0f);
            if (bsdf::Bsdf(m.program->evaluate(point).params, options).sharpLobes(_maxAlpha)) return true;
        }
        return false;
    };
    struct RecordInfo {
        bool caster = false;
        Box bounds;
    };
    std::unordered_map<const GeometryRecord*, RecordInfo> records;
    // Casters keyed by prim and placement: Embree's geometry ids follow the (parallel) sync
    // order, which changes from run to run; targets must not, or the same seed would trace
    // other light paths.
    struct Caster {
        int prim, placement;
        Box box;
        CausticTarget sphere;  ///< the tightest sphere known (an implicit sphere's own)
    };
    std::vector<Caster> casters;
    Box sceneBox;
    _casterByInstance.assign(scene.geometryByInstance.size(), 0);
    for (size_t inst = 0; inst < scene.geometryByInstance.size(); ++inst) {
        const GeometryRecord* rec = scene.geometryByInstance[inst];
        if (!rec) continue;
        auto [it, fresh] = records.try_emplace(rec);
        RecordInfo& info = it->second;
        if (fresh) {
            info.bounds = objectBounds(*rec);
            // Points and curves stay with the path tracer (their widths are not in the bounds).
            if (rec->kind == GeometryRecord::Kind::Triangles || rec->kind == GeometryRecord::Kind::Sphere) {
                std::vector<int> mats{rec->materialIndex};
                for (int m : rec->triangleMaterial)
                    if (std::find(mats.begin(), mats.end(), m) == mats.end()) mats.push_back(m);
                for (int m : mats) info.caster = info.caster || sharpAt(*rec, m);
            }
        }
        if (!info.bounds.valid()) continue;
        const InstanceRecord* placed = inst < scene.instanceByInstance.size() ? scene.instanceByInstance[inst] : nullptr;
        const Box world = transformed(info.bounds, placed ? placed->objectToWorld : rec->objectToWorld);
        if (!world.valid() || !std::isfinite(world.lo.x + world.lo.y + world.lo.z + world.hi.x + world.hi.y + world.hi.z))
            continue;
        sceneBox.grow(world);
        if (info.caster) {
            _casterByInstance[inst] = 1;
            const glm::mat4& m = placed ? placed->objectToWorld : rec->objectToWorld;
            CausticTarget sphere = world.sphere();
            if (rec->kind == GeometryRecord::Kind::Sphere) {
                // An implicit sphere: its own centre and radius (times the largest axis scale),
                // a third of its bounding box's sphere's cross-section.
                const float scale = std::max({glm::length(glm::vec3(m[0])), glm::length(glm::vec3(m[1])),
                                              glm::length(glm::vec3(m[2]))});
                const CausticTarget own{glm::vec3(m * glm::vec4(rec->center, 1.0f)), rec->radius * scale};
                if (own.radius < sphere.radius && std::isfinite(own.radius)) sphere = own;
            }
            casters.push_back({rec->primId, placed ? placed->instanceIndex : -1, world, sphere});
        }
    }
    std::sort(casters.begin(), casters.end(), [](const Caster& a, const Caster& b) {
        auto key = [](const Caster& c) {
            return std::tuple(c.prim, c.placement, c.box.lo.x, c.box.lo.y, c.box.lo.z, c.box.hi.x, c.box.hi.y, c.box.hi.z);
        };
        return key(a) < key(b);
    });
    std::vector<Box> casterBoxes;
    for (const Caster& c : casters) casterBoxes.push_back(c.box);
    _casters = casterBoxes.size();
    if (casterBoxes.empty()) return;
    const CausticTarget s = sceneBox.sphere();
    _sceneCenter = s.center;
    _sceneRadius = s.radius;

    // Targets: one per caster, or groups of casters split along their centres' longest spread.
    if (casters.size() <= kMaxTargets) {
        for (const Caster& c : casters) _targets.push_back(c.sphere);
    } else {
        Box centres;
        for (const Box& b : casterBoxes) centres.grow(0.5f * (b.lo + b.hi));
        const glm::vec3 ext = centres.hi - centres.lo;
        const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
        std::stable_sort(casterBoxes.begin(), casterBoxes.end(),
                  [axis](const Box& a, const Box& b) { return a.lo[axis] + a.hi[axis] < b.lo[axis] + b.hi[axis]; });
        for (size_t g = 0; g < kMaxTargets; ++g) {
            Box group;
            for (size_t i = g * casterBoxes.size() / kMaxTargets; i < (g + 1) * casterBoxes.size() / kMaxTargets; ++i)
                group.grow(casterBoxes[i]);
            if (group.valid()) _targets.push_back(group.sphere());
        }
    }
    for (CausticTarget& t : _targets) t.radius = std::max(t.radius * 1.0001f, 1e-6f);

    // Lights by their power toward the targets; each light's target pick by the same measure.
    for (size_t i = 0; i < scene.lights.size(); ++i) {
        if (!_lightFlag[i]) continue;
        const LightRecord& l = scene.lights[i];
        Light light;
        light.index = uint32_t(i);
        light.prob.resize(_targets.size());
        for (size_t t = 0; t < _targets.size(); ++t) {
            const CausticTarget& tg = _targets[t];
            if (l.kind == LightRecord::Kind::Distant) {
                light.prob[t] = kPi * tg.radius * tg.radius;  // the target's cross-section
            } else {
                const glm::vec3 d = tg.center - l.center;
                light.prob[t] = std::min(1.0f, tg.radius * tg.radius / std::max(glm::dot(d, d), 1e-12f));
            }
        }
        const float sum = std::accumulate(light.prob.begin(), light.prob.end(), 0.0f);
        if (!(sum > 0.0f) || !std::isfinite(sum)) {
            _lightFlag[i] = 0;
            continue;
        }
        float power;
        if (l.kind == LightRecord::Kind::Distant)
            power = (l.cosHalfAngle < 1.0f ? luminance(l.radiance) * 2.0f * kPi * l.oneMinusCosHalfAngle
                                           : luminance(l.irradiance)) * sum;
        else
            power = luminance(l.radiance) * l.area * kPi * 0.25f * sum;  // cosine-weighted share
        if (!(power > 0.0f) || !std::isfinite(power)) {
            _lightFlag[i] = 0;
            continue;
        }
        light.cdf.assign(1, 0.0f);
        for (float& p : light.prob) {
            p /= sum;
            light.cdf.push_back(light.cdf.back() + p);
        }
        light.cdf.back() = 1.0f;
        _lights.push_back(std::move(light));
        _lightProb.push_back(power);
    }
    const float total = std::accumulate(_lightProb.begin(), _lightProb.end(), 0.0f);
    if (!(total > 0.0f)) {
        _lights.clear();
        return;
    }
    _lightCdf.assign(1, 0.0f);
    for (float& p : _lightProb) {
        p /= total;
        _lightCdf.push_back(_lightCdf.back() + p);
    }
    _lightCdf.back() = 1.0f;
}

float CausticScene::meanTargetRadius() const {
    float sum = 0.0f;
    for (const CausticTarget& t : _targets) sum += t.radius;
    return _targets.empty() ? 0.0f : sum / float(_targets.size());
}

float CausticScene::directionPdf(const Light& l, const glm::vec3& p, const glm::vec3& d, size_t sampled) const {
    float pdf = 0.0f;
    for (size_t t = 0; t < _targets.size(); ++t) {
        const CausticTarget& tg = _targets[t];
        const glm::vec3 toC = tg.center - p;
        const float d2 = glm::dot(toC, toC);
        if (d2 <= tg.radius * tg.radius) {
            pdf += l.prob[t] / (4.0f * kPi);
            continue;
        }
        const float omc = oneMinusCosMax(tg.radius, d2);
        // The sampled target's cone holds d by construction (no rounding at its rim).
        if (t == sampled || glm::dot(d, toC) >= (1.0f - omc) * std::sqrt(d2)) pdf += l.prob[t] / (2.0f * kPi * omc);
    }
    return pdf;
}

bool CausticScene::sampleEmission(const SceneSnapshot& scene, float uLight, float uTarget, const glm::vec2& uPos,
                                  const glm::vec2& uDir, EmittedRay* out) const {
    if (!active()) return false;
    auto pick = [](const std::vector<float>& cdf, float u) {
        size_t i = size_t(std::upper_bound(cdf.begin() + 1, cdf.end() - 1, u) - (cdf.begin() + 1));
        return std::min(i, cdf.size() - 2);
    };
    const size_t slot = pick(_lightCdf, uLight);
    const Light& light = _lights[slot];
    const LightRecord& l = scene.lights[light.index];
    const size_t target = pick(light.cdf, uTarget);
    const CausticTarget& tg = _targets[target];
    const float pLight = _lightProb[slot];
    if (!(pLight > 0.0f) || !(light.prob[target] > 0.0f)) return false;

    if (l.kind == LightRecord::Kind::Distant) {
        glm::vec3 d = l.direction, Le = l.irradiance;
        float pdfDir = 1.0f;
        if (l.cosHalfAngle < 1.0f) {
            // A sun of finite size: a direction uniform in its cone carries its radiance.
            const float omc = l.oneMinusCosHalfAngle;
            d = sampleCone(l.direction, omc, uDir);
            Le = l.radiance;
            pdfDir = 1.0f / (2.0f * kPi * omc);
        }
        // The origin: uniform in the target's disc on the plane across d, placed behind the
        // scene. Its density is the mixture over every target's disc that holds it.
        glm::vec3 tu, tv;
        basis(d, &tu, &tv);
        const glm::vec2 c(glm::dot(tg.center, tu), glm::dot(tg.center, tv));
        const glm::vec2 q = c + tg.radius * bsdf::squareToConcentricDisk(uPos);
        float pdfArea = 0.0f;
        for (size_t t = 0; t < _targets.size(); ++t) {
            const CausticTarget& o = _targets[t];
            const glm::vec2 oc(glm::dot(o.center, tu), glm::dot(o.center, tv));
            const glm::vec2 r = q - oc;
            if (t == target || glm::dot(r, r) <= o.radius * o.radius)
                pdfArea += light.prob[t] / (kPi * o.radius * o.radius);
        }
        const float back = glm::dot(_sceneCenter, d) - 1.01f * _sceneRadius - 1e-3f;
        out->origin = q.x * tu + q.y * tv + back * d;
        out->direction = d;
        out->weight = Le / (pdfDir * pdfArea * pLight);
    } else {
        glm::vec3 p, n;
        if (!lightSurfacePoint(l, uPos, &p, &n)) return false;
        const glm::vec3 toC = tg.center - p;
        const float d2 = glm::dot(toC, toC);
        glm::vec3 d;
        if (d2 <= tg.radius * tg.radius) {
            d = bsdf::squareToUniformSphere(uDir);
        } else {
            d = sampleCone(toC / std::sqrt(d2), oneMinusCosMax(tg.radius, d2), uDir);
        }
        // Mesh lights emit from both sides; the others from the side n faces.
        const bool twoSided = l.kind == LightRecord::Kind::Mesh;
        const float cosL = twoSided ? std::abs(glm::dot(n, d)) : glm::dot(n, d);
        if (!(cosL > 0.0f)) return false;  // the emitting side faces away
        const glm::vec3 Le = emittedRadiance(l, p, d);
        if (Le == glm::vec3(0.0f)) return false;
        const float pdfDir = directionPdf(light, p, d, target);
        if (!(pdfDir > 0.0f)) return false;
        // A mesh light is geometry: the ray leaves its surface as a bounce would.
        out->origin = twoSided ? p + std::copysign(offsetScale(p), glm::dot(n, d)) * n : p;
        out->direction = d;
        out->weight = Le * (cosL * l.area / (pdfDir * pLight));
    }
    const glm::vec3& w = out->weight;
    return std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z) && std::max({w.x, w.y, w.z}) > 0.0f;
}

}  // namespace principled::embree
