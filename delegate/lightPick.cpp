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
    if (lights.size() <= kMaxLights) return;
    _many = true;
    std::vector<LightTree::Item> items;
    for (uint32_t i = 0; i < lights.size(); ++i) {
        const float base = lights[i].pickProbability;
        if (_bounds[i].w > 0.0f && base > 0.0f) {
            items.push_back({glm::vec3(_bounds[i]), _bounds[i].w, base, i});
        } else {
            _flat.push_back(i);
            _flatSum += base;
        }
    }
    _tree = LightTree(std::move(items), _sceneRadius2);
    _bounds.clear();  // weight() is not used: the tree and the flat list weigh the lights
}

float LightPick::weight(uint32_t i, const glm::vec3& p) const {
    const float base = _scene.lights[i].pickProbability;
    const glm::vec4& b = _bounds[i];
    if (b.w < 0.0f) return base;
    const glm::vec3 d = glm::vec3(b) - p;
    const float w = base * (_sceneRadius2 / std::max(glm::dot(d, d), b.w));
    return std::isfinite(w) ? w : base;
}

float LightPick::weigh(const glm::vec3& p, float* w) const {
    if (_many) return _flatSum + _tree.rootWeight(p);
    float sum = 0.0f;
    for (uint32_t i = 0; i < _bounds.size(); ++i) sum += (w[i] = weight(i, p));
    return sum;
}

uint32_t LightPick::pick(const glm::vec3& p, const float* w, float total, float u) const {
    if (u < kGlobalShare) return globalPick(std::min(u / kGlobalShare, 0.99999994f));  // u rescaled
    const float target = std::min((u - kGlobalShare) / (1.0f - kGlobalShare), 0.99999994f) * total;
    if (_many) {
        // The flat lights first (weight = global probability), then the tree with the rest.
        float sum = 0.0f;
        for (uint32_t i : _flat) {
            sum += _scene.lights[i].pickProbability;
            if (target < sum) return i;
        }
        if (_tree.empty()) return _flat.back();
        const float rest = total - _flatSum;
        const float v = rest > 0.0f ? (target - _flatSum) / rest : 0.0f;
        return _tree.pick(p, std::min(std::max(v, 0.0f), 0.99999994f));
    }
    const uint32_t n = uint32_t(_bounds.size());
    float sum = 0.0f;
    for (uint32_t i = 0; i < n; ++i) {
        sum += w[i];
        if (target < sum && w[i] > 0.0f) return i;
    }
    // Rounding left u * total at or above the last partial sum: the last light that can be picked.
    for (uint32_t i = n; i-- > 0;)
        if (w[i] > 0.0f) return i;
    return n - 1;
}

uint32_t LightPick::globalPick(float u) const {
    const auto& cdf = _scene.lightCdf;
    const size_t i = size_t(std::upper_bound(cdf.begin() + 1, cdf.end() - 1, u) - (cdf.begin() + 1));
    return uint32_t(std::min(i, _scene.lights.size() - 1));
}

float LightPick::probability(uint32_t i, const glm::vec3& p, float total) const {
    // total 0: the point fell back to the global pick (see the integrator).
    const float global = _scene.lights[i].pickProbability;
    if (!_spatial || !(total > 0.0f)) return global;
    if (_many) {
        const float spatial = _tree.contains(i) ? _tree.probability(i, p) * (_tree.rootWeight(p) / total)
                                                : global / total;
        return (1.0f - kGlobalShare) * spatial + kGlobalShare * global;
    }
    return (1.0f - kGlobalShare) * (weight(i, p) / total) + kGlobalShare * global;
}

}  // namespace principled::embree
