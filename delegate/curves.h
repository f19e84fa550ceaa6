// SPDX-License-Identifier: Apache-2.0
// BasisCurves: the Embree rprim for UsdGeomBasisCurves, ray traced as round tubes of
// diameter `widths` along linear, Bezier, B-spline or Catmull-Rom curves (Embree's curve
// primitives; nonperiodic, periodic and pinned wraps).
#pragma once

#include "delegate/geometryPrim.h"

namespace principled::embree {

class BasisCurves : public GeometryPrim {
public:
    using GeometryPrim::GeometryPrim;

protected:
    hd::DirtyBits geometryBits() const override;
    RTCGeometry rebuildGeometry(hd::SceneDelegate* delegate, EmbreeRenderParam* param) override;
};

}  // namespace principled::embree
