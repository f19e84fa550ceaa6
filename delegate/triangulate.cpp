// SPDX-License-Identifier: Apache-2.0
#include "delegate/triangulate.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace principled::embree {
namespace {

double cross2(const glm::dvec2& a, const glm::dvec2& b) { return a.x * b.y - a.y * b.x; }

// Whether segments (p, q) and (r, s) cross at a point inside both (touching ends do not count).
bool segmentsCross(const glm::dvec2& p, const glm::dvec2& q, const glm::dvec2& r, const glm::dvec2& s) {
    const double d1 = cross2(q - p, r - p), d2 = cross2(q - p, s - p);
    const double d3 = cross2(s - r, p - r), d4 = cross2(s - r, q - r);
    return ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0));
}

// Working arrays of earClip, reused from face to face (no allocation per face).
struct EarClipScratch {
    std::vector<glm::dvec2> p;
    std::vector<int> left;
    std::vector<glm::ivec3> out;
};

// The corners (indices into `ring`, in face order) of a concave face as ear-clipped triangles
// in scratch.out; false (nothing written) when the face is convex (the caller fans it). The
// face's plane is its Newell normal (Newell 1972, as in Sutherland et al. 1974); in a frame
// around it the face winds counter-clockwise, so a corner turning clockwise is reflex.
bool earClip(const std::vector<glm::dvec3>& ring, EarClipScratch& scratch) {
    const int n = int(ring.size());
    glm::dvec3 normal(0.0);
    for (int i = 0; i < n; ++i) {
        const glm::dvec3 &a = ring[size_t(i)], &b = ring[size_t((i + 1) % n)];
        normal += glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    const double len = glm::length(normal);
    if (!(len > 0.0) || !std::isfinite(len)) return false;
    normal /= len;
    const glm::dvec3 t = glm::normalize(std::abs(normal.x) > 0.9 ? glm::cross(normal, glm::dvec3(0, 1, 0))
                                                                  : glm::cross(normal, glm::dvec3(1, 0, 0)));
    const glm::dvec3 b = glm::cross(normal, t);
    std::vector<glm::dvec2>& p = scratch.p;
    p.resize(ring.size());
    for (int i = 0; i < n; ++i) p[size_t(i)] = {glm::dot(ring[size_t(i)], t), glm::dot(ring[size_t(i)], b)};
    // Scale-relative tolerance for "turns" and "inside" (collinear corners are not reflex).
    double extent = 0.0;
    for (const auto& q : p) extent = std::max({extent, std::abs(q.x - p[0].x), std::abs(q.y - p[0].y)});
    const double eps = 1e-12 * extent * extent;
    auto turn = [&](int a, int c, int d) {
        return cross2(p[size_t(c)] - p[size_t(a)], p[size_t(d)] - p[size_t(c)]);
    };
    bool convex = true;
    for (int i = 0; i < n && convex; ++i) convex = turn((i + n - 1) % n, i, (i + 1) % n) >= -eps;
    if (convex) return false;

    // A ring that passes a point twice (two shapes touching at a corner, a keyhole): an ear's
    // diagonal must then also cross no edge, which the containment test alone does not see.
    bool repeats = false;
    {
        std::vector<glm::dvec2> sorted(p);
        std::sort(sorted.begin(), sorted.end(), [](const glm::dvec2& u, const glm::dvec2& v) {
            return u.x < v.x || (u.x == v.x && u.y < v.y);
        });
        repeats = std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end();
    }
    std::vector<int>& left = scratch.left;
    left.resize(ring.size());
    for (int i = 0; i < n; ++i) left[size_t(i)] = i;
    std::vector<glm::ivec3>& out = scratch.out;
    out.clear();
    auto inside = [&](const glm::dvec2& q, int a, int c, int d) {
        // Strictly inside or on an edge of the counter-clockwise triangle (a, c, d).
        const glm::dvec2 &A = p[size_t(a)], &C = p[size_t(c)], &D = p[size_t(d)];
        return cross2(C - A, q - A) >= -eps && cross2(D - C, q - C) >= -eps && cross2(A - D, q - D) >= -eps;
    };
    // The area still to cover: an ear larger than it lies (partly) outside the face (a ring
    // pinched at a repeated point leaves a flat remainder whose "ears" are not in the face).
    double remaining = 0.0;
    for (int i = 0; i < n; ++i) remaining += 0.5 * cross2(p[size_t(i)], p[size_t((i + 1) % n)]);
    const double areaEps = 1e-9 * std::abs(remaining);
    auto isEar = [&](int k) {
        const int m = int(left.size());
        const int a = left[size_t((k + m - 1) % m)], c = left[size_t(k)], d = left[size_t((k + 1) % m)];
        if (turn(a, c, d) <= eps) return false;  // reflex or flat
        if (remaining - 0.5 * turn(a, c, d) < -areaEps) return false;
        for (int j = 0; j < m; ++j) {
            const int v = left[size_t(j)];
            if (v == a || v == c || v == d) continue;
            if (p[size_t(v)] == p[size_t(a)] || p[size_t(v)] == p[size_t(c)] || p[size_t(v)] == p[size_t(d)]) continue;
            if (inside(p[size_t(v)], a, c, d)) return false;
        }
        if (repeats)
            for (int j = 0; j < m; ++j)
                if (segmentsCross(p[size_t(a)], p[size_t(d)], p[size_t(left[size_t(j)])], p[size_t(left[size_t((j + 1) % m)])]))
                    return false;
        return true;
    };
    // The search goes on from the last ear (clipping one rarely makes an earlier corner an
    // ear), around the ring once before giving up.
    int k = 0;
    while (left.size() > 3) {
        const int m = int(left.size());
        int tried = 0;
        while (tried < m && !isEar(k % m)) ++tried, ++k;
        if (tried == m) break;  // self-intersecting: fan what is left
        k %= m;
        const int a = left[size_t((k + m - 1) % m)], c = left[size_t(k)], d = left[size_t((k + 1) % m)];
        out.emplace_back(a, c, d);
        remaining -= 0.5 * turn(a, c, d);
        left.erase(left.begin() + k);
        if (k > 0) --k;
    }
    // What is left is a triangle, a flat remainder of a pinched ring (nothing to cover), or a
    // self-intersecting rest (fanned).
    if (remaining > areaEps)
        for (size_t j = 1; j + 1 < left.size(); ++j) out.emplace_back(left[0], left[j], left[j + 1]);
    return true;
}

}  // namespace

