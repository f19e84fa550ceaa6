// SPDX-License-Identifier: Apache-2.0
// Primvar descriptors: the name, interpolation and role of a primitive variable.
#pragma once

#include "delegate/hd/token.h"

namespace principled::hd {

/// How many values a primvar has (UsdGeomPrimvar interpolation).
enum class Interpolation { Constant, Uniform, Varying, Vertex, FaceVarying, Instance };

struct PrimvarDescriptor {
    Token name;
    Interpolation interpolation = Interpolation::Constant;
    Token role;          ///< point | normal | vector | color | textureCoordinate | (empty)
    bool indexed = false;
};

}  // namespace principled::hd
