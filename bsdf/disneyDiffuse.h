// SPDX-License-Identifier: Apache-2.0
// Burley's diffuse with retro-reflection, blended with the Hanrahan-Krueger-like subsurface
// approximation, cosine-sampled.
#pragma once

#include "bsdf/fresnel.h"
#include "bsdf/lobe.h"
#include "bsdf/warp.h"

namespace principled::bsdf {

struct DisneyDiffuse {
    glm::vec3 color{0.0f};  ///< baseColor (1 - metallic)(1 - specTrans)
    float roughness = 0.5f;
    float subsurface = 0.0f;

    /// The scalar factor multiplying color / pi: mix(Fd, ss, subsurface).
    float shape(const glm::vec3& wo, const glm::vec3& wi) const {
        return shape(wo, wi, schlickWeight(wo.z), cos2ThetaD(wo, wi));
    }
    /// cos^2 theta_d = (l.h)^2 = (1 + l.v) / 2, without normalising h.
    static float cos2ThetaD(const glm::vec3& wo, const glm::vec3& wi) {
        return std::clamp(0.5f * (1.0f + glm::dot(wi, wo)), 0.0f, 1.0f);
    }
    /// shape() with fv = schlickWeight(wo.z) and cos2d = cos2ThetaD(wo, wi) precomputed.
    float shape(const glm::vec3& wo, const glm::vec3& wi, float fv, float cos2d) const {
        float fl = schlickWeight(wi.z);
        // Burley 2012, "Physically-Based Shading at Disney", §5.3, eq. 3 (with the 2013 fix
        // cos^2 theta_d, wdas/brdf commit 820ccba): Fd90 = 0.5 + 2 r cos^2 theta_d.
        float fd90 = 0.5f + 2.0f * roughness * cos2d;
        float fd = (1.0f + (fd90 - 1.0f) * fl) * (1.0f + (fd90 - 1.0f) * fv);
        if (subsurface <= 0.0f) return fd;
        // Burley 2012, §5.3 and wdas/brdf disney.brdf: Hanrahan-Krueger-like subsurface,
        // ss = 1.25 (Fss (1/(cos_i + cos_o) - 0.5) + 0.5), Fss90 = r cos^2 theta_d.
        float fss90 = roughness * cos2d;
        float fss = (1.0f + (fss90 - 1.0f) * fl) * (1.0f + (fss90 - 1.0f) * fv);
        float ss = 1.25f * (fss * (1.0f / (wi.z + wo.z) - 0.5f) + 0.5f);
        return fd + (ss - fd) * subsurface;
    }

    glm::vec3 eval(const glm::vec3& wo, const glm::vec3& wi) const {
        if (wo.z <= 0.0f || wi.z <= 0.0f) return glm::vec3(0.0f);
        return color * (kInvPi * shape(wo, wi) * wi.z);
    }
    /// eval() for the facade (wo.z > 0, wi.z > 0) with fv and cos2d shared with other lobes.
    glm::vec3 eval(const glm::vec3& wo, const glm::vec3& wi, float fv, float cos2d) const {
        return color * (kInvPi * shape(wo, wi, fv, cos2d) * wi.z);
    }
    float pdf(const glm::vec3& wo, const glm::vec3& wi) const { return cosineLobePdf(wo, wi); }
    std::optional<LobeSample> sample(const glm::vec3& wo, const glm::vec2& u, float) const {
        return sampleCosineLobe(*this, wo, u);
    }
    float selectionWeight(const glm::vec3&) const { return luminance(color); }
};

}  // namespace principled::bsdf
