// SPDX-License-Identifier: Apache-2.0
// Points: the Embree rprim for UsdGeomPoints, each point an exact sphere of diameter
// widths[i] (Embree's sphere point primitive).
#pragma once

#include "delegate/geometryPrim.h"

namespace principled::embree {

class Points : public GeometryPrim {
public:
    using GeometryPrim::GeometryPrim;

protected:
    hd::DirtyBits geometryBits() const override;
    RTCGeometry rebuildGeometry(hd::SceneDelegate* delegate, EmbreeRenderParam* param) override;
};

}  // namespace principled::embree
