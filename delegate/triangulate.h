// SPDX-License-Identifier: Apache-2.0
// Polygon triangulation with validation: faces become fans, bad faces are reported, not read.
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "delegate/hd/meshTopology.h"

namespace principled::embree {

struct Triangulation {
    std::vector<glm::uvec3> triangles;   ///< vertex indices
    std::vector<glm::uvec3> corners;     ///< face-vertex (corner) indices of each triangle
    std::vector<int> triangleFace;       ///< authored face of each triangle
    int skippedFaces = 0;                ///< faces with < 3 vertices, holes, bad indices
    std::string firstProblem;            ///< description of the first skipped face
};

/// Fan-triangulates every face (quads and n-gons), honouring holeIndices and leftHanded
/// orientation. Returns false (with *error) when the topology is inconsistent as a whole:
/// the counts do not sum to the number of indices. Faces that only reference out-of-range
/// points or have fewer than 3 vertices are skipped and counted.
bool triangulate(const hd::MeshTopology& topology, size_t pointCount, Triangulation* out,
                 std::string* error);

}  // namespace principled::embree
