// SPDX-License-Identifier: Apache-2.0
// Placeholder Lambert + isotropic GGX until the full Disney/UE4 lobe library replaces it.
#include "bsdf/bsdf.h"

#include <algorithm>
#include <cmath>

namespace principled::bsdf {
namespace {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInvPi = 1.0f / kPi;

float cosTheta(const glm::vec3& w) { return w.z; }

// Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces", eq. 33 (GGX D).
float ggxD(float cosH, float alpha) {
    float a2 = alpha * alpha;
    float d = cosH * cosH * (a2 - 1.0f) + 1.0f;
    return a2 / (kPi * d * d);
}

// Walter et al. 2007, eq. 34 (Smith G1 for GGX).
float ggxG1(float cosW, float alpha) {
    float c2 = cosW * cosW;
    float t2 = std::max(0.0f, 1.0f - c2) / std::max(c2, 1e-12f);
    return 2.0f / (1.0f + std::sqrt(1.0f + alpha * alpha * t2));
}

glm::vec3 schlick(const glm::vec3& f0, float c) {
    float m = std::clamp(1.0f - c, 0.0f, 1.0f);
    float m5 = m * m * m * m * m;
    return f0 + (glm::vec3(1.0f) - f0) * m5;
}

}  // namespace

Bsdf::Bsdf(const MaterialParams& params, const Options& options) : _p(params), _o(options) {
    float r = std::clamp(_p.roughness, 0.0f, 1.0f);
    _alpha = std::max(r * r, 1e-3f);
    float m = std::clamp(_p.metallic, 0.0f, 1.0f);
    _diffuse = _p.baseColor * (1.0f - m);
    _f0 = glm::mix(glm::vec3(0.08f * _p.specular), _p.baseColor, m);
    float dw = (_diffuse.x + _diffuse.y + _diffuse.z) / 3.0f;
    float sw = (_f0.x + _f0.y + _f0.z) / 3.0f + 0.1f;
    _specWeight = sw / (sw + dw);
    _lobes = lobeBit(Lobe::Specular) | (dw > 0.0f ? lobeBit(Lobe::Diffuse) : 0u);
}

glm::vec3 Bsdf::eval(const glm::vec3& wo, const glm::vec3& wi, float* pdfOut,
                     LobeValues* perLobe) const {
    if (perLobe) perLobe->fill(glm::vec3(0.0f));
    if (pdfOut) *pdfOut = 0.0f;
    float co = cosTheta(wo), ci = cosTheta(wi);
    if (co <= 0.0f || ci <= 0.0f) return glm::vec3(0.0f);
    glm::vec3 h = glm::normalize(wo + wi);
    float d = ggxD(h.z, _alpha);
    glm::vec3 spec = schlick(_f0, glm::dot(wi, h)) * d * ggxG1(co, _alpha) * ggxG1(ci, _alpha) /
                     (4.0f * co);  // times cos_i already folded
    glm::vec3 diff = _diffuse * kInvPi * ci;
    if (perLobe) {
        (*perLobe)[int(Lobe::Diffuse)] = diff;
        (*perLobe)[int(Lobe::Specular)] = spec;
    }
    if (pdfOut) *pdfOut = pdf(wo, wi);
    return diff + spec;
}

float Bsdf::pdf(const glm::vec3& wo, const glm::vec3& wi) const {
    if (cosTheta(wo) <= 0.0f || cosTheta(wi) <= 0.0f) return 0.0f;
    glm::vec3 h = glm::normalize(wo + wi);
    float pSpec = ggxD(h.z, _alpha) * h.z / (4.0f * std::max(glm::dot(wo, h), 1e-8f));
    float pDiff = cosTheta(wi) * kInvPi;
    return _specWeight * pSpec + (1.0f - _specWeight) * pDiff;
}

std::optional<BsdfSample> Bsdf::sample(const glm::vec3& wo, float uLobe, const glm::vec2& u) const {
    if (cosTheta(wo) <= 0.0f) return std::nullopt;
    glm::vec3 wi;
    if (uLobe < _specWeight) {
        // Walter et al. 2007, eq. 35-36: GGX half-vector sampling.
        float phi = 2.0f * kPi * u.x;
        float cos2 = (1.0f - u.y) / (1.0f + (_alpha * _alpha - 1.0f) * u.y);
        float c = std::sqrt(std::max(0.0f, cos2)), s = std::sqrt(std::max(0.0f, 1.0f - cos2));
        glm::vec3 h(s * std::cos(phi), s * std::sin(phi), c);
        wi = 2.0f * glm::dot(wo, h) * h - wo;
    } else {
        // Malley's method: cosine-weighted hemisphere.
        float r = std::sqrt(u.x), phi = 2.0f * kPi * u.y;
        wi = glm::vec3(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - u.x)));
    }
    if (cosTheta(wi) <= 0.0f) return std::nullopt;
    BsdfSample s;
    s.wi = wi;
    s.f = eval(wo, wi, &s.pdf);
    s.lobe = uLobe < _specWeight ? Lobe::Specular : Lobe::Diffuse;
    if (!(s.pdf > 0.0f)) return std::nullopt;
    return s;
}

}  // namespace principled::bsdf
