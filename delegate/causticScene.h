// SPDX-License-Identifier: Apache-2.0
// What caustic light tracing needs from a scene snapshot: the casters (placed geometry whose
// material has a sharp lobe), bounding spheres that enclose them (the targets light paths are
// aimed at), the lights that cast caustics, and the sampling of a light's emitted rays toward
// the targets.
//
// Path-space split (docs/caustics.md): a camera path x1 (first hit) -> x2 ... xk -> light whose
// vertices x2..xk scatter through sharp lobes of casters and whose x1 scatters through a lobe
// that is not sharp is a caustic path. Per path, its share of the contribution is
//   c = f1_rest / f1 * prod_{j=2..k} f_j_sharp / f_j   (componentwise)
// The path tracer keeps (1 - c) of every path that ends on a caustic light; light tracing
// estimates the c part, starting at the light and connecting x1 to the camera. Both are
// deterministic functions of the path, so the sum is the whole integral (Veach 1997, §10.2:
// a partition of path space between estimators is unbiased like MIS with 0/1 weights).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "bsdf/types.h"
#include "delegate/sceneData.h"

namespace principled::embree {

/// A sphere that encloses casters; light paths are aimed at it.
struct CausticTarget {
    glm::vec3 center{0.0f};
    float radius = 0.0f;
};

/// A ray leaving a light with its estimator weight: radiance (or a delta light's irradiance)
/// times the cosine at the light over the sampling density of origin and direction, so that
/// weight * (what the ray then carries to the film) is an unbiased estimate.
struct EmittedRay {
    glm::vec3 origin{0.0f};
    glm::vec3 direction{0.0f, 0.0f, -1.0f};
    glm::vec3 weight{0.0f};
};

class CausticScene {
public:
    /// Most targets kept: more casters are grouped along their longest spread.
    static constexpr size_t kMaxTargets = 32;

    CausticScene() = default;
    /// Finds the casters of `scene` whose materials have a lobe at most `maxRoughness` rough
    /// (alpha = roughness^2; textured materials are probed at a few points), and the lights
    /// that cast caustics (distant, sphere, rect, disk and cylinder lights; dome and mesh
    /// lights are left to the path tracer).
    CausticScene(const SceneSnapshot& scene, const bsdf::Options& options, float maxRoughness);

    /// Light tracing has something to do: a caster and a caustic light.
    bool active() const { return !_targets.empty() && !_lights.empty(); }
    /// GGX alpha at or below which a lobe counts as sharp (Bsdf::sharpLobes).
    float maxAlpha() const { return _maxAlpha; }
    /// Whether the Embree instance geomID is a caster.
    bool isCaster(unsigned instId) const {
        return instId < _casterByInstance.size() && _casterByInstance[instId];
    }
    /// Whether light `index` (SceneSnapshot::lights) is a caustic light.
    bool isCausticLight(size_t index) const { return index < _lightFlag.size() && _lightFlag[index]; }
    const std::vector<CausticTarget>& targets() const { return _targets; }
    size_t casterCount() const { return _casters; }
    /// Caustic lights: those light paths start from (with casters), else those found.
    size_t lightCount() const { return size_t(std::count(_lightFlag.begin(), _lightFlag.end(), uint8_t(1))); }
    /// Radius of a sphere around every placed prim.
    float sceneRadius() const { return _sceneRadius; }
    /// Mean radius of the targets (the photon search radius's scale).
    float meanTargetRadius() const;

    /// A ray emitted by a caustic light toward the targets: uLight picks the light (by power
    /// toward the targets), uTarget the target, uPos and uDir the origin and direction. False
    /// when the sample carries no light.
    bool sampleEmission(const SceneSnapshot& scene, float uLight, float uTarget, const glm::vec2& uPos,
                        const glm::vec2& uDir, EmittedRay* out) const;

private:
    struct Light {
        uint32_t index = 0;          ///< into SceneSnapshot::lights
        std::vector<float> cdf;      ///< targets.size() + 1: the target pick
        std::vector<float> prob;     ///< the pick probabilities
    };
    /// Density over directions from p of the target mixture of light `l` (cone sampling); the
    /// cone of target `sampled` is taken to hold d.
    float directionPdf(const Light& l, const glm::vec3& p, const glm::vec3& d, size_t sampled) const;

    std::vector<uint8_t> _casterByInstance;
    std::vector<uint8_t> _lightFlag;
    std::vector<CausticTarget> _targets;
    std::vector<Light> _lights;
    std::vector<float> _lightCdf;  ///< _lights.size() + 1
    std::vector<float> _lightProb;
    glm::vec3 _sceneCenter{0.0f};
    float _sceneRadius = 0.0f;
    float _maxAlpha = 0.0f;
    size_t _casters = 0;
};

}  // namespace principled::embree
