// SPDX-License-Identifier: Apache-2.0
// Sphere: the Embree rprim for UsdGeomSphere, ray traced as an exact implicit sphere (Embree's
// sphere primitive), never tessellated.
#pragma once

#include "delegate/geometryPrim.h"

namespace principled::embree {

class Sphere : public GeometryPrim {
public:
    using GeometryPrim::GeometryPrim;

protected:
    hd::DirtyBits geometryBits() const override;
    RTCGeometry rebuildGeometry(hd::SceneDelegate* delegate, EmbreeRenderParam* param) override;
};

}  // namespace principled::embree
