// SPDX-License-Identifier: Apache-2.0
// Primvar helpers shared by rprims: flattening values, expanding any interpolation to
// per-triangle-corner values, smooth normals, and constant display colour.
#pragma once

#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "delegate/hd/path.h"
#include "delegate/hd/primvar.h"
#include "delegate/hd/value.h"

namespace principled::hd {
class SceneDelegate;
}

namespace principled::embree {

/// A float, vec2, vec3 or vec4 array (or scalar) as flat floats; false for other types.
bool flattenFloats(const hd::Value& value, std::vector<float>* out, int* components);

/// The triangle mesh a primvar is expanded onto: triangles (point indices), their corners
/// (face-vertex indices) and authored faces.
struct CornerLayout {
    size_t pointCount = 0;
    size_t faceCount = 0;
    size_t faceVertexCount = 0;
    const std::vector<glm::uvec3>* triangles = nullptr;
    const std::vector<glm::uvec3>* corners = nullptr;
    const std::vector<int>* triangleFace = nullptr;
};

/// Expands flat values (components each, optionally indexed) of the given interpolation to
/// three elements per triangle. Returns false when the element count does not match the
/// interpolation (the primvar is then ignored rather than read out of bounds).
bool expandToCorners(const std::vector<float>& values, int components, const std::vector<int>& indices,
                     hd::Interpolation interp, const CornerLayout& layout, std::vector<float>* out);

/// Authored normals (the "normals" primvar in any interpolation), three per triangle,
/// normalised; empty when none are authored or they do not fit (then *problem, when given,
/// says why: not three components, or the wrong number of values or indices for their
/// interpolation).
std::vector<glm::vec3> authoredCornerNormals(const hd::SceneDelegate* delegate, const hd::Path& id,
                                             const CornerLayout& layout, std::string* problem = nullptr);

/// Area-weighted vertex normals, three per triangle.
std::vector<glm::vec3> smoothCornerNormals(const std::vector<glm::vec3>& points,
                                           const std::vector<glm::uvec3>& triangles);

/// primvars:displayColor when it holds one value (a constant colour); nullopt otherwise.
std::optional<glm::vec3> constantDisplayColor(const hd::SceneDelegate* delegate,
                                              const hd::Path& id);

/// The interpolation a primvar is authored with, if the prim has it.
std::optional<hd::Interpolation> primvarInterpolation(const hd::SceneDelegate* delegate,
                                                      const hd::Path& id, const hd::Token& name);

}  // namespace principled::embree
