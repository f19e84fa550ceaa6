// SPDX-License-Identifier: Apache-2.0
// EmbreeRenderDelegate: the Embree path-tracing render delegate. Creates the prims, commits
// the two-level BVH and the material/light tables once per sync, and holds the settings.
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <vector>

#include "delegate/embreeDevice.h"
#include "delegate/hd/renderDelegate.h"
#include "delegate/integrator.h"
#include "delegate/renderParam.h"
#include "delegate/sceneData.h"

namespace principled::embree {

class EmbreeRenderDelegate : public hd::RenderDelegate {
public:
    EmbreeRenderDelegate();
    ~EmbreeRenderDelegate() override;

    const std::vector<hd::Token>& supportedRprimTypes() const override;
    const std::vector<hd::Token>& supportedSprimTypes() const override;
    const std::vector<hd::Token>& supportedBprimTypes() const override;

    std::unique_ptr<hd::Rprim> createRprim(const hd::Token& typeId, const hd::Path& id) override;
    std::unique_ptr<hd::Sprim> createSprim(const hd::Token& typeId, const hd::Path& id) override;
    std::unique_ptr<hd::Bprim> createBprim(const hd::Token& typeId, const hd::Path& id) override;
    std::unique_ptr<hd::RenderPass> createRenderPass(hd::RenderIndex* index) override;

    hd::RenderParam* renderParam() override { return _param.get(); }
    /// The scene-wide subdivision budget (render setting subdivisionBudget): plans the levels
    /// of the meshes this sync rebuilds (delegate/subdiv/levelBudget.h).
    void prepareRprimSync(const std::vector<hd::Rprim*>& prims, const std::vector<hd::SceneDelegate*>& delegates,
                          const std::vector<hd::DirtyBits>& bits,
                          std::vector<std::pair<hd::Rprim*, hd::DirtyBits>>* alsoSync) override;
    void commitResources(hd::ChangeTracker* tracker) override;

    hd::AovDescriptor defaultAovDescriptor(const hd::Token& aovName) const override;

    std::vector<hd::RenderSettingDescriptor> renderSettingDescriptors() const override;
    void setRenderSetting(const hd::Token& key, const hd::Value& value) override;
    hd::Value renderSetting(const hd::Token& key) const override;
    unsigned renderSettingsVersion() const override { return _settingsVersion.load(); }
    /// Bumped by every commit that changed what is rendered (the render pass restarts on it,
    /// not on every edit the change tracker saw).
    unsigned contentVersion() const { return _contentVersion.load(); }
    /// What reloadTextures() re-reads: nothing (!any), every file (all), or `paths`.
    struct TextureReload {
        bool any = false;
        bool all = false;
        std::vector<std::string> paths;
    };
    /// Texture files edited on disk: onlyChanged re-reads the files (material textures, and the
    /// lights' through TextureCache::watch) that changed (TextureCache::reloadChanged), else
    /// every one. The render restarts when anything is re-read. The caller re-syncs the
    /// materials and the lights whose images changed (RenderSession::reloadTextures): lights
    /// read their images at sync, materials take their textures' descriptions (channels,
    /// colour tags) at sync. Call between render passes.
    TextureReload reloadTextures(bool onlyChanged);

    std::map<std::string, double> renderStats() const override;
    /// What the committed scene uses and what the renderer skips for it, in one line
    /// (delegate/sceneFeatures.h); the same figures are in renderStats() as "scene.*".
    std::string sceneSummary() const;

    /// What the committed scene holds, for `principled info` and hosts' scene statistics.
    struct Summary {
        size_t meshes = 0, spheres = 0, triangles = 0, instances = 0, instancers = 0;
        size_t points = 0, curvePrims = 0, curveSegments = 0;
        std::map<std::string, size_t> lightsByKind;
        /// Material path -> the lobes its (constant) parameters use, e.g. "diffuse+specular";
        /// "textured" when they vary over the surface.
        std::map<std::string, std::string> materialLobes;
    };
    Summary summary() const;

    /// Problems found in user data since the last call (one line each, prim path first).
    std::vector<std::string> takeWarnings() { return _param->takeWarnings(); }
    void warn(const hd::Path& id, const std::string& message) { _param->warn(id, message); }

    /// The view adaptive subdivision measures projected size from (the render camera):
    /// world position, vertical field of view (radians) and image height. Applies to meshes
    /// synced afterwards.
    void setDicingView(const glm::vec3& cameraPosition, float verticalFov, int imageHeight);

