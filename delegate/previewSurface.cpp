// SPDX-License-Identifier: Apache-2.0
#include "delegate/previewSurface.h"

#include <algorithm>
#include <cmath>

namespace principled::embree {

using namespace hd;

namespace {

float clamp01(float v) { return std::isfinite(v) ? std::clamp(v, 0.0f, 1.0f) : 0.0f; }
glm::vec3 clamp01(const glm::vec3& v) { return {clamp01(v.x), clamp01(v.y), clamp01(v.z)}; }

}  // namespace

float specularFromIor(float ior) {
    if (!std::isfinite(ior) || ior <= 0.0f) return 0.5f;
    float r = (ior - 1.0f) / (ior + 1.0f);
    return clamp01(r * r / 0.08f);
}

MaterialRecord mapPreviewSurface(const MaterialNetwork& network, std::vector<std::string>* notes) {
    MaterialRecord rec;
    bsdf::MaterialParams& p = rec.params;
    // UsdPreviewSurface fallbacks (spec 2.5): diffuse 0.18, roughness 0.5, ior 1.5.
    p.baseColor = glm::vec3(0.18f);
    p.roughness = 0.5f;
    p.metallic = 0.0f;
    p.specular = specularFromIor(1.5f);
    p.clearcoatGloss = 1.0f - 0.01f;
    const MaterialNode* surface = network.node(network.surfaceTerminal);
    if (!surface) {
        notes->push_back("no surface shader; using UsdPreviewSurface defaults");
        return rec;
    }
    if (surface->identifier != Token("UsdPreviewSurface")) {
        notes->push_back("surface shader '" + surface->identifier.str() +
                         "' is not UsdPreviewSurface; using its defaults");
        return rec;
    }
    auto input = [&](const char* name) -> const Value* {
        auto c = surface->inputConnections.find(Token(name));
        if (c != surface->inputConnections.end() && !c->second.empty())
            notes->push_back(std::string("input '") + name +
                             "' is connected to a texture; textures are not evaluated yet, "
                             "using the authored or fallback value");
        auto it = surface->parameters.find(Token(name));
        return it == surface->parameters.end() ? nullptr : &it->second;
    };
    auto scalar = [&](const char* name, float* out) {
        if (const Value* v = input(name))
            if (auto f = getFloat(*v); f && std::isfinite(*f)) *out = *f;
    };
    auto color = [&](const char* name, glm::vec3* out) {
        if (const Value* v = input(name))
            if (auto c = getVec3(*v)) *out = *c;
    };
    color("diffuseColor", &p.baseColor);
    p.baseColor = clamp01(p.baseColor);
    scalar("metallic", &p.metallic);
    scalar("roughness", &p.roughness);
    float ior = 1.5f;
    scalar("ior", &ior);
    if (std::isfinite(ior) && ior > 0.0f) p.ior = ior;
    p.specular = specularFromIor(ior);
    scalar("clearcoat", &p.clearcoat);
    float ccRough = 0.01f;
    scalar("clearcoatRoughness", &ccRough);
    p.clearcoatGloss = 1.0f - clamp01(ccRough);
    color("emissiveColor", &rec.emission);
    scalar("opacity", &rec.opacity);
    float useSpecular = 0.0f;
    scalar("useSpecularWorkflow", &useSpecular);
    if (useSpecular > 0.5f) {
        // Specular workflow: F0 = specularColor with F90 = 1 and no metal. Approximated until
        // the BSDF takes an explicit F0: strength from the brightest channel, tint from chroma.
        glm::vec3 sc(0.0f);
        color("specularColor", &sc);
        sc = clamp01(sc);
        float m = std::max({sc.x, sc.y, sc.z});
        p.metallic = 0.0f;
        p.specular = clamp01(m / 0.08f);
        p.specularTint = m > 0.0f && (sc.x != sc.y || sc.y != sc.z) ? 1.0f : 0.0f;
    }
    // Disney parameters UsdPreviewSurface cannot express, read from extra inputs named as in
    // MaterialX's Disney BSDF nodes, so a scene can author the whole model.
    scalar("subsurface", &p.subsurface);
    scalar("specular", &p.specular);
    scalar("specularTint", &p.specularTint);
    scalar("anisotropic", &p.anisotropic);
    scalar("sheen", &p.sheen);
    scalar("sheenTint", &p.sheenTint);
    scalar("clearcoatGloss", &p.clearcoatGloss);
    scalar("specTrans", &p.specTrans);
    p.metallic = clamp01(p.metallic);
    p.roughness = clamp01(p.roughness);
    p.subsurface = clamp01(p.subsurface);
    p.specular = clamp01(p.specular);
    p.specularTint = clamp01(p.specularTint);
    p.anisotropic = clamp01(p.anisotropic);
    p.sheen = clamp01(p.sheen);
    p.sheenTint = clamp01(p.sheenTint);
    p.clearcoat = clamp01(p.clearcoat);
    p.clearcoatGloss = clamp01(p.clearcoatGloss);
    p.specTrans = clamp01(p.specTrans);
    rec.opacity = clamp01(rec.opacity);
    for (float* c : {&rec.emission.x, &rec.emission.y, &rec.emission.z})
        if (!std::isfinite(*c) || *c < 0.0f) *c = 0.0f;
    return rec;
}

}  // namespace principled::embree
