// SPDX-License-Identifier: Apache-2.0
// Polygon triangulation with validation: convex faces become fans, concave ones are split
// inside their outline; bad faces are reported, not read.
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
    int badHoles = 0;                    ///< holeIndices entries that name no face
    std::string firstProblem;            ///< description of the first skipped face
};

/// Triangulates every face, honouring holeIndices and leftHanded orientation: a fan from its
/// first corner when the face is convex in its plane (or `points` is null); a concave quad
/// (a dart) split along its other diagonal; a larger concave face ear-clipped in its plane
/// (Newell normal), so an L, a C or a letter keeps its notches; a face ear clipping cannot
/// finish (self-intersecting) ends as a fan of what is left.
/// Returns false (with *error) when the topology is inconsistent as a whole: the counts do not
/// sum to the number of indices. Faces that only reference out-of-range points or have fewer
/// than 3 vertices are skipped and counted; holeIndices that name no face are counted in
/// badHoles.
bool triangulate(const hd::MeshTopology& topology, size_t pointCount, Triangulation* out,
                 std::string* error, const glm::vec3* points = nullptr);

}  // namespace principled::embree
