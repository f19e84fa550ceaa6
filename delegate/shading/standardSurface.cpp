// SPDX-License-Identifier: Apache-2.0
#include "delegate/shading/standardSurface.h"

#include <algorithm>
#include <cmath>

namespace principled::shading {

namespace {

glm::vec3 colour(const glm::vec4& v, int count) {
    return count >= 3 ? glm::vec3(v) : glm::vec3(v.x);
}

}  // namespace

StandardSurfaceParams StandardSurfaceParams::defaults(const hd::Token& id) {
    StandardSurfaceParams s;
    if (id == hd::Token("ND_standard_surface_surfaceshader_100")) {
        // Standard Surface 1.0.0 §Base: base 0.8, base_color 1 (1.0.1 swapped the two).
        s.base = 0.8f;
        s.baseColor = glm::vec3(1.0f);
    }
    return s;
}

bool StandardSurfaceParams::set(const std::string& name, const glm::vec4& v, int count) {
    float f = v.x;
    if (name == "base_color" || name == "specular_color" || name == "sheen_color" ||
        name == "emission_color" || name == "opacity") {
        glm::vec3 c = colour(v, count);
        if (name == "base_color") baseColor = c;
        if (name == "specular_color") specularColor = c;
        if (name == "sheen_color") sheenColor = c;
        if (name == "emission_color") emissionColor = c;
        if (name == "opacity") opacity = c;
        return true;
    }
    float* target = name == "base"                  ? &base
                    : name == "metalness"           ? &metalness
                    : name == "specular"            ? &specular
                    : name == "specular_roughness"  ? &specularRoughness
                    : name == "specular_IOR"        ? &specularIor
                    : name == "specular_anisotropy" ? &specularAnisotropy
                    : name == "transmission"        ? &transmission
                    : name == "subsurface"          ? &subsurface
                    : name == "sheen"               ? &sheen
                    : name == "coat"                ? &coat
                    : name == "coat_roughness"      ? &coatRoughness
                    : name == "emission"            ? &emission
                                                    : nullptr;
    if (target) {
        if (std::isfinite(f)) *target = f;  // a non-finite value keeps the default
        return true;
    }
    if (name == "thin_walled") {
        thinWalled = f > 0.5f;
        return true;
    }
    return false;
}

bool isStandardSurface(const hd::Token& id) {
    return id == hd::Token("ND_standard_surface_surfaceshader") ||
           id == hd::Token("ND_standard_surface_surfaceshader_100");
}

float luminance(const glm::vec3& c) {
    // ITU-R BT.709 luma weights on linear values.
    return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z;
}

float disneySpecularPerWeight(const StandardSurfaceParams& s) {
    // Standard Surface §Specular: dielectric F0 = ((ior-1)/(ior+1))^2, scaled by specular_color;
    // Burley 2012, "specular" parameter: F0 = 0.08 * specular (specularFromIor()).
    return specularFromIor(s.specularIor) * luminance(s.specularColor);
}

float disneySheenPerWeight(const StandardSurfaceParams& s) {
    // Standard Surface §Sheen: the layer's reflectance is sheen * sheen_color.
    return luminance(s.sheenColor);
}

PreviewSurfaceParams mapStandardSurface(const StandardSurfaceParams& s) {
    PreviewSurfaceParams p;
    // Standard Surface §Base: diffuse (and metal F0) colour = base * base_color.
    p.diffuseColor = s.base * s.baseColor;
    // Standard Surface §Metal: metalness blends to a conductor with F0 = base * base_color.
    p.metallic = s.metalness;
    // Standard Surface §Specular: one GGX roughness for specular, metal and transmission.
    p.roughness = s.specularRoughness;
    // Standard Surface §Transmission: specular_IOR is the refractive index too.
    p.ior = s.specularIor;
    // Standard Surface §Specular: F0 = specular * ((ior-1)/(ior+1))^2; Disney specular = F0/0.08.
    p.specular = s.specular * disneySpecularPerWeight(s);
    // Disney specularTint tints towards the base colour, not a free colour: left at 0.
    p.specularTint = 0.0f;
    // Standard Surface §Specular: specular_anisotropy in [0,1] like Disney anisotropic.
    p.anisotropic = s.specularAnisotropy;
    // Standard Surface §Transmission: transmission weight -> Burley 2015 specTrans.
    p.specTrans = s.transmission;
    // Standard Surface §Subsurface: subsurface weight -> Disney subsurface (Hanrahan-Krueger).
    p.subsurface = s.subsurface;
    // Standard Surface §Sheen: sheen * luminance(sheen_color); white sheen (no base tint).
    p.sheen = s.sheen * disneySheenPerWeight(s);
    p.sheenTint = 0.0f;
    // Standard Surface §Coat: coat weight -> Disney clearcoat (both IOR 1.5 GGX layers).
    p.clearcoat = s.coat;
    // Standard Surface §Coat: a GGX coat of alpha = coat_roughness^2, which is how
    // mapPreviewSurface() reads clearcoatRoughness (MaterialParams::clearcoatAlpha).
    p.clearcoatRoughness = std::isfinite(s.coatRoughness) ? std::clamp(s.coatRoughness, 0.0f, 1.0f) : 0.0f;
    // Standard Surface §Emission: emitted radiance = emission * emission_color.
    p.emissiveColor = s.emission * s.emissionColor;
    // Standard Surface §Opacity: a colour; the principled model has one presence value (mean).
    p.opacity = (s.opacity.x + s.opacity.y + s.opacity.z) / 3.0f;
    p.opacityMode = OpacityMode::Presence;
    // Standard Surface §Thin Walled: no refraction of the path through the surface.
    p.thin = s.thinWalled;
    return p;
}

}  // namespace principled::shading
