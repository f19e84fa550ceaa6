// SPDX-License-Identifier: Apache-2.0
// The anisotropic GGX (Trowbridge-Reitz, "GTR2") microfacet distribution: D, Lambda, Smith G1,
// visible-normal sampling (Heitz 2018) and classic distribution sampling (Walter 2007).
#pragma once

#include "bsdf/frame.h"

namespace principled::bsdf {

/// Smallest alpha on either axis. 1e-4: one near-zero axis makes D() overflow in float
/// (pbrt-v4 TrowbridgeReitzDistribution clamps to the same value); see reference/bsdf.md §4.1.
inline constexpr float kMinAlpha = 1e-4f;

/// Burley 2012, "Physically-Based Shading at Disney", §5.4 / addendum: aspect =
/// sqrt(1 - 0.9 anisotropic), ax = r^2 / aspect, ay = r^2 aspect (aspect ratio capped at 10:1).
/// Both axes are floored at 0.001 as in the reference code (wdas/brdf, pbrt-v3, Mitsuba).
inline glm::vec2 disneyAlpha(float roughness, float anisotropic) {
    constexpr float kFloor = 1e-3f;  // 0.001: the reference code's alpha floor
    float aspect = std::sqrt(1.0f - 0.9f * std::clamp(anisotropic, 0.0f, 1.0f));
    float a = roughness * roughness;
    return {std::max(kFloor, a / aspect), std::max(kFloor, a * aspect)};
}

/// Per-material reciprocals of a Ggx, computed once per Bsdf for the facade's fused evaluation
/// (multiplications instead of divisions in D; differs from Ggx::D by float rounding only).
struct GgxConst {
    float invAx = 4.0f, invAy = 4.0f, invPiAxAy = 16.0f * kInvPi;
};

struct Ggx {
    float ax = 0.25f, ay = 0.25f;

    /// Burley 2012, appendix B.2, eq. 13 (anisotropic GTR2):
    /// D = 1 / (pi ax ay ((h.x/ax)^2 + (h.y/ay)^2 + h.z^2)^2).
    float D(const glm::vec3& h) const {
        if (h.z <= 0.0f) return 0.0f;
        float e = sqr(h.x / ax) + sqr(h.y / ay) + h.z * h.z;
        float d = kPi * ax * ay * e * e;
        return d > 0.0f ? 1.0f / d : 0.0f;
    }

    /// Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs",
    /// eq. 86 (anisotropic GGX): G1 = 1 / (1 + Lambda) = 2|w.z| / (|w.z| + |(ax w.x, ay w.y, w.z)|),
    /// written without tan so that grazing directions give 0 instead of NaN.
    float G1(const glm::vec3& w) const {
        float c = std::abs(w.z);
        float r = std::sqrt(sqr(ax * w.x) + sqr(ay * w.y) + c * c);
        float d = c + r;
        return d > 0.0f ? 2.0f * c / d : 0.0f;
    }

    /// Separable Smith masking-shadowing G1(wo) G1(wi), as in the Disney reference code
    /// (wdas/brdf disney.brdf after commit 9aee636, 2017).
    float G(const glm::vec3& wo, const glm::vec3& wi) const { return G1(wo) * G1(wi); }

    GgxConst constants() const { return {1.0f / ax, 1.0f / ay, 1.0f / (kPi * ax * ay)}; }
    /// Burley 2012, appendix B.2, eq. 13 with the reciprocals precomputed: returns the squared
    /// denominator term e = (h.x/ax)^2 + (h.y/ay)^2 + h.z^2 (D = invPiAxAy / e^2).
    static float dTerm(const glm::vec3& h, const GgxConst& k) {
        float x = h.x * k.invAx, y = h.y * k.invAy;
        return x * x + y * y + h.z * h.z;
    }

    /// Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4), listing 1.
    /// Requires wo.z > 0. Density of m: pdfVisible(wo, m) = G1(wo) max(0, wo.m) D(m) / wo.z.
    glm::vec3 sampleVisible(const glm::vec3& wo, const glm::vec2& u) const {
        glm::vec3 vh = glm::normalize(glm::vec3(ax * wo.x, ay * wo.y, wo.z));
        float l2 = vh.x * vh.x + vh.y * vh.y;
        glm::vec3 t1 = l2 > 0.0f ? glm::vec3(-vh.y, vh.x, 0.0f) / std::sqrt(l2)
                                 : glm::vec3(1.0f, 0.0f, 0.0f);
        glm::vec3 t2 = glm::cross(vh, t1);
        float r = std::sqrt(u.x), phi = kTwoPi * u.y;
        float p1 = r * std::cos(phi), p2 = r * std::sin(phi);
        float s = 0.5f * (1.0f + vh.z);
        p2 = (1.0f - s) * safeSqrt(1.0f - p1 * p1) + s * p2;
        glm::vec3 nh = p1 * t1 + p2 * t2 + safeSqrt(1.0f - p1 * p1 - p2 * p2) * vh;
        glm::vec3 m(ax * nh.x, ay * nh.y, std::max(1e-6f, nh.z));  // 1e-6: keep m above horizon
        return glm::normalize(m);
    }
    float pdfVisible(const glm::vec3& wo, const glm::vec3& m) const {
        if (wo.z <= 0.0f) return 0.0f;
        return G1(wo) * std::max(0.0f, glm::dot(wo, m)) * D(m) / wo.z;
    }

    /// Walter et al. 2007, eq. 35-36, extended to two axes (Burley 2012, appendix B.2, eq. 14):
    /// m = normalize(sqrt(u/(1-u)) (ax cos phi, ay sin phi), 1). Density of m: D(m) m.z.
    glm::vec3 sampleClassic(const glm::vec2& u) const {
        float phi = kTwoPi * u.y;
        float t = std::sqrt(u.x / std::max(1.0f - u.x, 1e-7f));  // 1e-7: u.x < 1 in float
        return glm::normalize(glm::vec3(t * ax * std::cos(phi), t * ay * std::sin(phi), 1.0f));
    }
    float pdfClassic(const glm::vec3& m) const { return D(m) * std::max(m.z, 0.0f); }

    /// Microfacet normal density of whichever method is selected.
    glm::vec3 sampleNormal(const glm::vec3& wo, const glm::vec2& u, bool visible) const {
        return visible ? sampleVisible(wo, u) : sampleClassic(u);
    }
    float pdfNormal(const glm::vec3& wo, const glm::vec3& m, bool visible) const {
        return visible ? pdfVisible(wo, m) : pdfClassic(m);
    }
};

}  // namespace principled::bsdf
