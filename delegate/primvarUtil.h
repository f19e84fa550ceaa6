// SPDX-License-Identifier: Apache-2.0
// Primvar helpers shared by rprims: expanding any interpolation to per-triangle-corner values,
// smooth normals, and constant display colour.
#pragma once

#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "delegate/hd/path.h"

namespace principled::hd {
class SceneDelegate;
}

namespace principled::embree {

/// Authored normals (the "normals" primvar in any interpolation, indexed or not) expanded to
/// three per triangle, normalised. Empty when none are authored or the count does not match
/// the interpolation (a mismatch is ignored rather than read out of bounds).
std::vector<glm::vec3> authoredCornerNormals(const hd::SceneDelegate* delegate, const hd::Path& id,
                                             size_t pointCount, size_t faceCount,
                                             const std::vector<glm::uvec3>& corners,
                                             const std::vector<glm::uvec3>& triangles,
                                             const std::vector<int>& triangleFace);

/// Area-weighted vertex normals, three per triangle.
std::vector<glm::vec3> smoothCornerNormals(const std::vector<glm::vec3>& points,
                                           const std::vector<glm::uvec3>& triangles);

/// primvars:displayColor when it is constant (or its first value otherwise).
std::optional<glm::vec3> constantDisplayColor(const hd::SceneDelegate* delegate,
                                              const hd::Path& id);

}  // namespace principled::embree
