// SPDX-License-Identifier: Apache-2.0
// The Disney clearcoat: GTR1 distribution, fixed IOR 1.5 Schlick Fresnel, Smith G with alpha
// 0.25, sampled from GTR1 itself.
#pragma once

#include "bsdf/fresnel.h"
#include "bsdf/ggx.h"
#include "bsdf/gtr1.h"
#include "bsdf/lobe.h"

namespace principled::bsdf {

struct Clearcoat {
    Gtr1 dist;
    float weight = 0.0f;  ///< 0.25 clearcoat

    /// Burley 2012, "Physically-Based Shading at Disney", §5.6 and wdas/brdf disney.brdf:
    /// f = 0.25 clearcoat Gr Fr Dr / (4 cos_o cos_i), Fr = Schlick(0.04), Gr = Smith GGX alpha 0.25.
    glm::vec3 eval(const glm::vec3& wo, const glm::vec3& wi) const {
        if (wo.z <= 0.0f || wi.z <= 0.0f) return glm::vec3(0.0f);
        glm::vec3 h = wo + wi;
        float l = glm::length(h);
        if (!(l > 0.0f)) return glm::vec3(0.0f);
        h /= l;
        constexpr Ggx kG{0.25f, 0.25f};  // 0.25: the fixed clearcoat G alpha of the reference code
        float fr = schlickFresnel(0.04f, glm::dot(wi, h));  // 0.04: F0 of IOR 1.5
        return glm::vec3(weight * dist.D(h.z) * fr * kG.G(wo, wi) / (4.0f * wo.z));
    }
    /// Walter et al. 2007, eq. 14 with the GTR1 normal density D(m) m.z.
    float pdf(const glm::vec3& wo, const glm::vec3& wi) const {
        if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
        glm::vec3 h = wo + wi;
        float l = glm::length(h);
        if (!(l > 0.0f)) return 0.0f;
        h /= l;
        float c = glm::dot(wo, h);
        return c > 0.0f ? dist.pdf(h) / (4.0f * c) : 0.0f;
    }
    /// eval() and pdf() in one pass for the facade: h = normalize(wo + wi) (wo.z > 0, wi.z > 0),
    /// g1o = Ggx{0.25, 0.25}.G1(wo) and piLogA2 = dist.piLogA2() precomputed.
    /// inv4CosO = 1 / (4 wo.z) (float rounding only).
    glm::vec3 evalPdf(const glm::vec3& wo, const glm::vec3& wi, const glm::vec3& h, float g1o,
                      float piLogA2, float inv4CosO, float* pdfOut) const {
        constexpr Ggx kG{0.25f, 0.25f};
        float d = dist.D(h.z, piLogA2);
        float c = glm::dot(wo, h);
        *pdfOut = c > 0.0f ? d * std::max(h.z, 0.0f) / (4.0f * c) : 0.0f;
        float fr = schlickFresnel(0.04f, glm::dot(wi, h));
        return glm::vec3(weight * d * fr * (g1o * kG.G1(wi)) * inv4CosO);
    }
    bool sampleWi(const glm::vec3& wo, const glm::vec2& u, glm::vec3* wi) const {
        glm::vec3 m = dist.sample(u);
        if (glm::dot(wo, m) <= 0.0f) return false;
        *wi = reflect(wo, m);
        return wi->z > 0.0f;
    }
    std::optional<LobeSample> sample(const glm::vec3& wo, const glm::vec2& u, float) const {
        if (wo.z <= 0.0f) return std::nullopt;
        glm::vec3 m = dist.sample(u);
        if (glm::dot(wo, m) <= 0.0f) return std::nullopt;
        glm::vec3 wi = reflect(wo, m);
        if (wi.z <= 0.0f) return std::nullopt;
        return LobeSample{wi, eval(wo, wi), pdf(wo, wi), false};
    }
    float selectionWeight(const glm::vec3& wo) const {
        return weight * schlickFresnel(0.04f, std::max(wo.z, 0.0f));
    }
};

}  // namespace principled::bsdf
