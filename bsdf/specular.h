// SPDX-License-Identifier: Apache-2.0
// Microfacet (GGX) reflection: the Disney specular lobe and the UE4 specular lobe, with the
// G and Fresnel variants of each model, and the perfect-mirror limit used below a roughness
// threshold.
#pragma once

#include <cstdint>

#include "bsdf/fresnel.h"
#include "bsdf/ggx.h"
#include "bsdf/lobe.h"

namespace principled::bsdf {

/// Which masking-shadowing term multiplies D F / (4 cos_o cos_i).
enum class SpecularG : uint8_t {
    Smith,          ///< separable Smith with the alphas of D (wdas/brdf after 2017, default)
    SmithRemapped,  ///< isotropic Smith with alpha = (0.5 + 0.5 r)^2 (Burley 2012 course notes)
    SchlickSmith,   ///< Schlick-Smith with k = (r + 1)^2 / 8 (Karis 2013, UE4)
};
/// Which Fresnel approximation.
enum class SpecularFresnel : uint8_t {
    Schlick,    ///< mix(F0, 1, (1 - cos)^5) (Burley 2012)
    SchlickSG,  ///< spherical-Gaussian Schlick (Karis 2013)
    /// mix(F0, 1, w), w = (F_d(cos, eta) - F_d(1, eta)) / (1 - F_d(1, eta)), F_d the exact
    /// dielectric Fresnel: Cycles 3.4's Principled v1 (bsdf_util.h, interpolate_fresnel_color)
    DielectricBlend,
};

struct Specular {
    Ggx dist;
    glm::vec3 f0{0.04f};
    float weight = 1.0f;  ///< 1 - specTrans (1 - metallic)
    float gParam = 0.25f;  ///< alpha for SmithRemapped, k for SchlickSmith
    SpecularG gModel = SpecularG::Smith;
    SpecularFresnel fModel = SpecularFresnel::Schlick;
    float eta = 1.5f;   ///< DielectricBlend: the index whose Fresnel curve shapes the blend
    float fd0 = 0.04f;  ///< DielectricBlend: F_d(1, eta), below 1
    bool visible = true;  ///< VNDF sampling (Heitz 2018) instead of D sampling
    bool delta = false;   ///< perfect mirror (roughness below Options::deltaRoughness)

    glm::vec3 fresnel(float cosD) const {
        if (fModel == SpecularFresnel::Schlick) [[likely]]  // the default: one test, no table
            return schlickFresnel(f0, cosD);
        switch (fModel) {
            case SpecularFresnel::Schlick:
                return schlickFresnel(f0, cosD);
            case SpecularFresnel::SchlickSG:
                return schlickFresnelSG(f0, cosD);
            case SpecularFresnel::DielectricBlend: {
                // Blender Foundation 2022, Cycles 3.4 kernel/closure/bsdf_util.h,
                // interpolate_fresnel_color: the normalised dielectric Fresnel blends F0 to white.
                // eta 1 (specular 0) gives 0/0 at grazing: w = 0 there (the comparison maps NaN to 0).
                float w = (fresnelDielectric(cosD, eta) - fd0) / (1.0f - fd0);
                return glm::mix(f0, glm::vec3(1.0f), w > 0.0f ? std::min(w, 1.0f) : 0.0f);
            }
        }
        return f0;
    }

    float G(const glm::vec3& wo, const glm::vec3& wi) const {
        switch (gModel) {
            case SpecularG::Smith:
                return dist.G(wo, wi);
            case SpecularG::SmithRemapped:
                // Burley 2012, "Physically-Based Shading at Disney", §5.6: G with
                // alpha_g = (0.5 + 0.5 roughness)^2 (obsoleted by wdas/brdf commit 9aee636).
                return Ggx{gParam, gParam}.G(wo, wi);
            case SpecularG::SchlickSmith: {
                // Karis 2013, "Real Shading in Unreal Engine 4", eq. 4: G1(v) = n.v / (n.v (1-k) + k).
                float k = gParam;
                float go = wo.z / (wo.z * (1.0f - k) + k), gi = wi.z / (wi.z * (1.0f - k) + k);
                return go * gi;
            }
        }
        return 0.0f;
    }

    /// Cook & Torrance 1982 / Walter et al. 2007, eq. 20: f = D G F / (4 cos_o cos_i); returns f cos_i.
    glm::vec3 eval(const glm::vec3& wo, const glm::vec3& wi) const {
        if (delta || wo.z <= 0.0f || wi.z <= 0.0f) return glm::vec3(0.0f);
        glm::vec3 h = wo + wi;
        float l = glm::length(h);
        if (!(l > 0.0f)) return glm::vec3(0.0f);
        h /= l;
        float d = dist.D(h);
        if (d == 0.0f) return glm::vec3(0.0f);
        return fresnel(glm::dot(wi, h)) * (weight * d * G(wo, wi) / (4.0f * wo.z));
    }

