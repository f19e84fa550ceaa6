// SPDX-License-Identifier: Apache-2.0
// UsdGeomXformable: a prim's local transform from its xformOpOrder.
#pragma once

#include <string>

#include <glm/glm.hpp>

namespace principled::usd {
class Prim;
}

namespace principled::adapter {

struct LocalTransform {
    glm::dmat4 matrix{1.0};      ///< column-vector convention: p_parent = matrix * p_local
    bool resetsXformStack = false;
    bool timeVarying = false;    ///< some op has time samples
};

/// Evaluates xformOpOrder at `time` (NaN = default). Ops: translate, scale, rotateX/Y/Z,
/// rotateXYZ/XZY/YXZ/YZX/ZXY/ZYX (degrees), orient (quaternion), transform (matrix4d), each
/// with an optional ":suffix" and the "!invert!" prefix; "!resetXformStack!" first. Problems
/// (missing op attribute, wrong value shape, singular inverse) go to *warning and the op is
/// skipped. Prims that are not UsdGeomXformable (untyped, Scope, Material, ...) have the
/// identity, with a warning when they author xformOpOrder.
LocalTransform computeLocalTransform(const usd::Prim& prim, double time, std::string* warning);

}  // namespace principled::adapter
