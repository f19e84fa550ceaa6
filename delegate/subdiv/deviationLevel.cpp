// SPDX-License-Identifier: Apache-2.0
#include "delegate/subdiv/deviationLevel.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace principled::subdiv {

float deviationLevel(const std::vector<glm::vec3>& points, const hd::MeshTopology& topology,
                     const hd::SubdivTags& tags, const ScreenMetric& view, float tolerancePixels) {
    constexpr float kUnknown = std::numeric_limits<float>::infinity();
    const size_t nPoints = points.size();
    const auto& counts = topology.faceVertexCounts;
    const auto& indices = topology.faceVertexIndices;
    if (nPoints == 0 || counts.empty() || view.imageHeight <= 0 || !(view.verticalFov > 0.0f) ||
        !(view.verticalFov < 3.14159265f) || !(tolerancePixels > 0.0f))
        return kUnknown;
    // Validate before indexing (SubdivTopology reports the details when it builds).
    size_t total = 0;
    for (int n : counts) {
        if (n < 3) return kUnknown;
        total += size_t(n);
    }
    if (total != indices.size()) return kUnknown;
    for (int i : indices)
        if (i < 0 || size_t(i) >= nPoints) return kUnknown;

    // Per vertex: sums of edge neighbours (two per incident face corner) and of incident face
    // centroids, and the nearest incident face's distance to the camera.
    std::vector<glm::dvec3> edgeSum(nPoints, glm::dvec3(0.0)), faceSum(nPoints, glm::dvec3(0.0));
    std::vector<glm::dvec3> normalSum(nPoints, glm::dvec3(0.0));  // area-weighted face normals
    std::vector<uint32_t> edgeCount(nPoints, 0), faceCount(nPoints, 0);
    std::vector<float> nearest(nPoints, std::numeric_limits<float>::infinity());
    std::vector<uint64_t> edges;  // (min << 32 | max), once per face side
    edges.reserve(indices.size());
    size_t start = 0;
    for (int n : counts) {
        const int* f = &indices[start];
        glm::dvec3 c(0.0);
        for (int k = 0; k < n; ++k) c += glm::dvec3(points[size_t(f[k])]);
        c /= double(n);
        double r = 0.0;
        for (int k = 0; k < n; ++k) r = std::max(r, glm::length(glm::dvec3(points[size_t(f[k])]) - c));
        const float distance = float(std::max(glm::length(c - glm::dvec3(view.cameraPosition)) - r, r * 1e-3));
        glm::dvec3 normal(0.0);  // Newell's method: twice the area vector of the polygon
        for (int k = 0; k < n; ++k)
            normal += glm::cross(glm::dvec3(points[size_t(f[k])]), glm::dvec3(points[size_t(f[(k + 1) % n])]));
        for (int k = 0; k < n; ++k) {
            const uint32_t v = uint32_t(f[k]), prev = uint32_t(f[(k + n - 1) % n]), next = uint32_t(f[(k + 1) % n]);
            edgeSum[v] += glm::dvec3(points[prev]) + glm::dvec3(points[next]);
            edgeCount[v] += 2;
            faceSum[v] += c;
            normalSum[v] += normal;
            ++faceCount[v];
            nearest[v] = std::min(nearest[v], distance);
            const uint32_t a = std::min(v, next), b = std::max(v, next);
            edges.push_back(uint64_t(a) << 32 | b);
        }
        start += size_t(n);
    }
    // Boundary edges: sides used by one face only.
    std::sort(edges.begin(), edges.end());
    std::vector<uint32_t> boundaryCount(nPoints, 0);
    std::vector<glm::dvec3> boundarySum(nPoints, glm::dvec3(0.0));
    bool anyBoundary = false;
    for (size_t i = 0; i < edges.size();) {
        size_t j = i;
        while (j < edges.size() && edges[j] == edges[i]) ++j;
        if (j - i == 1) {
            const uint32_t a = uint32_t(edges[i] >> 32), b = uint32_t(edges[i] & 0xffffffffu);
            boundarySum[a] += glm::dvec3(points[b]);
            boundarySum[b] += glm::dvec3(points[a]);
            ++boundaryCount[a];
            ++boundaryCount[b];
            anyBoundary = true;
        }
        i = j;
    }
    if (anyBoundary && tags.interpolateBoundary == hd::Token("none")) return kUnknown;
    const bool sharpCorners = tags.interpolateBoundary == hd::Token("edgeAndCorner");

    const float tanHalf = std::tan(0.5f * view.verticalFov);
    float worst = 0.0f;  // largest deviation in pixels
    for (size_t v = 0; v < nPoints; ++v) {
        if (faceCount[v] == 0) continue;  // unused point
        const glm::dvec3 p(points[v]);
        glm::dvec3 d(0.0);
        if (boundaryCount[v] == 0) {
            d = (2.0 / 9.0) * (edgeSum[v] / double(edgeCount[v]) - p) + (4.0 / 9.0) * (faceSum[v] / double(faceCount[v]) - p);
            // Inside the surface only the part along the normal moves it; a slide within the
            // tangent plane (an irregular flat grid) leaves the same picture.
            const double ln = glm::length(normalSum[v]);
            if (ln > 0.0 && std::isfinite(ln)) {
                const glm::dvec3 nv = normalSum[v] / ln;
                d = glm::dot(d, nv) * nv;
            }
        } else if (boundaryCount[v] == 2) {
            if (sharpCorners && faceCount[v] == 1) continue;  // a corner stays where it is
            d = (1.0 / 3.0) * (0.5 * boundarySum[v] - p);
        } else {
            return kUnknown;  // non-manifold boundary: no estimate
        }
        const float pixels = float(glm::length(d)) * float(view.imageHeight) / (2.0f * nearest[v] * tanHalf);
        if (!std::isfinite(pixels)) return kUnknown;
        worst = std::max(worst, pixels);
    }
    if (!(worst > tolerancePixels)) return -std::numeric_limits<float>::infinity();
    return 0.5f * std::log2(worst / tolerancePixels);
}

}  // namespace principled::subdiv
