// SPDX-License-Identifier: Apache-2.0
#include "delegate/shading/previewSurfaceParams.h"

#include <algorithm>
#include <cmath>

namespace principled::shading {

namespace {

float clamp01(float v) {
    return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f;
}
glm::vec3 clamp01(const glm::vec3& v) {
    return {clamp01(v.x), clamp01(v.y), clamp01(v.z)};
}
float nonNegative(float v) {
    return std::isfinite(v) && v > 0.0f ? v : 0.0f;
}

void apply(const std::optional<float>& v, float* out) {
    if (v && std::isfinite(*v)) *out = *v;
}

// The explicit-F0 fields exist only once bsdf/ has the specular workflow (branch bsdf);
// set them when present, so this file builds against either version of MaterialParams.
template <typename Params>
void setExplicitF0(Params& p, const glm::vec3& f0) {
    if constexpr (requires {
                      p.specularWorkflow = true;
                      p.specularColor = f0;
                  }) {
        p.specularWorkflow = true;
        p.specularColor = f0;
    }
}

glm::vec3 unitNormal(glm::vec3 n) {
    for (int i = 0; i < 3; ++i) n[i] = std::isfinite(n[i]) ? std::clamp(n[i], -1.0f, 1.0f) : 0.0f;
    float len = glm::length(n);
    // 1e-6: below this the map is degenerate (e.g. an all-zero texel); keep the surface normal.
    if (!(len > 1e-6f)) return {0.0f, 0.0f, 1.0f};
    return n / len;
}

}  // namespace

float specularFromIor(float ior) {
    if (!std::isfinite(ior) || ior <= 0.0f) return 0.5f;
    // Mitsuba 3 principled BSDF: the inverse of eta = 2/(1-sqrt(0.08 specular)) - 1.
    float r = (ior - 1.0f) / (ior + 1.0f);
    return std::clamp(r * r / 0.08f, 0.0f, bsdf::kMaxSpecular);  // F0 = 0.08 specular
}

ShadedMaterial mapPreviewSurface(const PreviewSurfaceParams& in) {
    ShadedMaterial out;
    bsdf::MaterialParams& p = out.params;
    p.baseColor = clamp01(in.diffuseColor);
    p.metallic = in.metallic;
    p.roughness = in.roughness;
    if (std::isfinite(in.ior) && in.ior > 0.0f) p.ior = in.ior;
    p.specular = specularFromIor(in.ior);
    p.clearcoat = in.clearcoat;
    p.thin = in.thin;
    // clearcoatRoughness is a GGX roughness (Storm's preview surface; Blender imports it as the
    // Principled BSDF's Clearcoat Roughness, alpha = r^2 in Cycles): the coat's alpha is r^2,
    // over the whole range (Disney's gloss reaches only alpha 0.1; 1 - r as gloss kept a
    // roughness-1 coat sharp). The gloss stays the nearest Disney value, for diagnostics.
    {
        const float r = clamp01(in.clearcoatRoughness);
        p.clearcoatAlpha = std::max(r * r, 0.001f);
        p.clearcoatGloss = clamp01((0.1f - r * r) / 0.099f);
    }
    if (in.useSpecularWorkflow) {
        // Specular workflow: F0 = specularColor, F90 = 1, no metal. For a BSDF without an
        // explicit F0: strength from the brightest channel, tint from its chroma.
        glm::vec3 sc = clamp01(in.specularColor);
        float m = std::max({sc.x, sc.y, sc.z});
        p.metallic = 0.0f;
        p.specular = clamp01(m / 0.08f);  // 0.08: Disney specular 1 = F0 0.08
        p.specularTint = m > 0.0f && (sc.x != sc.y || sc.y != sc.z) ? 1.0f : 0.0f;
        out.specularWorkflow = true;
        out.specularColor = sc;
        setExplicitF0(p, sc);
    }
    apply(in.subsurface, &p.subsurface);
    apply(in.specular, &p.specular);
    apply(in.specularTint, &p.specularTint);
    apply(in.anisotropic, &p.anisotropic);
    apply(in.sheen, &p.sheen);
    apply(in.sheenTint, &p.sheenTint);
    if (in.clearcoatGloss && std::isfinite(*in.clearcoatGloss)) p.clearcoatAlpha = -1.0f;  // Disney's own input wins
    apply(in.clearcoatGloss, &p.clearcoatGloss);
    apply(in.specTrans, &p.specTrans);
    p.metallic = clamp01(p.metallic);
    p.roughness = clamp01(p.roughness);
    p.subsurface = clamp01(p.subsurface);
    p.specular = std::isfinite(p.specular) ? std::clamp(p.specular, 0.0f, bsdf::kMaxSpecular) : 0.0f;
    p.specularTint = clamp01(p.specularTint);
    p.anisotropic = clamp01(p.anisotropic);
    p.sheen = clamp01(p.sheen);
    p.sheenTint = clamp01(p.sheenTint);
    p.clearcoat = clamp01(p.clearcoat);
    p.clearcoatGloss = clamp01(p.clearcoatGloss);
    p.specTrans = clamp01(p.specTrans);
    out.emission = {nonNegative(in.emissiveColor.x), nonNegative(in.emissiveColor.y),
                    nonNegative(in.emissiveColor.z)};
    out.opacity = clamp01(in.opacity);
    out.opacityThreshold = clamp01(in.opacityThreshold);
    out.opacityMode = in.opacityMode;
    // Transparent mode: opacity scales the lobes that are not specular; the integrator lets
    // (1 - opacity) of the light through as well (ShadedMaterial::keepsSpecular).
    if (out.keepsSpecular()) out.params.diffuseScale = out.opacity;
    out.tangentNormal = unitNormal(in.normal);
    out.hasNormalMap = in.normalVaries || out.tangentNormal != glm::vec3(0.0f, 0.0f, 1.0f);
    return out;
}

}  // namespace principled::shading
