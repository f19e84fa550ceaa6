// SPDX-License-Identifier: Apache-2.0
// The shading-model interface the integrator calls: one Bsdf per shading point, built from
// material parameters, evaluated and sampled in the local shading frame (z = shading normal,
// wo and wi both point away from the surface, as in pbrt).
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include <glm/glm.hpp>

#include "bsdf/lobeSet.h"
#include "bsdf/types.h"

namespace principled::bsdf {

/// A BSDF at one shading point. Construction is cheap; nothing is cached across points.
/// Views below the shading hemisphere: for opaque materials wo is bent back to just above the
/// horizon (no black rims from shading normals); for solid transmissive materials (specTrans > 0,
/// thin = false) wo.z < 0 means "inside the object", where only the transmission lobe acts, with
/// the inverse index (so the frame's normal must keep pointing outward); thin materials are
/// two-sided (mirrored through the surface).
class Bsdf {
public:
    Bsdf(const MaterialParams& params, const Options& options);

    /// f(wo, wi) * |cos(theta_i)| summed over the non-delta lobes. Writes the mixture pdf of
    /// sampling wi (solid angle) to *pdf and the per-lobe split to *perLobe when given.
    glm::vec3 eval(const glm::vec3& wo, const glm::vec3& wi, float* pdf = nullptr,
                   LobeValues* perLobe = nullptr) const;

    /// Samples wi given two uniform numbers: uLobe picks the lobe, u picks the direction.
    std::optional<BsdfSample> sample(const glm::vec3& wo, float uLobe, const glm::vec2& u) const;

    /// The part of eval() and sample() that depends on wo only (which side, the bent or
    /// mirrored wo, the lobe probabilities). A caller that evaluates and samples at the same wo
    /// (next-event estimation, then the path's next direction) prepares it once; the results
    /// are identical to eval(wo, ...) and sample(wo, ...).
    struct View {
        glm::vec3 wo{0.0f};
        float flip = 1.0f;      ///< -1 when the lobes' frame is mirrored through the surface
        bool inside = false;    ///< view inside a solid transmissive object
        LobeMask active = 0;
        std::array<float, kLobeCount> prob{};
        // Terms of the lobes that depend on wo only, computed once here (bit-identical to the
        // lobes' own eval()/pdf()): Schlick weight (1 - wo.z)^5, Smith G1(wo) of the specular,
        // clearcoat (alpha 0.25) and transmission distributions.
        float fv = 0.0f;
        float g1Spec = 0.0f, g1Coat = 0.0f, g1Trans = 0.0f;
        float inv4CosO = 0.0f;  ///< 1 / (4 wo.z)
        float g1SpecK = 0.0f;   ///< g1Spec / (4 wo.z)
        /// The surface's own normal in the lobes' frame when the shading normal leans away from
        /// it: the diffuse and sheen lobes are then shadowed by bumpShadowing(smoothNormal, wi).
        glm::vec3 smoothNormal;  ///< set (and read) only when bumped
        bool bumped = false;
    };
    View prepare(const glm::vec3& wo) const;
    /// prepare(wo) for a shading normal (+z) that differs from the surface's own unit normal
    /// smoothNormal (same frame): eval() and sample() then scale the diffuse and sheen lobes by
    /// bumpShadowing (bsdf/bumpShadowing.h), as Cycles 3.4 does; the pdfs are unchanged.
    View prepare(const glm::vec3& wo, const glm::vec3& smoothNormal) const;
    glm::vec3 eval(const View& view, const glm::vec3& wi, float* pdf = nullptr,
                   LobeValues* perLobe = nullptr) const;
    std::optional<BsdfSample> sample(const View& view, float uLobe, const glm::vec2& u) const;

    /// Mixture pdf of sample() producing wi (solid angle); 0 for delta-only materials.
    float pdf(const glm::vec3& wo, const glm::vec3& wi) const;

    /// The lobes this material actually uses after pruning.
    LobeMask lobes() const { return _lobes; }
    /// True when every lobe is a delta lobe (next-event estimation is pointless).
    bool isDeltaOnly() const { return _deltaOnly; }
    /// True when the transmission lobe is active and not a delta: light from the far side of
    /// the surface can then be sampled directly (next-event estimation through the surface).
    bool hasRoughTransmission() const {
        const LobeMask t = lobeBit(Lobe::Transmission);
        return (_lobes & t) && !(_set.deltaMask & t);
    }

    /// The lobes narrow enough to carry caustics: delta lobes, and specular, clearcoat and
    /// transmission lobes whose GGX/GTR1 alpha (the larger of an anisotropic pair) is at most
    /// maxAlpha. Diffuse and sheen are never sharp.
    LobeMask sharpLobes(float maxAlpha) const;
    /// The view restricted to the lobes in `lobes`: sample() then picks among those only (with
    /// renormalised probabilities) and eval()/the sample's f and pdf cover those lobes only.
    /// The returned view has no active lobe when none of `lobes` is active in `view`.
    View restrict(const View& view, LobeMask lobes) const;

    /// Probability that sample() picks each lobe for this wo (never depends on wi).
    std::array<float, kLobeCount> lobeProbabilities(const glm::vec3& wo) const;

    /// The concrete lobes (for tests and tools).
    const LobeSet& lobeSet() const { return _set; }

private:

    glm::vec3 evalLive(const View& v, const glm::vec3& wi, LobeMask live, float* pdf,
                       LobeValues* perLobe) const;

    LobeSet _set;
    /// Selection weights that do not depend on wo (diffuse, sheen, transmission), and
    /// kPi ln(alpha^2) of the clearcoat GTR1, computed once at construction.
    float _weightDiffuse = 0.0f, _weightSheen = 0.0f, _weightTrans = 0.0f;
    float _ccPiLogA2 = 0.0f;
    GgxConst _specK;
    LobeMask _lobes = 0;
    bool _deltaOnly = false;
};

}  // namespace principled::bsdf
