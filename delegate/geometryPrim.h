// SPDX-License-Identifier: Apache-2.0
// GeometryPrim: what every Embree rprim shares: its geometry record, its instance in the
// top-level scene, and the sync of transform, visibility, sidedness and material binding.
// Subclasses only build their bottom-level geometry.
#pragma once

#include "delegate/embreeInstance.h"
#include "delegate/instancer.h"
#include "delegate/hd/prim.h"
#include "delegate/renderParam.h"

namespace principled::embree {

class GeometryPrim : public hd::Rprim, public GeometrySource {
public:
    using Rprim::Rprim;

    void sync(hd::SceneDelegate* delegate, hd::RenderParam* param, hd::DirtyBits* bits) final;
    void finalize(hd::RenderParam* param) override;

    unsigned instanceId() const override { return _instance.instanceId(); }
    GeometryRecord* record() override { return &_record; }
    void bindMaterials(const std::unordered_map<hd::Path, int>& materialIndex) override;
    const std::vector<unsigned>* instanceGeomIds() const override {
        return _instancer.empty() ? nullptr : &_instances.geomIds();
    }
    hd::Path instancerId() const override { return _instancer; }
    const std::vector<hd::Token>& categories() const override { return _categories; }
    const std::vector<InstanceRecord>* instanceRecords() const override {
        return _instancer.empty() ? nullptr : &_instances.records();
    }

protected:
    /// The dirty bits that make rebuildGeometry() run.
    virtual hd::DirtyBits geometryBits() const = 0;
    /// Rebuilds _record's geometry; returns the new Embree geometry (uncommitted) or nullptr
    /// when the prim cannot be rendered (after param->warn()).
    virtual RTCGeometry rebuildGeometry(hd::SceneDelegate* delegate, EmbreeRenderParam* param) = 0;

    GeometryRecord _record;

private:
    void syncInstances(hd::SceneDelegate* delegate, EmbreeRenderParam* param);

    EmbreeInstance _instance;
    hd::Path _materialId;
    std::vector<std::pair<hd::Path, std::vector<int>>> _subsets;  ///< GeomSubset bindings
    std::vector<hd::Token> _categories;  ///< light-linking categories (read with the binding)
    hd::Path _instancer;      ///< non-empty: a PointInstancer prototype, drawn only by _instances
    InstanceSet _instances;
    bool _registered = false;
    bool _visible = true;
    bool _badTransform = false;
};

}  // namespace principled::embree
