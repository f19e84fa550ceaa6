// SPDX-License-Identifier: Apache-2.0
// The UE4 shading model (Karis 2013): Lambert diffuse and GGX specular with Schlick-Smith G and
// the spherical-Gaussian Schlick Fresnel. Only baseColor, metallic, specular and roughness apply.
#pragma once

#include "bsdf/lobeSet.h"

namespace principled::bsdf {

inline LobeSet buildUe4(const MaterialParams& p, const Options& o) {
    LobeSet s;
    s.lambertDiffuse = true;
    glm::vec3 base = glm::max(p.baseColor, glm::vec3(0.0f));
    float r = std::clamp(p.roughness, 0.0f, 1.0f);
    float metallic = p.specularWorkflow ? 0.0f : std::clamp(p.metallic, 0.0f, 1.0f);
    // Karis 2013, "Real Shading in Unreal Engine 4", p. 2-3: c_diff = baseColor (1 - metallic),
    // F0 = mix(0.08 specular, baseColor, metallic), alpha = roughness^2.
    s.lambert.color = base * (1.0f - metallic) * std::clamp(p.diffuseScale, 0.0f, 1.0f);
    if (keepLobe(o, Lobe::Diffuse, maxComponent(s.lambert.color))) s.mask |= lobeBit(Lobe::Diffuse);

    glm::vec2 alpha = disneyAlpha(r, 0.0f);
    s.specular.dist = {alpha.x, alpha.y};
    s.specular.f0 = glm::mix(glm::vec3(0.08f * std::clamp(p.specular, 0.0f, kMaxSpecular)), base, metallic);
    if (p.specularWorkflow) s.specular.f0 = glm::clamp(p.specularColor, 0.0f, 1.0f);
    s.specular.weight = 1.0f;
    s.specular.gModel = SpecularG::SchlickSmith;
    s.specular.gParam = sqr(r + 1.0f) / 8.0f;  // Karis 2013, eq. 4: k = (r + 1)^2 / 8 (analytic lights)
    s.specular.fModel = SpecularFresnel::SchlickSG;
    s.specular.visible = o.vndfSampling;
    s.specular.delta = r < o.deltaRoughness;
    if (keepLobe(o, Lobe::Specular, s.specular.weight)) s.mask |= lobeBit(Lobe::Specular);
    if (s.specular.delta) s.deltaMask |= lobeBit(Lobe::Specular);
    return s;
}

}  // namespace principled::bsdf
