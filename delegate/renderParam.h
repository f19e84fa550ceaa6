// SPDX-License-Identifier: Apache-2.0
// EmbreeRenderParam: the delegate state prims reach during sync: the Embree device and
// top-level scene, the registries of shaded prims and lights, and the edit counters.
#pragma once

#include <atomic>
#include <mutex>
#include <set>
#include <string>
#include <utility>
#include <vector>
#include <unordered_map>

#include <embree3/rtcore.h>

#include "delegate/hd/path.h"
#include "delegate/hd/prim.h"
#include "delegate/instancerPrimvars.h"
#include "delegate/sceneData.h"
#include "delegate/shading/textureCache.h"

namespace principled::embree {

/// Implemented by rprims: their geometry record, their Embree instance in the top-level scene
/// and the material bindings resolved at commit time.
class GeometrySource {
public:
    virtual ~GeometrySource() = default;
    /// Embree geomID of this prim's instance in the top-level scene (RTC_INVALID_GEOMETRY_ID if none).
    virtual unsigned instanceId() const = 0;
    virtual GeometryRecord* record() = 0;
    /// Resolves material paths to indices into the material table.
    virtual void bindMaterials(const std::unordered_map<hd::Path, int>& materialIndex) = 0;
    /// PointInstancer prototypes: the geomIDs of the top-level instances drawing record() and
    /// their placements (parallel arrays); nullptr for a prim drawn on its own.
    virtual const std::vector<unsigned>* instanceGeomIds() const { return nullptr; }
    virtual const std::vector<InstanceRecord>* instanceRecords() const { return nullptr; }
    /// The instancer drawing this prim (empty: drawn on its own).
    virtual hd::Path instancerId() const { return hd::Path(); }
    /// Light-linking categories the prim belongs to (SceneDelegate::getCategories).
    virtual const std::vector<hd::Token>& categories() const {
        static const std::vector<hd::Token> kNone;
        return kNone;
    }
};

/// Implemented by light sprims.
class LightSource {
public:
    virtual ~LightSource() = default;
    virtual const hd::Path& lightId() const = 0;
    virtual const LightRecord& record() const = 0;
    virtual bool enabled() const = 0;
};

/// Implemented by material sprims.
class MaterialSource {
public:
    virtual ~MaterialSource() = default;
    virtual const hd::Path& materialId() const = 0;
    virtual const MaterialRecord& record() const = 0;
};

class EmbreeRenderParam : public hd::RenderParam {
public:
    EmbreeRenderParam(RTCDevice device, RTCScene scene) : _device(device), _scene(scene) {}

    RTCDevice device() const { return _device; }
    /// The top-level scene; rtcAttachGeometry on it is thread-safe (Embree 3.13 docs).
    RTCScene scene() const { return _scene; }

    /// Something in the top-level scene changed: commit it before the next pass.
    void markSceneDirty() { _sceneDirty = true; }
    bool takeSceneDirty() { return _sceneDirty.exchange(false); }
    /// Anything may have changed (a setting such as defaultLighting): rebuild every table.
    void markTablesDirty() { _tablesDirty = true; }
    bool takeTablesDirty() { return _tablesDirty.exchange(false); }

    // Finer changes, so commitResources() redoes only what they affect (issue 7, edit latency).
    /// A registered material's record changed in place (its path, hence its index, did not).
    void materialChanged(MaterialSource* m) { std::lock_guard<std::mutex> l(_mutex); _changedMaterials.insert(m); }
    /// A light was added, removed or changed: rebuild the light table (not the materials).
    void markLightsDirty() { _lightsDirty = true; }
    /// A prim's material binding (or its GeomSubsets' triangles) changed: rebind that prim.
    void bindingChanged(GeometrySource* g) { std::lock_guard<std::mutex> l(_mutex); _changedBindings.insert(g); }
    /// A prim's placement, visibility or geometry changed (the top level is re-committed).
    void geometryChanged(GeometrySource* g) {
        std::lock_guard<std::mutex> l(_mutex);
        _changedGeometry.insert(g);
        _sceneDirty = true;
    }

    /// What changed since the last commit (taken by commitResources()).
    struct Changes {
        bool scene = false, all = false, lights = false, materialSet = false, geometrySet = false;
        std::set<MaterialSource*> materials;
        std::set<GeometrySource*> bindings, geometry;
        bool any() const {
            return scene || all || lights || materialSet || geometrySet || !materials.empty() ||
                   !bindings.empty() || !geometry.empty();
        }
    };
    Changes takeChanges() {
        std::lock_guard<std::mutex> l(_mutex);
        Changes c;
        c.scene = _sceneDirty.exchange(false);
        c.all = _tablesDirty.exchange(false);
        c.lights = _lightsDirty.exchange(false);
        c.materialSet = std::exchange(_materialSetChanged, false);
        c.geometrySet = std::exchange(_geometrySetChanged, false);
        c.materials = std::exchange(_changedMaterials, {});
        c.bindings = std::exchange(_changedBindings, {});
        c.geometry = std::exchange(_changedGeometry, {});
        return c;
    }

