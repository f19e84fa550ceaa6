// SPDX-License-Identifier: Apache-2.0
#include "delegate/subdiv/deviationLevel.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace principled;
using namespace principled::subdiv;

namespace {

// tan(fov/2) = 0.5, 1000 pixels high: a length s at distance D covers 1000 s / D pixels.
ScreenMetric camera(const glm::vec3& eye) {
    ScreenMetric v;
    v.cameraPosition = eye;
    v.verticalFov = 2.0f * std::atan(0.5f);
    v.imageHeight = 1000;
    return v;
}

// An n x n grid of unit quads in z = 0, points jittered within the plane by `jitter`.
void grid(int n, float jitter, std::vector<glm::vec3>* points, hd::MeshTopology* t) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-jitter, jitter);
    points->clear();
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const bool edge = i == 0 || j == 0 || i == n || j == n;  // keep the outline straight
            points->emplace_back(float(i) + (edge ? 0.0f : u(rng)), float(j) + (edge ? 0.0f : u(rng)), 0.0f);
        }
    t->faceVertexCounts.assign(size_t(n * n), 4);
    t->faceVertexIndices.clear();
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int v = j * (n + 1) + i;
            for (int c : {v, v + 1, v + n + 2, v + n + 1}) t->faceVertexIndices.push_back(c);
        }
}

// The cube [-1, 1]^3 as six quads.
void cube(std::vector<glm::vec3>* points, hd::MeshTopology* t) {
    *points = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1}, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}};
    t->faceVertexCounts.assign(6, 4);
    t->faceVertexIndices = {0, 3, 2, 1, 4, 5, 6, 7, 0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6, 3, 0, 4, 7};
}

}  // namespace

TEST(DeviationLevel, FlatGridsNeedNoRefinementUnderEdgeAndCorner) {
    std::vector<glm::vec3> points;
    hd::MeshTopology t;
    hd::SubdivTags tags;  // edgeAndCorner
    for (float jitter : {0.0f, 0.3f}) {  // a slide within the plane changes nothing on screen
        grid(8, jitter, &points, &t);
        EXPECT_EQ(deviationLevel(points, t, tags, camera({4, 4, 0.5f}), 0.1f), -INFINITY) << jitter;
    }
    // edgeOnly rounds the corners off: the outline moves, so some level is asked for.
    tags.interpolateBoundary = hd::Token("edgeOnly");
    grid(8, 0.0f, &points, &t);
    EXPECT_GT(deviationLevel(points, t, tags, camera({4, 4, 5}), 0.1f), 1.0f);
    // "none" drops the boundary faces from the limit: no estimate, the caller keeps its metric.
    tags.interpolateBoundary = hd::Token("none");
    EXPECT_EQ(deviationLevel(points, t, tags, camera({4, 4, 5}), 0.1f), INFINITY);
}

TEST(DeviationLevel, FollowsTheCubesLimitPointWithinALevel) {
    // Catmull-Clark takes the cube's corner (1,1,1) to (0.5,0.5,0.5) in the limit, a gap of
    // sqrt(3)/2 (limit mask of a valence-3 vertex: (9 v + 4 sum e + sum f) / 24); the estimate,
    // exact for regular vertices, gives 4 sqrt(3)/9 here.
    std::vector<glm::vec3> points;
    hd::MeshTopology t;
    cube(&points, &t);
    const float D = 100.0f;
    const ScreenMetric view = camera({0, 0, D + 3.0f});
    const float x = deviationLevel(points, t, hd::SubdivTags{}, view, 0.1f);
    // The nearest face (z = 1) is at D + 3 - 1 - sqrt(2) from the camera.
    const float px = std::sqrt(3.0f) / 2.0f * 1000.0f / (D + 2.0f - std::sqrt(2.0f));
    EXPECT_NEAR(x, 0.5f * std::log2(px / 0.1f), 0.15f);
    // Twice as far: half the pixels, half a level less; a tolerance 4x looser: one level less.
    const ScreenMetric far = camera({0, 0, 2.0f * (D + 2.0f - std::sqrt(2.0f)) + 1.0f + std::sqrt(2.0f)});
    EXPECT_NEAR(deviationLevel(points, t, hd::SubdivTags{}, far, 0.1f), x - 0.5f, 1e-3f);
    EXPECT_NEAR(deviationLevel(points, t, hd::SubdivTags{}, view, 0.4f), x - 1.0f, 1e-4f);
}

