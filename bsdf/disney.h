// SPDX-License-Identifier: Apache-2.0
// The Disney principled BSDF: the eleven parameters of Burley 2012 plus the specTrans / ior /
// thin extension of Burley 2015, turned into weighted lobes.
#pragma once

#include "bsdf/lobeSet.h"

namespace principled::bsdf {

inline LobeSet buildDisney(const MaterialParams& p, const Options& o) {
    LobeSet s;
    glm::vec3 base = glm::max(p.baseColor, glm::vec3(0.0f));
    float r = std::clamp(p.roughness, 0.0f, 1.0f);
    float metallic = p.specularWorkflow ? 0.0f : std::clamp(p.metallic, 0.0f, 1.0f);
    float specTrans = std::clamp(p.specTrans, 0.0f, 1.0f);
    // Burley 2012, "Physically-Based Shading at Disney", §5.1 and wdas/brdf disney.brdf:
    // Ctint = baseColor / luminance (white when black), Cspec0 = mix(0.08 specular
    // mix(1, Ctint, specularTint), baseColor, metallic), Csheen = mix(1, Ctint, sheenTint).
    float lum = luminance(base);
    // Divided as a full 4-lane vector: left to itself the compiler packs the three divisions
    // with an undefined fourth lane (a denormal there costs a microcode assist, ~40 ns).
    glm::vec3 tint = lum > 0.0f ? glm::vec3(glm::vec4(base, lum) / lum) : glm::vec3(1.0f);
    glm::vec3 cspec0 = glm::mix(0.08f * std::clamp(p.specular, 0.0f, kMaxSpecular) *
                                    glm::mix(glm::vec3(1.0f), tint, std::clamp(p.specularTint, 0.0f, 1.0f)),
                                base, metallic);
    if (p.specularWorkflow) cspec0 = glm::clamp(p.specularColor, 0.0f, 1.0f);
    glm::vec3 csheen = glm::mix(glm::vec3(1.0f), tint, std::clamp(p.sheenTint, 0.0f, 1.0f));
    // Burley 2015, "Extending the Disney BRDF to a BSDF with Integrated Subsurface Scattering",
    // §3: the diffuse-like lobes are scaled by (1 - metallic)(1 - specTrans).
    float diffuseWeight = (1.0f - metallic) * (1.0f - specTrans) * std::clamp(p.diffuseScale, 0.0f, 1.0f);
    float transWeight = (1.0f - metallic) * specTrans;

    s.diffuse = {base * diffuseWeight, r, std::clamp(p.subsurface, 0.0f, 1.0f)};
    if (keepLobe(o, Lobe::Diffuse, maxComponent(s.diffuse.color))) s.mask |= lobeBit(Lobe::Diffuse);

    s.sheen.color = std::clamp(p.sheen, 0.0f, 1.0f) * csheen * diffuseWeight;
    if (keepLobe(o, Lobe::Sheen, maxComponent(s.sheen.color))) s.mask |= lobeBit(Lobe::Sheen);

    glm::vec2 alpha = disneyAlpha(r, p.anisotropic);
    s.specular.dist = {alpha.x, alpha.y};
    s.specular.f0 = cspec0;
    s.specular.weight = 1.0f - transWeight;
    if (o.legacySpecularG) {
        s.specular.gModel = SpecularG::SmithRemapped;
        s.specular.gParam = sqr(0.5f + 0.5f * r);
    }
    if (o.dielectricFresnel) {
        // Cycles 3.4's Principled v1: the index of the Disney specular F0 = 0.08 specular,
        // eta = 2 / (1 - sqrt(F0)) - 1, inverting F0 = ((eta - 1) / (eta + 1))^2 (Walter et al.
        // 2007, eq. 22 at cos = 1); the specular workflow uses the material's ior.
        float f0d = 0.08f * std::clamp(p.specular, 0.0f, kMaxSpecular);
        float eta = p.specularWorkflow ? std::max(p.ior, 1.0f) : 2.0f / (1.0f - std::sqrt(f0d)) - 1.0f;
        s.specular.fModel = SpecularFresnel::DielectricBlend;
        s.specular.eta = eta;
        s.specular.fd0 = std::min(fresnelDielectric(1.0f, eta), 0.999f);
    }
    s.specular.visible = o.vndfSampling;
    s.specular.delta = r < o.deltaRoughness;
    if (keepLobe(o, Lobe::Specular, s.specular.weight)) s.mask |= lobeBit(Lobe::Specular);

    // Burley 2012, §5.6: clearcoat alpha = mix(0.1, 0.001, clearcoatGloss), weight 0.25 clearcoat;
    // or the alpha given directly (a roughness beyond Disney's range).
    s.clearcoat.dist.alpha = p.clearcoatAlpha >= 0.0f ? std::clamp(p.clearcoatAlpha, 0.001f, 1.0f)
                                                      : glm::mix(0.1f, 0.001f, std::clamp(p.clearcoatGloss, 0.0f, 1.0f));
    s.clearcoat.weight = 0.25f * std::clamp(p.clearcoat, 0.0f, 1.0f);
    if (keepLobe(o, Lobe::Clearcoat, s.clearcoat.weight)) s.mask |= lobeBit(Lobe::Clearcoat);

    // 1.001: an index of exactly 1 makes the refraction half vector degenerate (Mitsuba does the same).
    float ior = std::abs(p.ior - 1.0f) < 1e-3f ? 1.001f : std::clamp(p.ior, 0.1f, 10.0f);
    // Both interfaces are written field by field from registers: copying one Dielectric into
    // the other reloads bytes still in the store buffer (a store-forwarding stall per Bsdf).
    s.thin = p.thin;
    Ggx distT{alpha.x, alpha.y};  // the specular alphas
    glm::vec3 tintT;
    if (p.thin) {
        // Burley 2015, §4.3, fig. 15: thin roughness scaled by (0.65 eta - 0.35).
        float rt = std::clamp((0.65f * ior - 0.35f) * r, 0.0f, 1.0f);
        glm::vec2 at = disneyAlpha(rt, p.anisotropic);
        distT = {at.x, at.y};
        tintT = base;
    } else {
        // two interfaces of a closed object give baseColor (4 lanes: no undefined lane)
        tintT = glm::vec3(glm::sqrt(glm::vec4(base, 1.0f)));
    }
    const bool deltaT = r < o.deltaRoughness;
    for (Dielectric* t : {&s.transmission, &s.transmissionInside}) {
        t->dist = distT;
        t->tint = tintT;
        t->weight = transWeight;
        t->thin = p.thin;
        t->visible = o.vndfSampling;
        t->delta = deltaT;
    }
    s.transmission.eta = ior;
    s.transmissionInside.eta = 1.0f / ior;
    const Dielectric& t = s.transmission;
    if (keepLobe(o, Lobe::Transmission, t.weight)) s.mask |= lobeBit(Lobe::Transmission);

    if (s.specular.delta) s.deltaMask |= lobeBit(Lobe::Specular);
    if (t.delta) s.deltaMask |= lobeBit(Lobe::Transmission);
    return s;
}

}  // namespace principled::bsdf