    void add(GeometrySource* p) {
        std::lock_guard<std::mutex> l(_mutex);
        _geometry.insert(p);
        _geometrySetChanged = true;
    }
    void remove(GeometrySource* p) {
        std::lock_guard<std::mutex> l(_mutex);
        _geometry.erase(p);
        _changedBindings.erase(p);
        _changedGeometry.erase(p);
        _geometrySetChanged = true;
    }
    void add(LightSource* p) { std::lock_guard<std::mutex> l(_mutex); _lights.insert(p); _lightsDirty = true; }
    void remove(LightSource* p) { std::lock_guard<std::mutex> l(_mutex); _lights.erase(p); _lightsDirty = true; }
    void add(MaterialSource* p) {
        std::lock_guard<std::mutex> l(_mutex);
        _materials.insert(p);
        _materialSetChanged = true;
    }
    void remove(MaterialSource* p) {
        std::lock_guard<std::mutex> l(_mutex);
        _materials.erase(p);
        _changedMaterials.erase(p);
        _materialSetChanged = true;
    }

    const std::set<GeometrySource*>& geometry() const { return _geometry; }
    const std::set<LightSource*>& lights() const { return _lights; }
    const std::set<MaterialSource*>& materials() const { return _materials; }

    /// How meshes pick their subdivision level: a fixed level (>= 0) or adaptive (-1) from the
    /// dicing view (set by the render pass's camera before sync).
    struct Dicing {
        int level = -1;
        bool haveView = false;
        glm::vec3 cameraPosition{0.0f};
        float verticalFov = 0.8f;
        int imageHeight = 720;
        float targetEdgePixels = 1.5f;
        /// How far (pixels) the refined surface may lie from its limit; 0: edge length only.
        float tolerancePixels = 0.1f;
        int maxLevel = 6;
        int fallbackLevel = 2;  ///< adaptive without a view
    };
    Dicing dicing() const {
        std::lock_guard<std::mutex> l(_mutex);
        return _dicing;
    }
    void setDicing(const Dicing& d) {
        std::lock_guard<std::mutex> l(_mutex);
        _dicing = d;
    }
    /// The texture cache materials compile against (owned by the delegate).
    shading::TextureCache* textureCache() const { return _textures; }
    void setTextureCache(shading::TextureCache* t) { _textures = t; }

    /// A subdivision mesh went away: the scene-wide budget is fitted again at the next sync
    /// (EmbreeRenderDelegate::prepareRprimSync), from the plans the others were built with.
    void requestSubdivisionRefit() { _subdivisionRefit = true; }
    bool takeSubdivisionRefit() { return _subdivisionRefit.exchange(false); }

    /// PointInstancers' per-instance primvars, read once for all prototypes of an instancer.
    InstancerPrimvarCache& instancerPrimvars() { return _instancerPrimvars; }

    // Counters for render stats and for tests of incremental updates.
    std::atomic<long> blasBuilds{0};
    std::atomic<long> meshesRebuilt{0};
    std::atomic<long> transformUpdates{0};

    /// A problem with user data found during sync (bad topology, unsupported value): the prim
    /// is skipped or simplified and the message kept for the host to show.
    void warn(const hd::Path& id, const std::string& message) override {
        std::lock_guard<std::mutex> l(_mutex);
        _warnings.push_back(id.str() + ": " + message);
    }
    std::vector<std::string> takeWarnings() {
        std::lock_guard<std::mutex> l(_mutex);
        return std::exchange(_warnings, {});
    }

private:
    InstancerPrimvarCache _instancerPrimvars;
    RTCDevice _device;
    RTCScene _scene;
    std::atomic<bool> _sceneDirty{true};
    std::atomic<bool> _tablesDirty{true};
    std::atomic<bool> _lightsDirty{false};
    std::atomic<bool> _subdivisionRefit{false};
    bool _materialSetChanged = false, _geometrySetChanged = false;
    std::set<MaterialSource*> _changedMaterials;
    std::set<GeometrySource*> _changedBindings, _changedGeometry;
    mutable std::mutex _mutex;
    Dicing _dicing;
    shading::TextureCache* _textures = nullptr;
    std::set<GeometrySource*> _geometry;
    std::set<LightSource*> _lights;
    std::set<MaterialSource*> _materials;
    std::vector<std::string> _warnings;
};

}  // namespace principled::embree
