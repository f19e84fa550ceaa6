// SPDX-License-Identifier: Apache-2.0
#include "delegate/lightPick.h"

#include <algorithm>
#include <cmath>

#include "delegate/lightSampling.h"

namespace principled::embree {

LightPick::LightPick(const SceneSnapshot& scene, bool enabled) : _scene(scene) {
    const auto& lights = scene.lights;
    _spatial = enabled && !scene.neeAllLights && lights.size() > 1 && scene.lightSceneRadius > 0.0f &&
               std::isfinite(scene.lightSceneRadius);
    if (!_spatial) return;
    _sceneRadius2 = scene.lightSceneRadius * scene.lightSceneRadius;
    _bounds.resize(lights.size());
    for (size_t i = 0; i < lights.size(); ++i) {
        const LightRecord& l = lights[i];
        const bool local = l.kind != LightRecord::Kind::Distant && l.kind != LightRecord::Kind::Dome;
        const float r = lightBoundingRadius(l);
        // A point light's radius may be ~0: 1e-4 of the scene keeps 1/d^2 bounded next to it.
        const float r2 = std::max(r * r, 1e-8f * _sceneRadius2);
        const bool bounded = local && std::isfinite(r2) && std::isfinite(glm::dot(l.center, l.center));
        _bounds[i] = bounded ? glm::vec4(l.center, r2) : glm::vec4(0.0f, 0.0f, 0.0f, -1.0f);
    }
    _reach.resize(lights.size());
    for (size_t i = 0; i < lights.size(); ++i) _reach[i] = reachOf(lights[i]);
    if (lights.size() <= kMaxLights) return;
    _many = true;
    std::vector<LightTree::Item> items;
    for (uint32_t i = 0; i < lights.size(); ++i) {
        const float base = lights[i].pickProbability;
        if (_bounds[i].w > 0.0f && base > 0.0f) {
            items.push_back({glm::vec3(_bounds[i]), _bounds[i].w, base, i, emissionCone(_reach[i])});
        } else {
            _flat.push_back(i);
        }
    }
    _tree = LightTree(std::move(items), _sceneRadius2);
}

LightPick::Reach LightPick::reachOf(const LightRecord& l) {
    Reach r;
    if (l.kind == LightRecord::Kind::Distant) {
        // Below the receiver's horizon by more than its angular radius: no part of it is seen.
        r.tests = kHorizon;
        r.normal = -l.direction;
        const float c = std::clamp(l.cosHalfAngle, -1.0f, 1.0f);
        r.cosCone = -std::sqrt(std::max(0.0f, 1.0f - c * c));
        return r;
    }
    if (l.kind == LightRecord::Kind::Dome || l.kind == LightRecord::Kind::Mesh) return r;
    if ((l.kind == LightRecord::Kind::Rect || l.kind == LightRecord::Kind::Disk) &&
        std::isfinite(lightBoundingRadius(l))) {  // not sheared: every point lies in the plane
        r.tests |= kBehindPlane;
        r.normal = l.normal;
    }
    const LightShaping& s = l.shaping;
    if (s.enabled) {
        constexpr float kHalfPi = 1.57079632679489661923f;
        float cone = s.coneAngle;
        if (s.focus > 0.0f && s.focusTint == glm::vec3(0.0f)) cone = std::min(cone, kHalfPi);
        if (s.ies && s.iesAngleScale == 0.0f && s.ies->vertical.front() == 0.0f)
            cone = std::min(cone, s.ies->vertical.back() * (kHalfPi / 90.0f));
        if (cone < 2.0f * kHalfPi) {
            r.tests |= kCone;
            r.axis = s.axis;
            r.cosCone = std::cos(cone);
            r.sinCone = std::sin(cone);
        }
    }
    return r;
}

LightTree::Cone LightPick::emissionCone(const Reach& r) {
    // The directions the reach tests allow, as the tree's cone: the one-sided plane's hemisphere
    // about its normal, the shaping cone about its axis (both: the narrower, about the same axis,
    // as light.cpp aims the shaping axis along the normal).
    LightTree::Cone k;
    if (r.tests & kCone) {
        k.axis = r.axis;
        k.cosThetaO = 1.0f;
        k.cosThetaE = (r.tests & kBehindPlane) ? std::max(r.cosCone, 0.0f) : r.cosCone;
    } else if (r.tests & kBehindPlane) {
        k.axis = r.normal;
        k.cosThetaO = 1.0f;
        k.cosThetaE = 0.0f;
    }
    return k;
}

bool LightPick::reaches(uint32_t i, const glm::vec3& c, float r2, const glm::vec3& p, const glm::vec3& n) const {
    const glm::vec3 d = c - p;  // toward the light
    // The receiver: the whole bounding sphere behind its plane.
    if (n != glm::vec3(0.0f) && glm::dot(d, n) < 0.0f && glm::dot(d, n) * glm::dot(d, n) > r2) return false;
    if (_reach[i].tests == 0) return true;
    const Reach& e = _reach[i];
    if ((e.tests & kBehindPlane) && glm::dot(d, e.normal) >= 0.0f) return false;  // p at or behind it
    if (e.tests & kCone) {
        // The direction from any point of the sphere to p is within delta of -d, sin delta = r / |d|;
        // it misses the cone if the angle of -d off the axis exceeds cone + delta.
        const float dist2 = glm::dot(d, d);
        if (dist2 <= r2) return true;
        const float dist = std::sqrt(dist2);
        const float sinDelta = std::sqrt(r2) / dist, cosDelta = std::sqrt(std::max(0.0f, 1.0f - sinDelta * sinDelta));
        // cos(cone + delta), or -1 once cone + delta reaches pi.
        const float limit = e.cosCone * cosDelta - e.sinCone * sinDelta;
        const bool wraps = e.sinCone * cosDelta + e.cosCone * sinDelta < 0.0f;  // sin(cone + delta) < 0
        if (!wraps && -glm::dot(d, e.axis) < limit * dist) return false;
    }
    return true;
}

float LightPick::weight(uint32_t i, const glm::vec3& p, const glm::vec3& n) const {
    const float base = _scene.lights[i].pickProbability;
    const glm::vec4& b = _bounds[i];
    if (b.w < 0.0f) {
        const Reach& e = _reach[i];
        if ((e.tests & kHorizon) && n != glm::vec3(0.0f) && glm::dot(e.normal, n) < e.cosCone) return 0.0f;
        return base;
    }
    if (!reaches(i, glm::vec3(b), b.w, p, n)) return 0.0f;
    const glm::vec3 d = glm::vec3(b) - p;
    const float w = base * (_sceneRadius2 / std::max(glm::dot(d, d), b.w));
    return std::isfinite(w) ? w : base;
}

float LightPick::weigh(const glm::vec3& p, const glm::vec3& n, float* w) const {
    if (_many) {
        float sum = 0.0f;  // the flat lights, then the tree (pick() walks them in that order)
        for (uint32_t i : _flat) sum += weight(i, p, n);
        return sum + _tree.rootWeight(p, n);
    }
    float sum = 0.0f;
    for (uint32_t i = 0; i < _bounds.size(); ++i) sum += (w[i] = weight(i, p, n));
    return sum;
}

uint32_t LightPick::pick(const glm::vec3& p, const glm::vec3& n, const float* w, float total, float u) const {
    if (u < kGlobalShare) return globalPick(std::min(u / kGlobalShare, 0.99999994f));  // u rescaled
    const float target = std::min((u - kGlobalShare) / (1.0f - kGlobalShare), 0.99999994f) * total;
    if (_many) {
        // The flat lights first, then the tree with the rest.
        float sum = 0.0f;
        uint32_t last = _flat.empty() ? 0u : _flat.front();
        for (uint32_t i : _flat) {
            const float wi = weight(i, p, n);
            sum += wi;
            if (wi > 0.0f) last = i;
            if (target < sum && wi > 0.0f) return i;
        }
        const float root = _tree.rootWeight(p, n);
        if (!(root > 0.0f)) return last;  // rounding left target at the flat lights' sum
        const float v = (target - sum) / root;
        return _tree.pick(p, std::min(std::max(v, 0.0f), 0.99999994f), n);
    }
    const uint32_t count = uint32_t(_bounds.size());
    float sum = 0.0f;
    for (uint32_t i = 0; i < count; ++i) {
        sum += w[i];
        if (target < sum && w[i] > 0.0f) return i;
    }
    // Rounding left u * total at or above the last partial sum: the last light that can be picked.
    for (uint32_t i = count; i-- > 0;)
        if (w[i] > 0.0f) return i;
    return count - 1;
}

uint32_t LightPick::globalPick(float u) const {
    const auto& cdf = _scene.lightCdf;
    const size_t i = size_t(std::upper_bound(cdf.begin() + 1, cdf.end() - 1, u) - (cdf.begin() + 1));
    return uint32_t(std::min(i, _scene.lights.size() - 1));
}

float LightPick::probability(uint32_t i, const glm::vec3& p, const glm::vec3& n, float total) const {
    // total 0: the point fell back to the global pick (see the integrator).
    const float global = _scene.lights[i].pickProbability;
    if (!_spatial || !(total > 0.0f)) return global;
    if (_many && _tree.contains(i)) {
        const float spatial = _tree.probability(i, p, n) * (_tree.rootWeight(p, n) / total);
        return (1.0f - kGlobalShare) * spatial + kGlobalShare * global;
    }
    return (1.0f - kGlobalShare) * (weight(i, p, n) / total) + kGlobalShare * global;
}

}  // namespace principled::embree
