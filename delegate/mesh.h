// SPDX-License-Identifier: Apache-2.0
// Mesh: the Embree rprim for UsdGeomMesh. Triangulates the authored polygons (fan) and keeps
// normals per corner; its BVH is instanced into the top-level scene.
#pragma once

#include "delegate/geometryPrim.h"

namespace principled::embree {

class Mesh : public GeometryPrim {
public:
    using GeometryPrim::GeometryPrim;

protected:
    hd::DirtyBits geometryBits() const override;
    RTCGeometry rebuildGeometry(hd::SceneDelegate* delegate, EmbreeRenderParam* param) override;
};

}  // namespace principled::embree
