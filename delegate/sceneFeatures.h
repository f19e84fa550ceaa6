// SPDX-License-Identifier: Apache-2.0
// What a committed scene asks of the renderer ("no more than a scene needs", issue 7): which
// BSDF lobes its materials use, which lights, geometry kinds and shading features are present,
// and which work the renderer skips because of it. Reported in the delegate's statistics
// (`principled render --stats`, RenderSession::stats(), the C ABI and Python) and printed by
// `principled render` after a render.
#pragma once

#include <array>
#include <map>
#include <string>

#include "bsdf/types.h"
#include "delegate/sceneData.h"

namespace principled::embree {

struct SceneFeatures {
    /// Untextured materials whose BSDF has each lobe after pruning (bsdf::Lobe order).
    std::array<int, bsdf::kLobeCount> materialsWithLobe{};
    /// Lobes removed by pruning across untextured materials (what lobePruning = 0 would add).
    int prunedLobes = 0;
    int untexturedMaterials = 0;   ///< BSDF built once per pass, not per hit
    int texturedMaterials = 0;     ///< evaluated per hit (lobes decided per hit)
    int partlyPresentMaterials = 0;  ///< opacity < 1 somewhere: shadow rays evaluate them
    int emissiveMaterials = 0;
    int normalMappedMaterials = 0;  ///< untextured ones with a constant tilted normal are rare
    /// Lights by kind (LightRecord::Kind order: distant, dome, sphere, rect, disk, cylinder, mesh).
    std::array<int, 7> lightsOfKind{};
    int texturedLights = 0;  ///< dome or rect lights with an image
    int shapedLights = 0;    ///< UsdLux ShapingAPI cones
    /// Geometry records by kind (GeometryRecord::Kind order: triangles, sphere, points, curves)
    /// and their triangle count.
    std::array<int, 4> geometryOfKind{};
    size_t triangles = 0;
    /// Skips in force: shadow rays use a plain occlusion query (no material is partly present);
    /// next-event estimation samples every light (few lights) instead of picking one.
    bool plainShadowRays = true;
    bool neeAllLights = false;
};

SceneFeatures describeScene(const SceneSnapshot& scene, const bsdf::Options& options);

/// As statistics: "scene.lobe.diffuse" = materials with the lobe, "scene.light.rect" = count...
std::map<std::string, double> sceneFeatureStats(const SceneFeatures& f);

/// One line for a person: "lobes: diffuse 5, specular 3 (1 pruned); lights: mesh 1; ...".
std::string describeFeatures(const SceneFeatures& f);

}  // namespace principled::embree
