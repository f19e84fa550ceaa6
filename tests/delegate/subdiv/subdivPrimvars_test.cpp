// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "delegate/subdiv/subdivTopology.h"
#include "tests/delegate/subdiv/subdivTestMeshes.h"

using namespace principled;
using namespace principled::subdiv;
using principled::subdiv::test::Cage;

namespace {

std::unique_ptr<SubdivTopology> make(const Cage& c, const BuildOptions& o,
                                     const hd::SubdivTags& tags = {}) {
    std::string err;
    auto t = SubdivTopology::create(c.topology, tags, c.points.size(), o, &err);
    EXPECT_TRUE(t) << err;
    return t;
}

/// st per face-vertex over a grid where every face is its own UV island:
/// face f gets (10 f + u, v) at its corners, u, v in {0, 1}.
FaceVaryingChannel islands(const Cage& g, std::vector<float>* st) {
    FaceVaryingChannel ch;
    const float corner[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (size_t f = 0; f < g.topology.faceVertexCounts.size(); ++f) {
        for (int k = 0; k < 4; ++k) {
            ch.indices.push_back(int(4 * f + k));
            st->push_back(10.0f * float(f) + corner[k][0]);
            st->push_back(corner[k][1]);
        }
    }
    ch.valueCount = ch.indices.size();
    return ch;
}

}  // namespace

TEST(SubdivPrimvars, VertexPrimvarsFollowThePointsAnyComponentCount) {
    Cage c = test::cube();
    auto t = make(c, BuildOptions{2});
    RefinedMesh m;
    ASSERT_TRUE(t->refine(c.points, &m));
    // 5 components: xyz, then a constant and x again.
    std::vector<float> values;
    for (const glm::vec3& p : c.points) values.insert(values.end(), {p.x, p.y, p.z, 1.0f, p.x});
    std::vector<float> out;
    std::string err;
    ASSERT_TRUE(t->refineVertex(values.data(), c.points.size(), 5, &out, &err)) << err;
    ASSERT_EQ(out.size(), m.points.size() * 5);
    for (size_t i = 0; i < m.points.size(); ++i) {
        ASSERT_NEAR(out[5 * i + 0], m.points[i].x, 1e-6f);
        ASSERT_NEAR(out[5 * i + 2], m.points[i].z, 1e-6f);
        ASSERT_NEAR(out[5 * i + 3], 1.0f, 1e-5f);  // stencil weights sum to 1
        ASSERT_NEAR(out[5 * i + 4], m.points[i].x, 1e-6f);
    }
    EXPECT_FALSE(t->refineVertex(values.data(), 7, 5, &out, &err));
}

TEST(SubdivPrimvars, VaryingIsLinearOnTheCage) {
    Cage c = test::cube();
    auto t = make(c, BuildOptions{3});
    std::vector<float> out;
    ASSERT_TRUE(t->refineVarying(&c.points[0].x, c.points.size(), 3, &out));
    ASSERT_EQ(out.size(), t->refinedPointCount() * 3);
    // Linear interpolation of the cage keeps every value on a cube face.
    for (size_t i = 0; i < out.size(); i += 3)
        ASSERT_NEAR(std::max({std::abs(out[i]), std::abs(out[i + 1]), std::abs(out[i + 2])}), 0.5f,
                    1e-6f);
    BuildOptions noVarying{3};
    noVarying.varying = false;
    auto t2 = make(c, noVarying);
    std::string err;
    EXPECT_FALSE(t2->refineVarying(&c.points[0].x, c.points.size(), 3, &out, &err));
}

TEST(SubdivPrimvars, FaceVaryingStOnAUniformGridStaysLinear) {
    // st = xy / n with values shared like the points: both "all" (linear) and USD's default
    // cornersPlus1 reproduce the linear map on a uniform grid, so st == xy / n at each corner.
    const int n = 4;
    Cage g = test::grid(n);
    std::vector<float> st;
    for (const glm::vec3& p : g.points) st.insert(st.end(), {p.x / n, p.y / n});
    for (const char* mode : {"all", "cornersPlus1"}) {
        hd::SubdivTags tags;
        tags.faceVaryingLinearInterpolation = mode;
        BuildOptions o{3};
        o.faceVarying = {{g.topology.faceVertexIndices, g.points.size()}};
        auto t = make(g, o, tags);
        RefinedMesh m;
        ASSERT_TRUE(t->refine(g.points, &m));
        std::vector<float> out;
        std::string err;
        ASSERT_TRUE(t->refineFaceVarying(0, st.data(), g.points.size(), 2, &out, &err)) << err;
        ASSERT_EQ(out.size(), m.triangles.size() * 3 * 2);
        for (size_t tri = 0; tri < m.triangles.size(); ++tri) {
            for (int k = 0; k < 3; ++k) {
                const glm::vec3& p = m.points[m.triangles[tri][k]];
                ASSERT_NEAR(out[(3 * tri + k) * 2 + 0], p.x / n, 1e-5f) << mode;
                ASSERT_NEAR(out[(3 * tri + k) * 2 + 1], p.y / n, 1e-5f) << mode;
            }
        }
    }
}

TEST(SubdivPrimvars, FaceVaryingIslandsUseTheirOwnChannel) {
    Cage g = test::grid(3);
    std::vector<float> st;
    FaceVaryingChannel ch = islands(g, &st);
    for (const char* mode : {"all", "none"}) {
        hd::SubdivTags tags;
        tags.faceVaryingLinearInterpolation = mode;
        BuildOptions o{2};
        o.faceVarying = {ch};
        auto t = make(g, o, tags);
        std::vector<float> out;
        ASSERT_TRUE(t->refineFaceVarying(0, st.data(), ch.valueCount, 2, &out));
        bool exactCorner = false;
        for (size_t corner = 0; corner < out.size() / 2; ++corner) {
            const int f = t->triangleFace()[corner / 3];
            const float s = out[2 * corner] - 10.0f * float(f), v = out[2 * corner + 1];
            // Values never leak from a neighbouring island.
            ASSERT_GE(s, -1e-5f);
            ASSERT_LE(s, 1.0f + 1e-5f);
            ASSERT_GE(v, -1e-5f);
            ASSERT_LE(v, 1.0f + 1e-5f);
            if (std::abs(s) < 1e-6f && std::abs(v) < 1e-6f) exactCorner = true;
        }
        // Both keep the corner of a one-face island (OpenSubdiv makes such values corners).
        EXPECT_TRUE(exactCorner) << mode;
    }
}

TEST(SubdivPrimvars, FaceVaryingLinearAllKeepsEveryValueSmoothModesDoNot) {
    // 2x2 grid, st = xy / 2 with the centre value bumped to 0.7. "all" interpolates every
    // value (the limit st at the centre point stays 0.7); "none" and "cornersPlus1" smooth the
    // interior value with the Catmull-Clark limit mask (16 v + 4 sum e + sum f) / 36.
    Cage g = test::grid(2);
    std::vector<float> st;
    for (const glm::vec3& p : g.points) st.insert(st.end(), {p.x / 2, p.y / 2});
    st[2 * 4] = st[2 * 4 + 1] = 0.7f;  // point 4 is the centre (1, 1)
    // Limit of the bumped centre on the level-0 masks: edge neighbours sum to 2 per axis,
    // face neighbours sum to 2 as well, so (16 * 0.7 + 4 * 2 + 2) / 36.
    const float smooth = (16.0f * 0.7f + 8.0f + 2.0f) / 36.0f;
    for (const char* mode : {"all", "none", "cornersPlus1"}) {
        hd::SubdivTags tags;
        tags.faceVaryingLinearInterpolation = mode;
        BuildOptions o{2};
        o.faceVarying = {{g.topology.faceVertexIndices, g.points.size()}};
        auto t = make(g, o, tags);
        RefinedMesh m;
        ASSERT_TRUE(t->refine(g.points, &m));
        std::vector<float> out;
        ASSERT_TRUE(t->refineFaceVarying(0, st.data(), g.points.size(), 2, &out));
        int found = 0;
        for (size_t c = 0; c < m.triangles.size() * 3; ++c) {
            if (glm::length(m.points[m.triangles[c / 3][c % 3]] - glm::vec3(1, 1, 0)) > 1e-6f)
                continue;
            ++found;
            const float expected = std::string(mode) == "all" ? 0.7f : smooth;
            EXPECT_NEAR(out[2 * c], expected, 1e-5f) << mode;
            EXPECT_NEAR(out[2 * c + 1], expected, 1e-5f) << mode;
        }
        EXPECT_GT(found, 0);
    }
}

TEST(SubdivPrimvars, UniformFollowsTheCoarseFaceMap) {
    Cage c = test::cube();
    c.topology.holeIndices = {2};
    auto t = make(c, BuildOptions{2});
    std::vector<float> perFace = {0, 1, 2, 3, 4, 5}, out;
    ASSERT_TRUE(t->refineUniform(perFace.data(), 6, 1, &out));
    ASSERT_EQ(out.size(), t->triangleCount());
    for (size_t i = 0; i < out.size(); ++i) ASSERT_EQ(out[i], float(t->triangleFace()[i]));
    std::string err;
    EXPECT_FALSE(t->refineUniform(perFace.data(), 5, 1, &out, &err));
}

TEST(SubdivPrimvars, CageLevelGathersFaceVaryingPerCorner) {
    Cage g = test::grid(2);
    std::vector<float> st;
    FaceVaryingChannel ch = islands(g, &st);
    BuildOptions o{0};
    o.faceVarying = {ch};
    auto t = make(g, o);
    std::vector<float> out;
    ASSERT_TRUE(t->refineFaceVarying(0, st.data(), ch.valueCount, 2, &out));
    ASSERT_EQ(out.size(), 8u * 3u * 2u);
    // Triangle 0 = corners 0, 1, 2 of face 0.
    EXPECT_EQ(std::vector<float>(out.begin(), out.begin() + 6),
              (std::vector<float>{0, 0, 1, 0, 1, 1}));
}

TEST(SubdivPrimvars, BadFaceVaryingChannelIsDroppedWithAWarning) {
    Cage g = test::grid(2);
    BuildOptions o{1};
    o.faceVarying = {{{0, 1, 2}, 3}, {g.topology.faceVertexIndices, 2}};  // short; out of range
    auto t = make(g, o);
    EXPECT_FALSE(t->faceVaryingAvailable(0));
    EXPECT_FALSE(t->faceVaryingAvailable(1));
    EXPECT_EQ(t->warnings().size(), 2u);
    std::vector<float> values(6), out;
    std::string err;
    EXPECT_FALSE(t->refineFaceVarying(0, values.data(), 3, 2, &out, &err));
    EXPECT_FALSE(err.empty());
    RefinedMesh m;
    EXPECT_TRUE(t->refine(g.points, &m));  // the geometry itself is fine
}

TEST(SubdivPrimvars, PerLevelChainsMatchFlatFarStencilTables) {
    // The default per-level tables and OpenSubdiv's flattened StencilTableFactory tables are
    // two factorings of the same refinement: every output must agree.
    struct Case {
        Cage cage;
        hd::SubdivTags tags;
        int level;
    };
    std::vector<Case> cases;
    {
        Case c{test::cube(), {}, 3};
        c.tags.creaseIndices = {0, 1, 3};
        c.tags.creaseLengths = {3};
        c.tags.creaseSharpnesses = {2.5f};
        c.tags.cornerIndices = {6};
        c.tags.cornerSharpnesses = {10};
        c.cage.topology.orientation = "leftHanded";
        cases.push_back(c);
    }
    {
        Case c{test::tetrahedron(), {}, 3};
        c.cage.topology.scheme = "loop";
        cases.push_back(c);
    }
    {
        Case c{test::grid(4), {}, 2};
        c.tags.interpolateBoundary = "edgeOnly";
        c.tags.faceVaryingLinearInterpolation = "cornersOnly";
        cases.push_back(c);
    }
    {
        Case c{test::grid(3), {}, 2};
        c.cage.topology.scheme = "bilinear";
        cases.push_back(c);
    }
    for (size_t k = 0; k < cases.size(); ++k) {
        const Case& c = cases[k];
        std::vector<float> st;
        BuildOptions perLevel{c.level};
        perLevel.faceVarying = {islands(c.cage, &st)};
        if (c.cage.topology.faceVertexCounts[0] != 4) {  // islands() assumes quads
            st.clear();
            FaceVaryingChannel ch{c.cage.topology.faceVertexIndices, c.cage.points.size()};
            for (const glm::vec3& p : c.cage.points) st.insert(st.end(), {p.x, p.y});
            perLevel.faceVarying = {ch};
        }
        BuildOptions flat = perLevel;
        flat.flatStencils = true;
        auto a = make(c.cage, perLevel, c.tags), b = make(c.cage, flat, c.tags);
        RefinedMesh ma, mb;
        ASSERT_TRUE(a->refine(c.cage.points, &ma));
        ASSERT_TRUE(b->refine(c.cage.points, &mb));
        ASSERT_EQ(ma.points.size(), mb.points.size()) << k;
        EXPECT_EQ(ma.triangles, mb.triangles);
        for (size_t i = 0; i < ma.points.size(); ++i) {
            ASSERT_NEAR(glm::length(ma.points[i] - mb.points[i]), 0.0f, 1e-5f) << k;
            ASSERT_NEAR(glm::length(ma.normals[i] - mb.normals[i]), 0.0f, 1e-4f) << k;
        }
        std::vector<float> fa, fb, va, vb;
        const size_t values = perLevel.faceVarying[0].valueCount;
        ASSERT_TRUE(a->refineFaceVarying(0, st.data(), values, 2, &fa));
        ASSERT_TRUE(b->refineFaceVarying(0, st.data(), values, 2, &fb));
        ASSERT_TRUE(a->refineVarying(&c.cage.points[0].x, c.cage.points.size(), 3, &va));
        ASSERT_TRUE(b->refineVarying(&c.cage.points[0].x, c.cage.points.size(), 3, &vb));
        ASSERT_EQ(fa.size(), fb.size());
        for (size_t i = 0; i < fa.size(); ++i) ASSERT_NEAR(fa[i], fb[i], 1e-4f) << k;
        ASSERT_EQ(va.size(), vb.size());
        for (size_t i = 0; i < va.size(); ++i) ASSERT_NEAR(va[i], vb[i], 1e-5f) << k;
    }
}

// The record keeps face-varying primvars as values + the shared corner map: gathering through
// faceVaryingCorners() must give exactly refineFaceVarying()'s per-corner floats, at every
// level (0 = the cage) and in linear and smooth modes.
TEST(SubdivPrimvars, FaceVaryingValuesThroughTheCornerMapEqualThePerCornerGather) {
    Cage g = test::grid(3);
    std::vector<float> st;
    FaceVaryingChannel ch = islands(g, &st);
    for (int level : {0, 1, 3})
        for (const char* mode : {"all", "cornersPlus1"}) {
            hd::SubdivTags tags;
            tags.faceVaryingLinearInterpolation = mode;
            BuildOptions o{level};
            o.faceVarying = {ch};
            auto t = make(g, o, tags);
            std::vector<float> perCorner, values;
            ASSERT_TRUE(t->refineFaceVarying(0, st.data(), ch.valueCount, 2, &perCorner));
            ASSERT_TRUE(t->refineFaceVaryingValues(0, st.data(), ch.valueCount, 2, &values));
            auto corners = t->faceVaryingCorners(0);
            ASSERT_TRUE(corners);
            ASSERT_EQ(corners->size(), 3 * t->triangleCount());
            ASSERT_EQ(perCorner.size(), 2 * corners->size());
            for (size_t k = 0; k < corners->size(); ++k) {
                const size_t v = size_t((*corners)[k]);
                ASSERT_LT(2 * v + 1, values.size());
                ASSERT_EQ(perCorner[2 * k], values[2 * v]) << level << mode << k;
                ASSERT_EQ(perCorner[2 * k + 1], values[2 * v + 1]) << level << mode << k;
            }
        }
    EXPECT_FALSE(make(g, BuildOptions{1})->faceVaryingCorners(0));
}
