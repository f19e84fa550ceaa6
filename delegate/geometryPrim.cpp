// SPDX-License-Identifier: Apache-2.0
#include "delegate/geometryPrim.h"

#include "delegate/hd/sceneDelegate.h"

namespace principled::embree {

using namespace hd;

void GeometryPrim::finalize(RenderParam* param) {
    auto* p = static_cast<EmbreeRenderParam*>(param);
    if (_registered) p->remove(static_cast<GeometrySource*>(this));
    _registered = false;
    if (_instance.valid()) p->markSceneDirty();
    _instance.release();
}

void GeometryPrim::sync(SceneDelegate* delegate, RenderParam* renderParam, DirtyBits* bits) {
    auto* param = static_cast<EmbreeRenderParam*>(renderParam);
    if (!_registered) {
        param->add(static_cast<GeometrySource*>(this));
        _registered = true;
    }
    if (*bits & RprimDirty::Transform) {
        glm::mat4 m(delegate->getTransform(id()));
        _record.objectToWorld = m;
        _record.worldToObject = glm::inverse(m);
        _record.normalToWorld = glm::transpose(glm::inverse(glm::mat3(m)));
        _instance.setTransform(m);
        param->transformUpdates++;
        param->markSceneDirty();
    }
    if (*bits & RprimDirty::Visibility) {
        _visible = delegate->getVisible(id());
        _instance.setEnabled(_visible);
        param->markSceneDirty();
    }
    if (*bits & geometryBits()) {
        if (RTCGeometry geom = rebuildGeometry(delegate, param)) {
            _instance.setGeometry(param->device(), param->scene(), geom, &_record);
            _instance.setTransform(_record.objectToWorld);
            if (!_visible) _instance.setEnabled(false);
            param->blasBuilds++;
        } else {
            _instance.release();
        }
        param->markSceneDirty();
    }
    if (*bits & RprimDirty::DoubleSided) _record.doubleSided = delegate->getDoubleSided(id());
    if (*bits & RprimDirty::MaterialId) {
        _materialId = delegate->getMaterialId(id());
        param->markTablesDirty();
    }
    _record.primId = primId();
    *bits = RprimDirty::Clean;
}

void GeometryPrim::bindMaterials(const std::unordered_map<Path, int>& materialIndex) {
    auto it = materialIndex.find(_materialId);
    _record.materialIndex = it == materialIndex.end() ? -1 : it->second;
}

}  // namespace principled::embree
