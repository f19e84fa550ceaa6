// SPDX-License-Identifier: Apache-2.0
// The coarse polygon cage: validation, holes and fan triangulation (levels 0 and scheme none).
#pragma once

#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "delegate/hd/meshTopology.h"

namespace principled::subdiv {

/// Checks what every consumer needs: non-negative counts summing to the number of indices,
/// faces of at least 3 vertices, indices inside [0, pointCount). On failure returns false and
/// a message naming the first bad face. O(faces + indices).
bool checkCage(const hd::MeshTopology& topology, size_t pointCount, std::string* error);

/// One flag per face: holeIndices, with out-of-range entries dropped with a warning.
std::vector<char> holeFlags(const hd::MeshTopology& topology, std::vector<std::string>* warnings);

/// Fan triangulation of the checked cage without its holes. leftHanded faces are emitted in
/// reverse order, so every triangle is counter-clockwise around its front normal.
struct CageTriangles {
    std::vector<glm::uvec3> triangles;  ///< point indices
    std::vector<glm::uvec3> corners;    ///< face-vertex indices (into faceVertexIndices)
    std::vector<int> triangleFace;      ///< coarse face of each triangle
};
CageTriangles triangulateCage(const hd::MeshTopology& topology, const std::vector<char>& holes);

}  // namespace principled::subdiv
