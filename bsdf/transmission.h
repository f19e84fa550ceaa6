// SPDX-License-Identifier: Apache-2.0
// Dielectric transmission (Burley 2015 specTrans): a rough (or smooth) dielectric interface
// that reflects with the exact Fresnel factor and refracts the rest (Walter et al. 2007), or,
// for thin surfaces, passes light straight through without bending it.
#pragma once

#include "bsdf/fresnel.h"
#include "bsdf/ggx.h"
#include "bsdf/lobe.h"

namespace principled::bsdf {

/// Evaluated in a frame where wo.z > 0 (the facade mirrors z when the view is inside a solid
/// and passes eta = n_inside / n_outside or its inverse). Throughput of refraction omits the
/// 1/eta^2 radiance compression, so the lobe is energy-neutral in a furnace (it cancels for
/// closed objects anyway).
struct Dielectric {
    Ggx dist;
    float eta = 1.5f;         ///< n on the far side of wo / n on wo's side
    glm::vec3 tint{1.0f};     ///< transmission colour (sqrt(baseColor) solid, baseColor thin)
    float weight = 0.0f;      ///< specTrans (1 - metallic)
    bool thin = false;
    bool visible = true;
    bool delta = false;       ///< smooth glass

    /// Microfacet normal of the pair: reflection half vector, or the generalised half vector of
    /// refraction (Walter et al. 2007, eq. 16), oriented to +z. Returns false when degenerate.
    bool halfVector(const glm::vec3& wo, const glm::vec3& wi, glm::vec3* m, bool* refr) const {
        *refr = wi.z < 0.0f;
        glm::vec3 h;
        if (!*refr) h = wo + wi;
        else if (thin) h = wo + flipZ(wi);
        else h = wo + eta * wi;
        float l = glm::length(h);
        if (!(l > 0.0f)) return false;
        h /= l;
        if (h.z < 0.0f) h = -h;
        *m = h;
        if (glm::dot(wo, h) <= 0.0f) return false;
        if (*refr && !thin) return glm::dot(wi, h) < 0.0f;
        return true;
    }

    glm::vec3 eval(const glm::vec3& wo, const glm::vec3& wi) const {
        if (delta || wo.z <= 0.0f || wi.z == 0.0f) return glm::vec3(0.0f);
        glm::vec3 m;
        bool refr;
        if (!halfVector(wo, wi, &m, &refr)) return glm::vec3(0.0f);
        float cosO = glm::dot(wo, m);
        float F = fresnelDielectric(cosO, eta);
        float d = dist.D(m);
        float g = dist.G(wo, wi);
        if (!refr) {
            // Walter et al. 2007, eq. 20: f_r = F G D / (4 |cos_o| |cos_i|).
            return glm::vec3(weight * F * d * g / (4.0f * wo.z));
        }
        if (thin) {
            // Thin sheet: the reflection geometry mirrored through the surface (Burley 2015,
            // "Extending the Disney BRDF to a BSDF with Integrated Subsurface Scattering", §4.3).
            return tint * (weight * (1.0f - F) * d * g / (4.0f * wo.z));
        }
        // Walter et al. 2007, eq. 21 (with n_o / n_i = eta):
        // f_t = |wo.m||wi.m| / (|cos_o||cos_i|) eta^2 (1 - F) G D / (wo.m + eta wi.m)^2.
        float cosI = glm::dot(wi, m);
        float denom = cosO + eta * cosI;
        float v = eta * eta * std::abs(cosI) * cosO * (1.0f - F) * g * d / (wo.z * denom * denom);
        return tint * (weight * v);
    }

    float pdf(const glm::vec3& wo, const glm::vec3& wi) const {
        if (delta || wo.z <= 0.0f || wi.z == 0.0f) return 0.0f;
        glm::vec3 m;
        bool refr;
        if (!halfVector(wo, wi, &m, &refr)) return 0.0f;
        float cosO = glm::dot(wo, m);
        float F = fresnelDielectric(cosO, eta);
        float pm = dist.pdfNormal(wo, m, visible);
        if (!refr || thin) return pm / (4.0f * cosO) * (refr ? 1.0f - F : F);
        // Walter et al. 2007, eq. 17: |d omega_m / d omega_i| = eta^2 |wi.m| / (wo.m + eta wi.m)^2.
        float cosI = glm::dot(wi, m);
        float denom = cosO + eta * cosI;
        return pm * eta * eta * std::abs(cosI) / (denom * denom) * (1.0f - F);
    }

