// SPDX-License-Identifier: Apache-2.0
// RefinedMesh: the triangles a SubdivTopology produces for one pose of the cage.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

namespace principled::subdiv {

/// Output of SubdivTopology::refine(). Triangles are counter-clockwise around their front
/// normal (leftHanded input already flipped), ready for Embree.
struct RefinedMesh {
    std::vector<glm::vec3> points;      ///< refined points (on the limit surface when subdivided)
    std::vector<glm::vec3> normals;     ///< unit limit normals per point; empty for cages
    std::vector<glm::uvec3> triangles;  ///< indices into points; holes removed
    std::vector<int> triangleFace;      ///< coarse (authored) face of each triangle
    /// SubdivTopology::id() that filled triangles/triangleFace. refine() copies the topology
    /// arrays only when this differs, so re-posing into the same RefinedMesh copies points
    /// and normals only.
    uint64_t topologyId = 0;
};

}  // namespace principled::subdiv