    /// Walter et al. 2007, eq. 14: pdf(wi) = pdf(m) / (4 |wo.m|).
    float pdf(const glm::vec3& wo, const glm::vec3& wi) const {
        if (delta || wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
        glm::vec3 h = wo + wi;
        float l = glm::length(h);
        if (!(l > 0.0f)) return 0.0f;
        h /= l;
        float c = glm::dot(wo, h);
        if (c <= 0.0f) return 0.0f;
        return dist.pdfNormal(wo, h, visible) / (4.0f * c);
    }

    /// eval() and pdf() in one pass for the facade, for wo.z > 0, wi.z > 0, not delta:
    /// h = normalize(wo + wi), k = dist.constants(), inv4CosO = 1 / (4 wo.z) and
    /// g1oK = dist.G1(wo) inv4CosO are computed once per material / view. The same formulas as
    /// eval() and pdf() with the divisions folded (equal up to float rounding):
    /// D G1(wi) = invPiAxAy 2 c_i / (e^2 (c_i + r_i)) and D = invPiAxAy / e^2 share one division,
    /// and the visible-normal pdf G1(wo) (wo.m) D / wo.z / (4 wo.m) = D G1(wo) / (4 wo.z).
    glm::vec3 evalPdf(const glm::vec3& wo, const glm::vec3& wi, const glm::vec3& h,
                      const GgxConst& k, float inv4CosO, float g1oK, float* pdfOut) const {
        float e = Ggx::dTerm(h, k);
        float c = glm::dot(wo, h);
        if (gModel == SpecularG::Smith) {
            // Heitz 2014, eq. 86: G1(wi) = 2 c_i / (c_i + r_i), r_i = |(ax wi.x, ay wi.y, wi.z)|.
            float ci = wi.z;
            float ri = std::sqrt(sqr(dist.ax * wi.x) + sqr(dist.ay * wi.y) + ci * ci);
            float s = ci + ri;
            float q = k.invPiAxAy / (e * e * s);
            float d = q * s;  // Burley 2012, eq. 13
            // Heitz 2018, eq. 3 (visible normals) or Walter et al. 2007, eq. 14 (D m.z), / (4 wo.m).
            *pdfOut = c > 0.0f ? (visible ? d * g1oK : d * h.z / (4.0f * c)) : 0.0f;
            // Walter et al. 2007, eq. 20: D F G1(wo) G1(wi) / (4 cos_o).
            return fresnel(glm::dot(wi, h)) * (weight * (2.0f * ci * q) * g1oK);
        }
        float d = k.invPiAxAy / (e * e);  // Burley 2012, eq. 13
        *pdfOut = c > 0.0f ? (visible ? d * g1oK : d * h.z / (4.0f * c)) : 0.0f;
        return fresnel(glm::dot(wi, h)) * (weight * d * G(wo, wi) * inv4CosO);
    }

    /// The direction part of sample() for a rough lobe (the facade evaluates the mixture itself).
    bool sampleWi(const glm::vec3& wo, const glm::vec2& u, glm::vec3* wi) const {
        glm::vec3 m = dist.sampleNormal(wo, u, visible);
        *wi = reflect(wo, m);
        return wi->z > 0.0f;
    }

    std::optional<LobeSample> sample(const glm::vec3& wo, const glm::vec2& u, float) const {
        if (wo.z <= 0.0f) return std::nullopt;
        if (delta) {
            // Perfect mirror: the alpha -> 0 limit of D G F / (4 cos_o cos_i) integrates to
            // F(cos_o) G(wo, wi) (G -> 1 for Smith, not for Schlick-Smith or the remap).
            glm::vec3 wi(-wo.x, -wo.y, wo.z);
            return LobeSample{wi, fresnel(wo.z) * (weight * G(wo, wi)), 1.0f, true};
        }
        glm::vec3 m = dist.sampleNormal(wo, u, visible);
        glm::vec3 wi = reflect(wo, m);
        if (wi.z <= 0.0f) return std::nullopt;  // VNDF/D samples below the horizon are lost
        return LobeSample{wi, eval(wo, wi), pdf(wo, wi), false};
    }

    float selectionWeight(const glm::vec3& wo) const {
        return weight * luminance(fresnel(std::max(wo.z, 0.0f)));
    }
};

}  // namespace principled::bsdf