    /// eval() and pdf() in one pass for the facade (one half vector, Fresnel factor and D),
    /// with g1o = dist.G1(wo) precomputed. Same expressions and order (bit-identical).
    glm::vec3 evalPdf(const glm::vec3& wo, const glm::vec3& wi, float g1o, float* pdfOut) const {
        *pdfOut = 0.0f;
        if (delta || wo.z <= 0.0f || wi.z == 0.0f) return glm::vec3(0.0f);
        glm::vec3 m;
        bool refr;
        if (!halfVector(wo, wi, &m, &refr)) return glm::vec3(0.0f);
        float cosO = glm::dot(wo, m);
        float F = fresnelDielectric(cosO, eta);
        float d = dist.D(m);
        float g = g1o * dist.G1(wi);
        // Heitz 2018, eq. 3 (visible normals) or Walter et al. 2007, eq. 14 (D m.z).
        float pm = visible ? g1o * std::max(0.0f, cosO) * d / wo.z : d * std::max(m.z, 0.0f);
        if (!refr) {
            *pdfOut = pm / (4.0f * cosO) * F;
            return glm::vec3(weight * F * d * g / (4.0f * wo.z));  // Walter et al. 2007, eq. 20
        }
        if (thin) {
            *pdfOut = pm / (4.0f * cosO) * (1.0f - F);
            return tint * (weight * (1.0f - F) * d * g / (4.0f * wo.z));  // Burley 2015, §4.3
        }
        // Walter et al. 2007, eq. 17 (pdf) and eq. 21 (f_t), as in pdf() and eval().
        float cosI = glm::dot(wi, m);
        float denom = cosO + eta * cosI;
        *pdfOut = pm * eta * eta * std::abs(cosI) / (denom * denom) * (1.0f - F);
        float v = eta * eta * std::abs(cosI) * cosO * (1.0f - F) * g * d / (wo.z * denom * denom);
        return tint * (weight * v);
    }

    /// The direction part of sample() for a rough interface (same rejections as sample()).
    bool sampleWi(const glm::vec3& wo, const glm::vec2& u, float uSub, glm::vec3* out) const {
        glm::vec3 m = dist.sampleNormal(wo, u, visible);
        float cosO = glm::dot(wo, m);
        if (cosO <= 0.0f) return false;
        float F = fresnelDielectric(cosO, eta);
        glm::vec3 wi;
        if (uSub < F) {
            wi = reflect(wo, m);
            if (wi.z <= 0.0f) return false;
        } else if (thin) {
            wi = flipZ(reflect(wo, m));
            if (wi.z >= 0.0f) return false;
        } else {
            if (!refract(wo, m, eta, &wi) || wi.z >= 0.0f) return false;
        }
        float p = pdf(wo, wi);
        if (!(p > 0.0f)) return false;
        *out = wi;
        return true;
    }

    /// uSub chooses reflection (probability F at the sampled normal) or transmission.
    std::optional<LobeSample> sample(const glm::vec3& wo, const glm::vec2& u, float uSub) const {
        if (wo.z <= 0.0f) return std::nullopt;
        if (delta) {
            float F = fresnelDielectric(wo.z, eta);
            if (uSub < F) return LobeSample{{-wo.x, -wo.y, wo.z}, glm::vec3(weight * F), F, true};
            glm::vec3 wi;
            if (thin) wi = -wo;
            else if (!refract(wo, glm::vec3(0, 0, 1), eta, &wi)) return std::nullopt;
            return LobeSample{wi, tint * (weight * (1.0f - F)), 1.0f - F, true};
        }
        glm::vec3 m = dist.sampleNormal(wo, u, visible);
        float cosO = glm::dot(wo, m);
        if (cosO <= 0.0f) return std::nullopt;
        float F = fresnelDielectric(cosO, eta);
        glm::vec3 wi;
        if (uSub < F) {
            wi = reflect(wo, m);
            if (wi.z <= 0.0f) return std::nullopt;
        } else if (thin) {
            wi = flipZ(reflect(wo, m));
            if (wi.z >= 0.0f) return std::nullopt;
        } else {
            if (!refract(wo, m, eta, &wi) || wi.z >= 0.0f) return std::nullopt;
        }
        float p = pdf(wo, wi);
        if (!(p > 0.0f)) return std::nullopt;
        return LobeSample{wi, eval(wo, wi), p, false};
    }

    float selectionWeight(const glm::vec3&) const { return weight; }
};

}  // namespace principled::bsdf
