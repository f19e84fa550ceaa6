// SPDX-License-Identifier: Apache-2.0
// primitivePrimvars: the primvars of a prim drawn as Embree primitives that are neither
// triangles nor implicit shapes (points, curve segments): one value per primitive.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "delegate/hd/path.h"
#include "delegate/hd/primvar.h"
#include "delegate/sceneData.h"

namespace principled::hd {
class SceneDelegate;
}

namespace principled::embree {

/// Which authored value (of `valueCount`, for interpolation `interp`) primitive `primitive`
/// takes; a value >= valueCount means the primvar does not fit the prim and is dropped.
using PrimitiveSource = std::function<size_t(hd::Interpolation interp, size_t primitive, size_t valueCount)>;

/// Every float primvar (1-4 components) except points, normals and widths: constant ones
/// stay constant, the others become perPrimitive channels through `source`. Primvars whose
/// value count does not fit are dropped and named in *dropped.
std::vector<PrimvarChannel> primitivePrimvars(const hd::SceneDelegate* delegate, const hd::Path& id,
                                              size_t primitiveCount, const PrimitiveSource& source,
                                              std::vector<hd::Token>* dropped);

}  // namespace principled::embree
