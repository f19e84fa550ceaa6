// SPDX-License-Identifier: Apache-2.0
// The Disney sheen lobe (grazing-angle tint for cloth), cosine-sampled.
#pragma once

#include "bsdf/fresnel.h"
#include "bsdf/lobe.h"
#include "bsdf/warp.h"

namespace principled::bsdf {

struct Sheen {
    glm::vec3 color{0.0f};  ///< sheen mix(1, Ctint, sheenTint) (1 - metallic)(1 - specTrans)

    /// Burley 2012, "Physically-Based Shading at Disney", §5.5 and wdas/brdf disney.brdf:
    /// f_sheen = sheen Csheen SchlickWeight(cos theta_d) (not divided by pi).
    glm::vec3 eval(const glm::vec3& wo, const glm::vec3& wi) const {
        if (wo.z <= 0.0f || wi.z <= 0.0f) return glm::vec3(0.0f);
        float cosD = std::sqrt(std::clamp(0.5f * (1.0f + glm::dot(wi, wo)), 0.0f, 1.0f));
        return color * (schlickWeight(cosD) * wi.z);
    }
    /// eval() for the facade (wo.z > 0, wi.z > 0) with cos2d = DisneyDiffuse::cos2ThetaD(wo, wi).
    glm::vec3 eval(float cos2d, const glm::vec3& wi) const {
        return color * (schlickWeight(std::sqrt(cos2d)) * wi.z);
    }
    float pdf(const glm::vec3& wo, const glm::vec3& wi) const {
        return wo.z > 0.0f ? cosineHemispherePdf(wi) : 0.0f;
    }
    std::optional<LobeSample> sample(const glm::vec3& wo, const glm::vec2& u, float) const {
        if (wo.z <= 0.0f) return std::nullopt;
        glm::vec3 wi = squareToCosineHemisphere(u);
        if (wi.z <= 0.0f) return std::nullopt;
        return LobeSample{wi, eval(wo, wi), pdf(wo, wi), false};
    }
    // 0.1: the sheen albedo of a white sheen is 0.02-0.2 (reference/bsdf.md §4.3 rows).
    float selectionWeight(const glm::vec3&) const { return 0.1f * luminance(color); }
};

}  // namespace principled::bsdf
