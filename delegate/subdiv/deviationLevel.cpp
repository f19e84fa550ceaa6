// SPDX-License-Identifier: Apache-2.0
#include "delegate/subdiv/deviationLevel.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace principled::subdiv {

namespace {

constexpr float kUnknown = std::numeric_limits<float>::infinity();

bool validTopology(const hd::MeshTopology& t, size_t valueCount, const std::vector<int>& indices) {
    if (valueCount == 0 || t.faceVertexCounts.empty()) return false;
    size_t total = 0;
    for (int n : t.faceVertexCounts) {
        if (n < 3) return false;
        total += size_t(n);
    }
    if (total != indices.size()) return false;
    for (int i : indices)
        if (i < 0 || size_t(i) >= valueCount) return false;
    return true;
}

// The gap between each value (a vertex, or a face-varying value) and its limit under the
// smooth rules, per component (see deviationLevel.h): interior (2/9)(mean edge neighbour - v)
// + (4/9)(mean face centroid - v); boundary (1/3)((b0 + b1)/2 - v); 0 at a corner kept sharp.
// indices: per face corner, into values (faceVertexIndices, or a face-varying channel's).
// Returns false where no estimate exists (a non-manifold boundary). normals (optional, 3
// components): the area-weighted vertex normal sums.
struct Gaps {
    std::vector<double> gap;  // valueCount x components
    std::vector<char> boundary;
};
bool limitGaps(const double* values, int components, size_t valueCount, const hd::MeshTopology& t,
               const std::vector<int>& indices, bool sharpCorners, Gaps* out) {
    const size_t nc = size_t(components);
    std::vector<double> edgeSum(valueCount * nc, 0.0), faceSum(valueCount * nc, 0.0), boundarySum(valueCount * nc, 0.0);
    std::vector<uint32_t> edgeCount(valueCount, 0), faceCount(valueCount, 0), boundaryCount(valueCount, 0);
    std::vector<uint64_t> edges;  // (min << 32 | max), once per face side
    edges.reserve(indices.size());
    std::vector<double> c(nc);
    size_t start = 0;
    for (int n : t.faceVertexCounts) {
        const int* f = &indices[start];
        std::fill(c.begin(), c.end(), 0.0);
        for (int k = 0; k < n; ++k)
            for (size_t j = 0; j < nc; ++j) c[j] += values[size_t(f[k]) * nc + j] / double(n);
        for (int k = 0; k < n; ++k) {
            const uint32_t v = uint32_t(f[k]), prev = uint32_t(f[(k + n - 1) % n]), next = uint32_t(f[(k + 1) % n]);
            for (size_t j = 0; j < nc; ++j) {
                edgeSum[v * nc + j] += values[prev * nc + j] + values[next * nc + j];
                faceSum[v * nc + j] += c[j];
            }
            edgeCount[v] += 2;
            ++faceCount[v];
            edges.push_back(uint64_t(std::min(v, next)) << 32 | std::max(v, next));
        }
        start += size_t(n);
    }
    std::sort(edges.begin(), edges.end());
    for (size_t i = 0; i < edges.size();) {
        size_t j = i;
        while (j < edges.size() && edges[j] == edges[i]) ++j;
        if (j - i == 1) {  // a side of one face only: a boundary edge
            const uint32_t a = uint32_t(edges[i] >> 32), b = uint32_t(edges[i] & 0xffffffffu);
            for (size_t k = 0; k < nc; ++k) {
                boundarySum[a * nc + k] += values[b * nc + k];
                boundarySum[b * nc + k] += values[a * nc + k];
            }
            ++boundaryCount[a];
            ++boundaryCount[b];
        }
        i = j;
    }
    out->gap.assign(valueCount * nc, 0.0);
    out->boundary.assign(valueCount, 0);
    for (size_t v = 0; v < valueCount; ++v) {
        if (faceCount[v] == 0) continue;  // unused
        out->boundary[v] = boundaryCount[v] != 0;
        if (boundaryCount[v] == 0) {
            for (size_t k = 0; k < nc; ++k)
                out->gap[v * nc + k] = (2.0 / 9.0) * (edgeSum[v * nc + k] / edgeCount[v] - values[v * nc + k]) +
                                       (4.0 / 9.0) * (faceSum[v * nc + k] / faceCount[v] - values[v * nc + k]);
        } else if (boundaryCount[v] == 2) {
            if (sharpCorners && faceCount[v] == 1) continue;  // a corner stays where it is
            for (size_t k = 0; k < nc; ++k)
                out->gap[v * nc + k] = (1.0 / 3.0) * (0.5 * boundarySum[v * nc + k] - values[v * nc + k]);
        } else {
            return false;  // non-manifold boundary
        }
    }
    return true;
}

// Whether polygon f (n >= 4 corners) turns the same way at every corner about its normal:
// a concave polygon is fan-triangulated over its notches at level 0.
bool convex(const std::vector<glm::dvec3>& p, const int* f, int n, const glm::dvec3& normal) {
    for (int k = 0; k < n; ++k) {
        const glm::dvec3& a = p[size_t(f[k])];
        const glm::dvec3& b = p[size_t(f[(k + 1) % n])];
        const glm::dvec3& c = p[size_t(f[(k + 2) % n])];
        if (glm::dot(glm::cross(b - a, c - b), normal) < 0.0) return false;
    }
    return true;
}

}  // namespace

