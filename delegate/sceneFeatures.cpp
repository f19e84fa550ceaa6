// SPDX-License-Identifier: Apache-2.0
#include "delegate/sceneFeatures.h"

#include <bit>
#include <set>
#include <sstream>

#include "bsdf/bsdf.h"

namespace principled::embree {
namespace {

constexpr const char* kLobeNames[bsdf::kLobeCount] = {"diffuse", "sheen", "specular", "clearcoat", "transmission"};
constexpr const char* kLightNames[7] = {"distant", "dome", "sphere", "rect", "disk", "cylinder", "mesh"};
constexpr const char* kGeometryNames[4] = {"mesh", "sphere", "points", "curves"};

}  // namespace

SceneFeatures describeScene(const SceneSnapshot& scene, const bsdf::Options& options) {
    SceneFeatures f;
    bsdf::Options unpruned = options;
    unpruned.pruneLobes = false;
    for (const MaterialRecord& m : scene.materials) {
        f.partlyPresentMaterials += m.mayBePartlyPresent;
        if (m.program) {
            ++f.texturedMaterials;
            continue;
        }
        ++f.untexturedMaterials;
        f.emissiveMaterials += m.constant.emission != glm::vec3(0.0f);
        f.normalMappedMaterials += m.constant.hasNormalMap;
        const bsdf::LobeMask lobes = bsdf::Bsdf(m.constant.params, options).lobes();
        const bsdf::LobeMask all = bsdf::Bsdf(m.constant.params, unpruned).lobes();
        for (int k = 0; k < bsdf::kLobeCount; ++k) f.materialsWithLobe[k] += (lobes >> k) & 1u;
        f.prunedLobes += std::popcount(all & ~lobes);
    }
    for (const LightRecord& l : scene.lights) {
        ++f.lightsOfKind[static_cast<int>(l.kind)];
        f.texturedLights += (l.environment != nullptr) || (l.rectTexture != nullptr);
        f.shapedLights += l.shaping.enabled;
    }
    std::set<const GeometryRecord*> seen;
    for (const GeometryRecord* g : scene.geometryByInstance) {
        if (!g || !seen.insert(g).second) continue;
        ++f.geometryOfKind[static_cast<int>(g->kind)];
        if (g->kind == GeometryRecord::Kind::Triangles) f.triangles += g->triangles.size();
    }
    f.plainShadowRays = !scene.anyPartlyPresent;
    f.neeAllLights = scene.neeAllLights;
    return f;
}

std::map<std::string, double> sceneFeatureStats(const SceneFeatures& f) {
    std::map<std::string, double> s;
    for (int k = 0; k < bsdf::kLobeCount; ++k) s[std::string("scene.lobe.") + kLobeNames[k]] = f.materialsWithLobe[k];
    s["scene.lobe.pruned"] = f.prunedLobes;
    s["scene.material.untextured"] = f.untexturedMaterials;
    s["scene.material.textured"] = f.texturedMaterials;
    s["scene.material.partlyPresent"] = f.partlyPresentMaterials;
    s["scene.material.emissive"] = f.emissiveMaterials;
    s["scene.material.normalMapped"] = f.normalMappedMaterials;
    for (int k = 0; k < 7; ++k) s[std::string("scene.light.") + kLightNames[k]] = f.lightsOfKind[k];
    s["scene.light.textured"] = f.texturedLights;
    s["scene.light.shaped"] = f.shapedLights;
    for (int k = 0; k < 4; ++k) s[std::string("scene.geometry.") + kGeometryNames[k]] = f.geometryOfKind[k];
    s["scene.geometry.triangles"] = double(f.triangles);
    s["scene.skip.plainShadowRays"] = f.plainShadowRays;
    s["scene.neeAllLights"] = f.neeAllLights;
    return s;
}

std::string describeFeatures(const SceneFeatures& f) {
    std::ostringstream o;
    auto list = [&](const char* title, const auto& counts, const char* const* names, size_t n) {
        o << title << ":";
        bool any = false;
        for (size_t k = 0; k < n; ++k)
            if (counts[k] > 0) o << (any ? ", " : " ") << names[k] << " " << counts[k], any = true;
        if (!any) o << " none";
    };
    list("lobes (untextured materials)", f.materialsWithLobe, kLobeNames, bsdf::kLobeCount);
    if (f.prunedLobes) o << " (" << f.prunedLobes << " pruned)";
    o << "; textured materials " << f.texturedMaterials << " (per hit), untextured " << f.untexturedMaterials
      << " (one BSDF per pass); ";
    list("lights", f.lightsOfKind, kLightNames, 7);
    o << "; ";
    list("geometry", f.geometryOfKind, kGeometryNames, 4);
    o << " (" << f.triangles << " triangles); shadow rays: "
      << (f.plainShadowRays ? "plain occlusion (no partly present material)" : "opacity-aware")
      << "; next-event estimation: " << (f.neeAllLights ? "every light" : "one light picked by power");
    return o.str();
}

}  // namespace principled::embree
