// SPDX-License-Identifier: Apache-2.0
#include "delegate/triangulate.h"

#include <algorithm>
#include <unordered_set>

namespace principled::embree {

bool triangulate(const hd::MeshTopology& topo, size_t pointCount, Triangulation* out,
                 std::string* error) {
    *out = Triangulation();
    size_t total = 0;
    for (int c : topo.faceVertexCounts) {
        if (c < 0) {
            *error = "faceVertexCounts has a negative count (" + std::to_string(c) + ")";
            return false;
        }
        total += static_cast<size_t>(c);
    }
    if (total != topo.faceVertexIndices.size()) {
        *error = "faceVertexCounts sum to " + std::to_string(total) + " but faceVertexIndices has " +
                 std::to_string(topo.faceVertexIndices.size()) + " entries";
        return false;
    }
    std::unordered_set<int> holes(topo.holeIndices.begin(), topo.holeIndices.end());
    bool flip = topo.orientation == hd::Token("leftHanded");
    size_t base = 0;
    const auto& idx = topo.faceVertexIndices;
    for (size_t f = 0; f < topo.faceVertexCounts.size(); ++f) {
        int n = topo.faceVertexCounts[f];
        size_t start = base;
        base += static_cast<size_t>(n);
        auto skip = [&](const std::string& why) {
            if (out->skippedFaces++ == 0) out->firstProblem = "face " + std::to_string(f) + ": " + why;
        };
        if (holes.count(static_cast<int>(f))) continue;  // a hole is intended, not a problem
        if (n < 3) {
            skip("has " + std::to_string(n) + " vertices (at least 3 needed)");
            continue;
        }
        bool inRange = true;
        for (int k = 0; k < n; ++k) {
            int v = idx[start + k];
            if (v < 0 || static_cast<size_t>(v) >= pointCount) inRange = false;
        }
        if (!inRange) {
            skip("references a point index outside [0, " + std::to_string(pointCount) + ")");
            continue;
        }
        for (int k = 1; k + 1 < n; ++k) {
            unsigned c0 = static_cast<unsigned>(start), c1 = static_cast<unsigned>(start + k),
                     c2 = static_cast<unsigned>(start + k + 1);
            if (flip) std::swap(c1, c2);
            out->corners.emplace_back(c0, c1, c2);
            out->triangles.emplace_back(idx[c0], idx[c1], idx[c2]);
            out->triangleFace.push_back(static_cast<int>(f));
        }
    }
    return true;
}

}  // namespace principled::embree