float deviationLevel(const std::vector<glm::vec3>& points, const hd::MeshTopology& topology,
                     const hd::SubdivTags& tags, const ScreenMetric& view, float tolerancePixels) {
    const size_t nPoints = points.size();
    const auto& counts = topology.faceVertexCounts;
    const auto& indices = topology.faceVertexIndices;
    if (view.imageHeight <= 0 || !(view.verticalFov > 0.0f) || !(view.verticalFov < 3.14159265f) ||
        !(tolerancePixels > 0.0f) || !validTopology(topology, nPoints, indices))
        return kUnknown;
    if (tags.interpolateBoundary == hd::Token("none")) return kUnknown;  // limit drops boundary faces
    std::vector<glm::dvec3> p(nPoints);
    for (size_t i = 0; i < nPoints; ++i) {
        p[i] = glm::dvec3(points[i]);
        if (!std::isfinite(p[i].x) || !std::isfinite(p[i].y) || !std::isfinite(p[i].z)) return kUnknown;
    }
    Gaps gaps;
    if (!limitGaps(&p[0].x, 3, nPoints, topology, indices, tags.interpolateBoundary == hd::Token("edgeAndCorner"), &gaps))
        return kUnknown;

    // Per face: its distance to the camera, its normal, and how far it is from flat.
    const double tanHalf = std::tan(0.5 * double(view.verticalFov));
    const double pixelsPerUnitAt1 = double(view.imageHeight) / (2.0 * tanHalf);
    std::vector<double> nearest(nPoints, std::numeric_limits<double>::infinity());
    std::vector<glm::dvec3> normalSum(nPoints, glm::dvec3(0.0));
    double worst = 0.0;  // largest gap in pixels
    size_t start = 0;
    for (int n : counts) {
        const int* f = &indices[start];
        start += size_t(n);
        glm::dvec3 c(0.0), normal(0.0);  // centroid; Newell's normal (twice the area vector)
        for (int k = 0; k < n; ++k) {
            c += p[size_t(f[k])];
            normal += glm::cross(p[size_t(f[k])], p[size_t(f[(k + 1) % n])]);
        }
        c /= double(n);
        double r = 0.0;
        for (int k = 0; k < n; ++k) r = std::max(r, glm::length(p[size_t(f[k])] - c));
        const double distance = std::max(glm::length(c - glm::dvec3(view.cameraPosition)) - r, r * 1e-3);
        for (int k = 0; k < n; ++k) {
            nearest[size_t(f[k])] = std::min(nearest[size_t(f[k])], distance);
            normalSum[size_t(f[k])] += normal;
        }
        const double area2 = glm::length(normal);
        if (n >= 4) {
            if (!(area2 > 0.0)) return kUnknown;  // degenerate polygon: no plane to test against
            const glm::dvec3 unit = normal / area2;
            if (!convex(p, f, n, unit)) return kUnknown;  // a fan would fill its notches
            // A face off its own plane (a twisted quad, a saddle, a bent n-gon) is far from its
            // fan triangles whatever its corners do: the largest corner height over the plane
            // through the centroid (half the diagonals' gap on a twisted quad).
            double h = 0.0;
            for (int k = 0; k < n; ++k) h = std::max(h, std::abs(glm::dot(p[size_t(f[k])] - c, unit)));
            worst = std::max(worst, h * pixelsPerUnitAt1 / distance);
        }
    }
    for (size_t v = 0; v < nPoints; ++v) {
        if (!std::isfinite(nearest[v])) continue;  // unused point
        glm::dvec3 d(gaps.gap[3 * v], gaps.gap[3 * v + 1], gaps.gap[3 * v + 2]);
        if (!gaps.boundary[v]) {
            // Inside the surface only the part along the normal moves it; a slide within the
            // tangent plane (an irregular flat grid) leaves the same picture.
            const double ln = glm::length(normalSum[v]);
            if (ln > 0.0 && std::isfinite(ln)) d = glm::dot(d, normalSum[v] / ln) * (normalSum[v] / ln);
        }
        worst = std::max(worst, glm::length(d) * pixelsPerUnitAt1 / nearest[v]);
    }
    if (!std::isfinite(worst)) return kUnknown;
    if (!(worst > double(tolerancePixels))) return -std::numeric_limits<float>::infinity();
    return float(0.5 * std::log2(worst / double(tolerancePixels)));
}

bool valuesFollowTheCage(const std::vector<float>& values, int components, const hd::MeshTopology& topology,
                         const std::vector<int>& indices, bool sharpCorners, double relativeTolerance) {
    if (components <= 0) return true;
    const size_t valueCount = values.size() / size_t(components);
    if (!validTopology(topology, valueCount, indices)) return false;
    std::vector<double> v(values.begin(), values.begin() + std::ptrdiff_t(valueCount * size_t(components)));
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (double x : v) {
        if (!std::isfinite(x)) return false;
        lo = std::min(lo, x);
        hi = std::max(hi, x);
    }
    Gaps gaps;
    if (!limitGaps(v.data(), components, valueCount, topology, indices, sharpCorners, &gaps)) return false;
    const double allowed = relativeTolerance * std::max(hi - lo, 1e-30);
    for (double g : gaps.gap)
        if (std::abs(g) > allowed) return false;
    return true;
}

}  // namespace principled::subdiv
