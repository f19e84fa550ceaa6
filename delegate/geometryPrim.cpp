// SPDX-License-Identifier: Apache-2.0
#include "delegate/geometryPrim.h"

#include <cmath>
#include <string>

#include "delegate/hd/sceneDelegate.h"
#include "delegate/transformCheck.h"

namespace principled::embree {

using namespace hd;

void GeometryPrim::finalize(RenderParam* param) {
    auto* p = static_cast<EmbreeRenderParam*>(param);
    if (_registered) p->remove(static_cast<GeometrySource*>(this));
    _registered = false;
    if (_instance.valid() || !_instances.geomIds().empty()) p->markSceneDirty();
    _instances.release();
    _instance.release();
}

void GeometryPrim::sync(SceneDelegate* delegate, RenderParam* renderParam, DirtyBits* bits) {
    auto* param = static_cast<EmbreeRenderParam*>(renderParam);
    if (!_registered) {
        param->add(static_cast<GeometrySource*>(this));
        _registered = true;
    }
    if (*bits & RprimDirty::Instancer) _instancer = delegate->getInstancerId(id());
    // A prototype (only its instances draw) and a prim with an unusable transform keep their
    // own instance disabled.
    if (*bits & RprimDirty::Transform) {
        glm::mat4 m(delegate->getTransform(id()));
        // Rays are moved into object space by the inverse (delegate/transformCheck.h).
        const char* why = unusableTransform(m);
        const bool usable = why == nullptr;
        if (!usable && !_badTransform)
            param->warn(id(), std::string("transform is ") + why + "; prim not rendered");
        _badTransform = !usable;
        if (!usable) m = glm::mat4(1.0f);
        _record.objectToWorld = m;
        _record.worldToObject = glm::inverse(m);
        _record.normalToWorld = glm::transpose(glm::inverse(glm::mat3(m)));
        _instance.setTransform(m);
        param->transformUpdates++;
        param->geometryChanged(this);
    }
    const bool drawnAlone = _instancer.empty() && !_badTransform;
    if (*bits & (RprimDirty::Visibility | RprimDirty::Transform)) {
        _visible = delegate->getVisible(id());
        _instance.setEnabled(_visible && drawnAlone);
        param->geometryChanged(this);
    }
    bool rebuilt = false;
    if (*bits & geometryBits()) {
        if (RTCGeometry geom = rebuildGeometry(delegate, param)) {
            _instance.setGeometry(param->device(), param->scene(), geom, &_record);
            _instance.setTransform(_record.objectToWorld);
            if (!_visible || !drawnAlone) _instance.setEnabled(false);
            param->blasBuilds++;
        } else {
            _instance.release();
        }
        rebuilt = true;
        param->geometryChanged(this);
        // Per-triangle GeomSubset materials follow the new triangles.
        if (!_subsets.empty()) param->bindingChanged(this);
    }
    if (*bits & RprimDirty::DoubleSided) _record.doubleSided = delegate->getDoubleSided(id());
    if (*bits & RprimDirty::MaterialId) {
        _materialId = delegate->getMaterialId(id());
        _subsets = delegate->getMaterialSubsets(id());
        _categories = delegate->getCategories(id());  // light linking changes come this way too
        param->bindingChanged(this);
    }
    constexpr DirtyBits kInstanceBits = RprimDirty::Transform | RprimDirty::Visibility |
                                        RprimDirty::Instancer | RprimDirty::InstanceIndex;
    if (!drawnAlone && (rebuilt || (*bits & kInstanceBits))) syncInstances(delegate, param);
    else if (drawnAlone && !_instances.geomIds().empty()) _instances.release();
    _record.primId = primId();
    *bits = RprimDirty::Clean;
}

void GeometryPrim::syncInstances(SceneDelegate* delegate, EmbreeRenderParam* param) {
    std::vector<InstanceRecord> records;
    if (_visible && _instance.blas()) {
        std::vector<std::string> warnings;
        records = computeInstances(delegate, _instancer, id(), _record.objectToWorld, &warnings,
                                   &param->instancerPrimvars());
        for (const auto& w : warnings) param->warn(_instancer, w);
    }
    _instances.rebuild(param->device(), param->scene(), _instance.blas(), &_record,
                       std::move(records));
    param->transformUpdates++;
    param->geometryChanged(this);
}

void GeometryPrim::bindMaterials(const std::unordered_map<Path, int>& materialIndex) {
    auto find = [&](const Path& p) {
        auto it = materialIndex.find(p);
        return it == materialIndex.end() ? -1 : it->second;
    };
    _record.materialIndex = find(_materialId);
    _record.triangleMaterial.clear();
    if (_subsets.empty() || _record.triangleFace.empty()) return;
    // Face -> material through the subsets (the first subset naming a face wins; USD requires
    // a materialBind family to be a partition), then per triangle through triangleFace.
    int faces = 0;
    for (int f : _record.triangleFace) faces = std::max(faces, f + 1);
    std::vector<int> faceMaterial(size_t(faces), -2);
    for (const auto& [material, indices] : _subsets) {
        int m = find(material);
        for (int f : indices)
            if (f >= 0 && f < faces && faceMaterial[size_t(f)] == -2) faceMaterial[size_t(f)] = m;
    }
    _record.triangleMaterial.resize(_record.triangleFace.size());
    for (size_t t = 0; t < _record.triangleFace.size(); ++t) {
        int f = _record.triangleFace[t];
        int m = (f >= 0 && f < faces) ? faceMaterial[size_t(f)] : -2;
        _record.triangleMaterial[t] = m == -2 ? _record.materialIndex : m;
    }
}

}  // namespace principled::embree
