// SPDX-License-Identifier: Apache-2.0
// Small cages for the subdivision tests: unit cube, planar grid, tetrahedron.
#pragma once

#include <glm/glm.hpp>
#include <vector>

#include "delegate/hd/meshTopology.h"

namespace principled::subdiv::test {

struct Cage {
    hd::MeshTopology topology;
    std::vector<glm::vec3> points;
};

/// [-0.5, 0.5]^3, quads counter-clockwise seen from outside (face 0 is +z).
inline Cage cube() {
    Cage c;
    c.points = {{-.5f, -.5f, .5f}, {.5f, -.5f, .5f}, {-.5f, .5f, .5f},   {.5f, .5f, .5f},
                {-.5f, .5f, -.5f}, {.5f, .5f, -.5f}, {-.5f, -.5f, -.5f}, {.5f, -.5f, -.5f}};
    c.topology.faceVertexCounts = {4, 4, 4, 4, 4, 4};
    c.topology.faceVertexIndices = {0, 1, 3, 2, 2, 3, 5, 4, 4, 5, 7, 6,
                                    6, 7, 1, 0, 1, 7, 5, 3, 6, 0, 2, 4};
    return c;
}

/// n x n quads over [0, n] x [0, n] at z = 0, counter-clockwise seen from +z.
/// Point (i, j) has index j * (n + 1) + i.
inline Cage grid(int n) {
    Cage c;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) c.points.emplace_back(float(i), float(j), 0.0f);
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            int v = j * (n + 1) + i;
            c.topology.faceVertexCounts.push_back(4);
            for (int k : {v, v + 1, v + n + 2, v + n + 1})
                c.topology.faceVertexIndices.push_back(k);
        }
    }
    return c;
}

/// Regular tetrahedron centred at the origin, triangles counter-clockwise seen from outside.
inline Cage tetrahedron() {
    Cage c;
    c.points = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
    c.topology.faceVertexCounts = {3, 3, 3, 3};
    c.topology.faceVertexIndices = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2};
    // Orient every face outward (the centroid direction of a convex cage around the origin).
    for (int f = 0; f < 4; ++f) {
        int* v = &c.topology.faceVertexIndices[size_t(3 * f)];
        glm::vec3 a = c.points[v[0]], b = c.points[v[1]], d = c.points[v[2]];
        if (glm::dot(glm::cross(b - a, d - a), a + b + d) < 0.0f) std::swap(v[1], v[2]);
    }
    return c;
}

}  // namespace principled::subdiv::test