    // Used by the render pass.
    const SceneSnapshot& snapshot() const { return _snapshot; }
    IntegratorSettings integratorSettings() const;
    int samplesPerPixel() const;
    float noiseThreshold() const { return std::max(0.0f, floatSetting("noiseThreshold", 0.0f)); }
    int minSamples() const { return intSetting("minSamples", 0); }
    int seed() const;
    void addPassStats(long rays, long samples, long invalidSamples, double seconds);
    /// Caustic light tracing as the last pass found it: casters, caustic lights, and the light
    /// paths it traced (added up); casters -1: turned off (settings caustics, clampIndirect, nee).
    void setCausticStats(long casters, long lights, long paths);

private:
    int intSetting(const char* key, int fallback) const;
    float floatSetting(const char* key, float fallback) const;

    void updateDicing();
    void buildLightDistribution();
    void buildMeshLights();
    /// One mesh light per material in `materials` (the emitting ones of r), r's points placed by
    /// objectToWorld; instance is the placed copy's Embree geomID (or RTC_INVALID_GEOMETRY_ID).
    void addMeshLights(GeometryRecord* r, const std::vector<int>& materials, const glm::mat4& objectToWorld,
                       unsigned instance);
    /// Estimated mean of a textured emission over a mesh light's triangles (for light picking).
    /// *emits: some probe emitted (a texture black everywhere probed does not light the scene).
    glm::vec3 meanEmission(const GeometryRecord& r, const MaterialRecord& m,
                           const std::vector<uint32_t>& triangles, bool* emits) const;
    void computeLightPower();
    float sceneRadius() const;
    /// LightRecord::linkBit of the linked lights and GeometryRecord::lightLinks of every prim.
    void assignLightLinks();
    bool _lightLinksAssigned = false;  ///< some prim may hold link bits (assignLightLinks)
    std::atomic<bool> _subdivisionSettingsChanged{false};  ///< re-plan every mesh at the next sync
    std::string _budgetWarning;  ///< the last fit's warning, given at commit (once per sync)
    bool mayEmit(const GeometryRecord* r) const;
    /// Whether material `materialIndex` of the table may emit (MaterialRecord::mayEmit).
    bool materialMayEmit(int materialIndex) const;
    void addInstancerInstances();

    EmbreeDevice _device;
    shading::TextureCache _textures;
    RTCScene _scene = nullptr;
    std::unique_ptr<EmbreeRenderParam> _param;
    SceneSnapshot _snapshot;
    std::vector<LightRecord> _sceneLights;  ///< the UsdLux lights, sorted by path
    std::shared_ptr<const PortalSet> _portals;  ///< the UsdLux portals, or null
    std::vector<LightRecord> _meshLights;   ///< emissive meshes, by prim id (after _sceneLights)
    /// The mesh lights of one prim, or of one placed copy of an instanced prototype (instance =
    /// its Embree geomID; RTC_INVALID_GEOMETRY_ID for a prim drawn on its own): count lights
    /// from _meshLights[first].
    struct MeshLightGroup {
        GeometryRecord* record;
        unsigned instance;
        int first, count;
    };
    std::vector<MeshLightGroup> _meshLightGroups;
    bool _anyEmitter = false;  ///< some geometry emits (then no default dome is added)
    bool _anyAuthoredLight = false;  ///< the scene has a light, visible or not (no default dome)
    std::unordered_map<hd::Path, int> _materialIndex;  ///< path -> index in _snapshot.materials
    std::vector<float> _lightPower;         ///< per light, without the R^2 of distant/dome
    std::vector<char> _lightPowerScales;    ///< 1: multiply by R^2
    float _lightRadius = -1.0f;
    bool _fullCommit = false;               ///< PRINCIPLED_FULL_COMMIT=1: rebuild all each commit             ///< scene radius of the last light distribution
    std::atomic<unsigned> _contentVersion{1};
    std::atomic<long> _materialTableBuilds{0}, _materialUpdates{0}, _bindings{0}, _lightTableBuilds{0},
        _meshLightBuilds{0}, _lightDistributionBuilds{0}, _instanceTableBuilds{0};
    mutable std::mutex _settingsMutex;
    hd::RenderSettingsMap _settings;
    std::atomic<unsigned> _settingsVersion{1};
    // Stats.
    std::atomic<long> _rays{0}, _samples{0}, _invalidSamples{0}, _topCommits{0};
    std::atomic<long> _causticCasters{-2}, _causticLights{0}, _causticPaths{0};
    std::atomic<double> _renderSeconds{0.0};
    std::atomic<long> _instances{0};  ///< instancer instances in the last commit
};

}  // namespace principled::embree