TEST(DeviationLevel, BadInputGivesNoEstimate) {
    std::vector<glm::vec3> points;
    hd::MeshTopology t;
    cube(&points, &t);
    hd::MeshTopology bad = t;
    bad.faceVertexIndices[3] = 99;  // out of range
    EXPECT_EQ(deviationLevel(points, bad, hd::SubdivTags{}, camera({0, 0, 5}), 0.1f), INFINITY);
    bad = t;
    bad.faceVertexCounts[0] = 2;
    EXPECT_EQ(deviationLevel(points, bad, hd::SubdivTags{}, camera({0, 0, 5}), 0.1f), INFINITY);
    EXPECT_EQ(deviationLevel(points, t, hd::SubdivTags{}, camera({0, 0, 5}), 0.0f), INFINITY);
    std::vector<glm::vec3> nan = points;
    nan[0].x = NAN;
    EXPECT_EQ(deviationLevel(nan, t, hd::SubdivTags{}, camera({0, 0, 5}), 0.1f), INFINITY);
}

TEST(DeviationLevel, SaddlesTwistedQuadsAndBentPolygonsAreNotFlat) {
    // z = x y over a 3 x 3 grid: every interior vertex already lies on its limit and the
    // boundary is straight, so only the faces' own twist shows that it is not flat.
    std::vector<glm::vec3> points;
    hd::MeshTopology t;
    grid(3, 0.0f, &points, &t);
    for (glm::vec3& p : points) p.z = 0.3f * (p.x - 1.5f) * (p.y - 1.5f);
    EXPECT_GT(deviationLevel(points, t, hd::SubdivTags{}, camera({1.5f, 1.5f, 6}), 0.1f), 2.0f);
    // One twisted quad: all four corners are sharp corners, the face term alone sees it.
    std::vector<glm::vec3> quad{{0, 0, 0}, {1, 0, 0.3f}, {1, 1, 0}, {0, 1, 0.3f}};
    hd::MeshTopology one;
    one.faceVertexCounts = {4};
    one.faceVertexIndices = {0, 1, 2, 3};
    EXPECT_GT(deviationLevel(quad, one, hd::SubdivTags{}, camera({0.5f, 0.5f, 5}), 0.1f), 2.0f);
    // The same quad flat: nothing to refine.
    for (glm::vec3& p : quad) p.z = 0.0f;
    EXPECT_EQ(deviationLevel(quad, one, hd::SubdivTags{}, camera({0.5f, 0.5f, 5}), 0.1f), -INFINITY);
}

TEST(DeviationLevel, AConcavePolygonGetsNoEstimate) {
    // A flat ten-point star: the level-0 fan would fill its notches.
    std::vector<glm::vec3> star;
    hd::MeshTopology t;
    for (int k = 0; k < 10; ++k) {
        const float a = float(k) * 0.6283185f, r = k % 2 ? 0.4f : 1.0f;
        star.emplace_back(r * std::cos(a), r * std::sin(a), 0.0f);
        t.faceVertexIndices.push_back(k);
    }
    t.faceVertexCounts = {10};
    EXPECT_EQ(deviationLevel(star, t, hd::SubdivTags{}, camera({0, 0, 5}), 0.1f), INFINITY);
}

TEST(DeviationLevel, PrimvarsFollowTheCageOnlyWhenTheyAreTheirOwnLimit) {
    std::vector<glm::vec3> points;
    hd::MeshTopology t;
    grid(4, 0.0f, &points, &t);
    // st linear over the regular grid (planar projection): its own limit.
    std::vector<float> st;
    for (const glm::vec3& p : points) st.insert(st.end(), {0.25f * p.x, 0.25f * p.y});
    EXPECT_TRUE(valuesFollowTheCage(st, 2, t, t.faceVertexIndices, true, 1e-4));
    // A painted colour (one bright vertex) is smoothed by the refinement.
    std::vector<float> color(points.size() * 3, 0.2f);
    color[3 * 12] = 1.0f;
    EXPECT_FALSE(valuesFollowTheCage(color, 3, t, t.faceVertexIndices, true, 1e-4));
    // A stretched layout (s = x^2) is not linear either.
    for (size_t i = 0; i < points.size(); ++i) st[2 * i] = points[i].x * points[i].x;
    EXPECT_FALSE(valuesFollowTheCage(st, 2, t, t.faceVertexIndices, true, 1e-4));
}
