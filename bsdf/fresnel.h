// SPDX-License-Identifier: Apache-2.0
// Fresnel reflectance: Schlick's approximation, UE4's spherical-Gaussian variant, exact dielectric.
#pragma once

#include "bsdf/frame.h"

namespace principled::bsdf {

/// Schlick 1994, "An Inexpensive BRDF Model for Physically-based Rendering", eq. 15: (1-cos)^5.
inline float schlickWeight(float cosTheta) {
    float m = std::clamp(1.0f - cosTheta, 0.0f, 1.0f);
    float m2 = m * m;
    return m2 * m2 * m;
}

/// Schlick 1994, eq. 15: F0 + (1 - F0)(1 - cos)^5.
inline glm::vec3 schlickFresnel(const glm::vec3& f0, float cosTheta) {
    return glm::mix(f0, glm::vec3(1.0f), schlickWeight(cosTheta));
}
inline float schlickFresnel(float f0, float cosTheta) {
    return f0 + (1.0f - f0) * schlickWeight(cosTheta);
}

/// Karis 2013, "Real Shading in Unreal Engine 4", p. 3: spherical-Gaussian Schlick,
/// F0 + (1 - F0) 2^((-5.55473 v.h - 6.98316) v.h).
inline glm::vec3 schlickFresnelSG(const glm::vec3& f0, float vDotH) {
    float c = std::clamp(vDotH, 0.0f, 1.0f);
    float w = std::exp2((-5.55473f * c - 6.98316f) * c);
    return glm::mix(f0, glm::vec3(1.0f), w);
}

/// Exact unpolarised Fresnel reflectance of a dielectric interface, cosI > 0 on the incident
/// side, eta = n_t / n_i. Returns 1 on total internal reflection.
/// Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces", eq. 22.
inline float fresnelDielectric(float cosI, float eta) {
    cosI = std::clamp(cosI, 0.0f, 1.0f);
    float g2 = eta * eta - 1.0f + cosI * cosI;
    if (g2 < 0.0f) return 1.0f;
    float g = std::sqrt(g2);
    float a = (g - cosI) / (g + cosI);
    float b = (cosI * (g + cosI) - 1.0f) / (cosI * (g - cosI) + 1.0f);
    return std::clamp(0.5f * a * a * (1.0f + b * b), 0.0f, 1.0f);
}

}  // namespace principled::bsdf
