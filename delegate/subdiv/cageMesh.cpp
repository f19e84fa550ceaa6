// SPDX-License-Identifier: Apache-2.0
#include "delegate/subdiv/cageMesh.h"

#include <limits>
#include <utility>

namespace principled::subdiv {

bool checkCage(const hd::MeshTopology& topology, size_t pointCount, std::string* error) {
    // OpenSubdiv indexes with int.
    constexpr size_t kIntMax = size_t(std::numeric_limits<int>::max());
    if (pointCount > kIntMax || topology.faceVertexIndices.size() > kIntMax) {
        *error = "mesh too large: " + std::to_string(pointCount) + " points, " +
                 std::to_string(topology.faceVertexIndices.size()) + " face-vertices";
        return false;
    }
    const auto& counts = topology.faceVertexCounts;
    const auto& indices = topology.faceVertexIndices;
    size_t total = 0;
    for (size_t f = 0; f < counts.size(); ++f) {
        if (counts[f] < 3) {
            *error = "face " + std::to_string(f) + " has " + std::to_string(counts[f]) +
                     " vertices (at least 3 needed)";
            return false;
        }
        total += size_t(counts[f]);
    }
    if (total != indices.size()) {
        *error = "faceVertexCounts sum to " + std::to_string(total) +
                 " but faceVertexIndices has " + std::to_string(indices.size()) + " entries";
        return false;
    }
    size_t start = 0;
    for (size_t f = 0; f < counts.size(); ++f) {
        for (int k = 0; k < counts[f]; ++k) {
            int v = indices[start + size_t(k)];
            if (v < 0 || size_t(v) >= pointCount) {
                *error = "face " + std::to_string(f) + " references point " + std::to_string(v) +
                         " outside [0, " + std::to_string(pointCount) + ")";
                return false;
            }
        }
        start += size_t(counts[f]);
    }
    return true;
}

std::vector<char> holeFlags(const hd::MeshTopology& topology, std::vector<std::string>* warnings) {
    std::vector<char> holes(topology.faceVertexCounts.size(), 0);
    for (int h : topology.holeIndices) {
        if (h < 0 || size_t(h) >= holes.size()) {
            warnings->push_back("holeIndices entry " + std::to_string(h) +
                                " is not a face; ignored");
            continue;
        }
        holes[size_t(h)] = 1;
    }
    return holes;
}

CageTriangles triangulateCage(const hd::MeshTopology& topology, const std::vector<char>& holes) {
    CageTriangles out;
    const bool flip = topology.orientation == hd::Token("leftHanded");
    const auto& idx = topology.faceVertexIndices;
    size_t start = 0;
    for (size_t f = 0; f < topology.faceVertexCounts.size(); ++f) {
        const int n = topology.faceVertexCounts[f];
        if (!holes[f]) {
            for (int k = 1; k + 1 < n; ++k) {
                unsigned c0 = unsigned(start), c1 = unsigned(start + k),
                         c2 = unsigned(start + k + 1);
                if (flip) std::swap(c1, c2);
                out.corners.emplace_back(c0, c1, c2);
                out.triangles.emplace_back(idx[c0], idx[c1], idx[c2]);
                out.triangleFace.push_back(int(f));
            }
        }
        start += size_t(n);
    }
    return out;
}

}  // namespace principled::subdiv