bool triangulate(const hd::MeshTopology& topo, size_t pointCount, Triangulation* out,
                 std::string* error, const glm::vec3* points) {
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
    std::unordered_set<int> holes;
    for (int h : topo.holeIndices) {
        if (h >= 0 && size_t(h) < topo.faceVertexCounts.size())
            holes.insert(h);
        else
            ++out->badHoles;
    }
    std::vector<glm::dvec3> ring;
    EarClipScratch scratch;
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
        auto emit = [&](int a, int b, int c) {  // corners of the face, in its order
            unsigned c0 = static_cast<unsigned>(start + size_t(a)), c1 = static_cast<unsigned>(start + size_t(b)),
                     c2 = static_cast<unsigned>(start + size_t(c));
            if (flip) std::swap(c1, c2);
            out->corners.emplace_back(c0, c1, c2);
            out->triangles.emplace_back(idx[c0], idx[c1], idx[c2]);
            out->triangleFace.push_back(static_cast<int>(f));
        };
        if (points && n == 4) {
            // A quad needs no plane: the fan's diagonal (0, 2) lies inside it unless its two
            // triangles face opposite ways (a dart with its reflex corner at 1 or 3), then the
            // other diagonal does.
            const glm::vec3 p0 = points[idx[start]], p1 = points[idx[start + 1]], p2 = points[idx[start + 2]],
                            p3 = points[idx[start + 3]];
            if (glm::dot(glm::cross(p1 - p0, p2 - p0), glm::cross(p2 - p0, p3 - p0)) < 0.0f) {
                emit(1, 2, 3);
                emit(1, 3, 0);
                continue;
            }
        } else if (points && n > 4) {
            ring.resize(size_t(n));
            for (int k = 0; k < n; ++k) ring[size_t(k)] = glm::dvec3(points[idx[start + size_t(k)]]);
            if (earClip(ring, scratch)) {
                for (const glm::ivec3& e : scratch.out) emit(e.x, e.y, e.z);
                continue;
            }
        }
        for (int k = 1; k + 1 < n; ++k) emit(0, k, k + 1);
    }
    return true;
}

}  // namespace principled::embree
