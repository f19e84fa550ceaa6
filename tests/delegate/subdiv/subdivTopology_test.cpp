// SPDX-License-Identifier: Apache-2.0
#include "delegate/subdiv/subdivTopology.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <thread>

#include "tests/delegate/subdiv/subdivTestMeshes.h"

using namespace principled;
using namespace principled::subdiv;
using principled::subdiv::test::Cage;

namespace {

struct Built {
    std::unique_ptr<SubdivTopology> topology;
    RefinedMesh mesh;
};

Built refineCage(const Cage& cage, int level, const hd::SubdivTags& tags = {}) {
    BuildOptions o;
    o.level = level;
    std::string err;
    Built b;
    b.topology = SubdivTopology::create(cage.topology, tags, cage.points.size(), o, &err);
    EXPECT_TRUE(b.topology) << err;
    if (b.topology) {
        EXPECT_TRUE(b.topology->refine(cage.points, &b.mesh, &err)) << err;
    }
    return b;
}

glm::vec3 triangleNormal(const RefinedMesh& m, size_t t) {
    const glm::uvec3& i = m.triangles[t];
    return glm::cross(m.points[i.y] - m.points[i.x], m.points[i.z] - m.points[i.x]);
}

/// Every normal is unit length and agrees with the winding of every triangle around it.
void expectNormalsFollowWinding(const RefinedMesh& m) {
    ASSERT_EQ(m.normals.size(), m.points.size());
    for (const glm::vec3& n : m.normals) ASSERT_NEAR(glm::length(n), 1.0f, 1e-4f);
    for (size_t t = 0; t < m.triangles.size(); ++t) {
        glm::vec3 fn = glm::normalize(triangleNormal(m, t));
        for (int k = 0; k < 3; ++k)
            ASSERT_GT(glm::dot(fn, m.normals[m.triangles[t][k]]), 0.0f) << "triangle " << t;
    }
}

bool hasPointNear(const RefinedMesh& m, glm::vec3 p, float eps) {
    return std::any_of(m.points.begin(), m.points.end(),
                       [&](const glm::vec3& q) { return glm::length(q - p) < eps; });
}

}  // namespace

TEST(SubdivTopology, CubeCatmullClarkFaceCountsPerLevel) {
    for (int level = 1; level <= 3; ++level) {
        Built b = refineCage(test::cube(), level);
        const size_t quads = 6u << (2 * level);  // 6 * 4^L
        EXPECT_EQ(b.mesh.triangles.size(), 2 * quads) << "level " << level;
        EXPECT_EQ(b.topology->scheme(), Scheme::CatmullClark);
        // V - E + F = 2 on the closed refined cube: V = F + 2 for an all-quad sphere.
        EXPECT_EQ(b.mesh.points.size(), quads + 2);
        for (int f : b.mesh.triangleFace) ASSERT_TRUE(f >= 0 && f < 6);
    }
}

TEST(SubdivTopology, CubeLimitMatchesAnalyticValues) {
    // Limit mask of a valence-n vertex of an all-quad mesh (Halstead et al. 1993, eq. 4):
    //   v_inf = (n^2 v + 4 sum(e_i) + sum(f_i)) / (n (n + 5)).
    // Cube corner (n = 3, cage level): (9*0.5 + 4*0.5 - 0.5) / 24 = 0.25 per axis.
    // +z face centre (n = 4, level 1: v = 0.5, edge points z = 3/8, corners z = 5/18):
    //   (16*0.5 + 4*4*3/8 + 4*5/18) / 36 = 34/81.
    for (int level = 1; level <= 3; ++level) {
        Built b = refineCage(test::cube(), level);
        EXPECT_TRUE(hasPointNear(b.mesh, glm::vec3(0.25f), 1e-5f)) << "level " << level;
        EXPECT_TRUE(hasPointNear(b.mesh, glm::vec3(0, 0, 34.0f / 81.0f), 1e-5f));
        EXPECT_TRUE(hasPointNear(b.mesh, glm::vec3(-0.25f), 1e-5f));
    }
}

TEST(SubdivTopology, CubeLimitIsSymmetricInsideTheCageWithOutwardNormals) {
    Built b = refineCage(test::cube(), 3);
    for (size_t i = 0; i < b.mesh.points.size(); ++i) {
        const glm::vec3& p = b.mesh.points[i];
        ASSERT_LE(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}), 0.5f + 1e-6f);
        ASSERT_TRUE(hasPointNear(b.mesh, -p, 1e-5f));                        // point symmetry
        ASSERT_TRUE(hasPointNear(b.mesh, glm::vec3(p.y, p.z, p.x), 1e-5f));  // axis rotation
        ASSERT_GT(glm::dot(b.mesh.normals[i], p), 0.0f);  // outward on a convex surface
    }
    expectNormalsFollowWinding(b.mesh);
    // At the corner limit point the normal is the diagonal.
    for (size_t i = 0; i < b.mesh.points.size(); ++i)
        if (glm::length(b.mesh.points[i] - glm::vec3(0.25f)) < 1e-5f) {
            EXPECT_NEAR(glm::dot(b.mesh.normals[i], glm::normalize(glm::vec3(1))), 1.0f, 1e-5f);
        }
}

TEST(SubdivTopology, PlanarGridStaysPlanarWithPlaneNormal) {
    Cage g = test::grid(4);
    Built b = refineCage(g, 2);
    EXPECT_EQ(b.mesh.triangles.size(), 2u * 16u * 16u);
    for (size_t i = 0; i < b.mesh.points.size(); ++i) {
        ASSERT_NEAR(b.mesh.points[i].z, 0.0f, 1e-6f);
        ASSERT_NEAR(b.mesh.normals[i].z, 1.0f, 1e-5f);
    }
    expectNormalsFollowWinding(b.mesh);
    // edgeAndCorner (USD's default) keeps the grid's corners; edgeOnly rounds them off.
    EXPECT_TRUE(hasPointNear(b.mesh, glm::vec3(0, 0, 0), 1e-6f));
    hd::SubdivTags edgeOnly;
    edgeOnly.interpolateBoundary = "edgeOnly";
    Built e = refineCage(g, 2, edgeOnly);
    EXPECT_FALSE(hasPointNear(e.mesh, glm::vec3(0, 0, 0), 1e-3f));
    for (const glm::vec3& n : e.mesh.normals) ASSERT_NEAR(n.z, 1.0f, 1e-5f);
    expectNormalsFollowWinding(e.mesh);
}

TEST(SubdivTopology, BoundaryNoneDropsBoundaryFaces) {
    hd::SubdivTags none;
    none.interpolateBoundary = "none";
    Built b = refineCage(test::grid(3), 2, none);
    EXPECT_EQ(b.mesh.triangles.size(), 2u * 16u);  // only the centre face survives
    for (int f : b.mesh.triangleFace) EXPECT_EQ(f, 4);
}

TEST(SubdivTopology, LeftHandedFlipsNormals) {
    Cage g = test::grid(3);
    g.topology.orientation = "leftHanded";
    Built b = refineCage(g, 2);
    for (const glm::vec3& n : b.mesh.normals) ASSERT_NEAR(n.z, -1.0f, 1e-5f);
    expectNormalsFollowWinding(b.mesh);
    for (const char* scheme : {"bilinear", "loop"}) {  // loop falls back to catmullClark here
        Cage s = g;
        s.topology.scheme = scheme;
        Built bs = refineCage(s, 2);
        for (const glm::vec3& n : bs.mesh.normals) ASSERT_NEAR(n.z, -1.0f, 1e-5f) << scheme;
        expectNormalsFollowWinding(bs.mesh);
    }
    Cage c = test::cube();
    c.topology.orientation = "leftHanded";
    Built lc = refineCage(c, 2);
    for (size_t i = 0; i < lc.mesh.points.size(); ++i)
        ASSERT_LT(glm::dot(lc.mesh.normals[i], lc.mesh.points[i]), 0.0f);
    expectNormalsFollowWinding(lc.mesh);
}

TEST(SubdivTopology, InfinitelySharpCreaseStaysOnTheCageEdges) {
    // The top face's border as one closed chain (per-crease sharpness), its corners pinned:
    // the crease limit curve is a B-spline of collinear points, so it stays on the cage edges.
    hd::SubdivTags tags;
    tags.creaseIndices = {0, 1, 3, 2, 0};
    tags.creaseLengths = {5};
    tags.creaseSharpnesses = {10.0f};
    tags.cornerIndices = {0, 1, 2, 3};
    tags.cornerSharpnesses = {10, 10, 10, 10};
    const int level = 3;
    Built b = refineCage(test::cube(), level, tags);
    EXPECT_TRUE(b.topology->warnings().empty());
    int onEdge = 0;
    for (const glm::vec3& p : b.mesh.points) {
        ASSERT_LE(p.z, 0.5f + 1e-6f);
        bool atTop = std::abs(p.z - 0.5f) < 1e-5f;
        bool onRim =
            std::abs(std::abs(p.x) - 0.5f) < 1e-5f || std::abs(std::abs(p.y) - 0.5f) < 1e-5f;
        if (atTop && onRim) ++onEdge;
    }
    EXPECT_EQ(onEdge, 4 << level);  // every refined vertex of the rim: 4 * 2^L
    // The same crease given per edge, as four 2-vertex creases, refines identically.
    hd::SubdivTags perEdge = tags;
    perEdge.creaseLengths = {2, 2, 2, 2};
    perEdge.creaseIndices = {0, 1, 1, 3, 3, 2, 2, 0};
    perEdge.creaseSharpnesses = {10, 10, 10, 10};
    Built e = refineCage(test::cube(), level, perEdge);
    ASSERT_EQ(e.mesh.points.size(), b.mesh.points.size());
    for (size_t i = 0; i < b.mesh.points.size(); ++i)
        ASSERT_NEAR(glm::length(e.mesh.points[i] - b.mesh.points[i]), 0.0f, 1e-6f);
}

TEST(SubdivTopology, CornerSharpnessKeepsTheCornerAndHolesRemoveFaces) {
    hd::SubdivTags tags;
    tags.cornerIndices = {6};
    tags.cornerSharpnesses = {10.0f};
    Built b = refineCage(test::cube(), 2, tags);
    EXPECT_TRUE(hasPointNear(b.mesh, glm::vec3(-0.5f), 1e-6f));
    Built smooth = refineCage(test::cube(), 2);
    EXPECT_FALSE(hasPointNear(smooth.mesh, glm::vec3(-0.5f), 1e-2f));

    Cage holed = test::cube();
    holed.topology.holeIndices = {0};
    Built h = refineCage(holed, 2);
    EXPECT_EQ(h.mesh.triangles.size(), 2u * 5u * 16u);
    for (int f : h.mesh.triangleFace) EXPECT_NE(f, 0);
}

TEST(SubdivTopology, LoopTetrahedronAndFallback) {
    for (int level = 1; level <= 3; ++level) {
        Cage t = test::tetrahedron();
        t.topology.scheme = "loop";
        Built b = refineCage(t, level);
        EXPECT_EQ(b.topology->scheme(), Scheme::Loop);
        EXPECT_EQ(b.mesh.triangles.size(), size_t(4) << (2 * level));
        for (size_t i = 0; i < b.mesh.points.size(); ++i)
            ASSERT_GT(glm::dot(b.mesh.normals[i], b.mesh.points[i]), 0.0f);
        expectNormalsFollowWinding(b.mesh);
    }
    Cage c = test::cube();
    c.topology.scheme = "loop";
    Built b = refineCage(c, 1);
    EXPECT_EQ(b.topology->scheme(), Scheme::CatmullClark);
    EXPECT_FALSE(b.topology->warnings().empty());
    EXPECT_EQ(b.mesh.triangles.size(), 48u);
}

TEST(SubdivTopology, BilinearKeepsPointsOnTheCageFaces) {
    Cage c = test::cube();
    c.topology.scheme = "bilinear";
    Built b = refineCage(c, 2);
    EXPECT_EQ(b.topology->scheme(), Scheme::Bilinear);
    EXPECT_EQ(b.mesh.triangles.size(), 2u * 6u * 16u);
    for (const glm::vec3& p : b.mesh.points)
        ASSERT_NEAR(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}), 0.5f, 1e-6f);
    expectNormalsFollowWinding(b.mesh);
}

TEST(SubdivTopology, LevelZeroAndSchemeNoneGiveTheCage) {
    for (int variant = 0; variant < 2; ++variant) {
        Cage c = test::cube();
        c.topology.holeIndices = {5};
        int level = 2;
        if (variant == 0)
            level = 0;
        else
            c.topology.scheme = "none";
        Built b = refineCage(c, level);
        EXPECT_FALSE(b.topology->subdivided());
        EXPECT_EQ(b.mesh.points, c.points);
        EXPECT_TRUE(b.mesh.normals.empty());
        ASSERT_EQ(b.mesh.triangles.size(), 10u);
        for (size_t t = 0; t < b.mesh.triangles.size(); ++t)  // outward winding
            EXPECT_GT(glm::dot(triangleNormal(b.mesh, t), b.mesh.points[b.mesh.triangles[t].x]),
                      0.0f);
    }
    Cage lh = test::cube();
    lh.topology.orientation = "leftHanded";
    Built b = refineCage(lh, 0);
    for (size_t t = 0; t < b.mesh.triangles.size(); ++t)
        EXPECT_LT(glm::dot(triangleNormal(b.mesh, t), b.mesh.points[b.mesh.triangles[t].x]), 0.0f);
}

TEST(SubdivTopology, ReposingUsesCachedStencilsOnly) {
    Cage c = test::cube();
    Built b = refineCage(c, 3);
    const uint64_t builds = SubdivTopology::refinerBuildCount();
    const glm::vec3 offset(1.5f, -2.0f, 0.25f);
    Cage moved = c;
    for (glm::vec3& p : moved.points) p += offset;
    RefinedMesh out;
    std::string err;
    ASSERT_TRUE(b.topology->refine(moved.points, &out, &err)) << err;
    ASSERT_EQ(out.points.size(), b.mesh.points.size());
    for (size_t i = 0; i < out.points.size(); ++i) {
        ASSERT_NEAR(glm::length(out.points[i] - (b.mesh.points[i] + offset)), 0.0f, 1e-5f);
        ASSERT_NEAR(glm::length(out.normals[i] - b.mesh.normals[i]), 0.0f, 1e-5f);
    }
    EXPECT_EQ(out.triangles, b.mesh.triangles);
    // Re-posing into the same mesh keeps its topology arrays (same id, no copy needed).
    ASSERT_TRUE(b.topology->refine(moved.points, &b.mesh, &err));
    EXPECT_EQ(b.mesh.topologyId, b.topology->id());
    EXPECT_EQ(SubdivTopology::refinerBuildCount(), builds);
    EXPECT_TRUE(b.topology->matches(c.topology, {}, c.points.size(), BuildOptions{3}));
    EXPECT_FALSE(b.topology->matches(c.topology, {}, c.points.size(), BuildOptions{2}));
}

TEST(SubdivTopology, InvalidTopologyIsAnErrorNotACrash) {
    struct Case {
        const char* what;
        std::vector<int> counts, indices;
        size_t points;
    };
    const Case cases[] = {
        {"index out of range", {4}, {0, 1, 2, 9}, 4},
        {"negative index", {3}, {0, -1, 2}, 4},
        {"counts not summing", {4, 4}, {0, 1, 2, 3}, 4},
        {"face of two vertices", {3, 2}, {0, 1, 2, 2, 3}, 4},
        {"negative count", {-3, 3}, {0, 1, 2}, 4},
    };
    for (const Case& k : cases) {
        hd::MeshTopology t;
        t.faceVertexCounts = k.counts;
        t.faceVertexIndices = k.indices;
        for (int level : {0, 2}) {
            std::string err;
            auto topo = SubdivTopology::create(t, {}, k.points, BuildOptions{level}, &err);
            EXPECT_FALSE(topo) << k.what;
            EXPECT_FALSE(err.empty()) << k.what;
        }
    }
    // A wrong point count at re-pose time.
    Built b = refineCage(test::cube(), 1);
    RefinedMesh out;
    std::string err;
    EXPECT_FALSE(b.topology->refine(std::vector<glm::vec3>(7), &out, &err));
    EXPECT_NE(err.find("7 points"), std::string::npos);
    // A level above the face budget is lowered before allocating: 6 * 4^3 = 384 <= 1000.
    BuildOptions huge{8};
    huge.maxRefinedFaces = 1000;
    Cage c = test::cube();
    auto lowered = SubdivTopology::create(c.topology, {}, 8, huge, &err);
    ASSERT_TRUE(lowered) << err;
    EXPECT_EQ(lowered->level(), 3);
    ASSERT_EQ(lowered->warnings().size(), 1u);
    EXPECT_NE(lowered->warnings()[0].find("using level 3"), std::string::npos);
    huge.maxRefinedFaces = 5;  // not even the cage fits: level 0 is always allowed
    lowered = SubdivTopology::create(c.topology, {}, 8, huge, &err);
    ASSERT_TRUE(lowered) << err;
    EXPECT_EQ(lowered->level(), 0);
    EXPECT_EQ(lowered->triangleCount(), 12u);
}

TEST(SubdivTopology, EmptyMeshesGiveNoTriangles) {
    for (size_t points : {size_t(0), size_t(5)}) {
        for (int level : {0, 2}) {
            std::string err;
            auto t = SubdivTopology::create({}, {}, points, BuildOptions{level}, &err);
            if (!t) {
                EXPECT_FALSE(err.empty());
                continue;
            }
            RefinedMesh m;
            EXPECT_TRUE(t->refine(std::vector<glm::vec3>(points), &m, &err)) << err;
            EXPECT_TRUE(m.triangles.empty());
        }
    }
}

TEST(SubdivTopology, NonManifoldAndDegenerateInputDoNotCrash) {
    // Three quads sharing one edge (non-manifold), a face repeating a vertex, an unused point.
    hd::MeshTopology t;
    t.faceVertexCounts = {4, 4, 4, 4};
    t.faceVertexIndices = {0, 1, 2, 3, 1, 0, 4, 5, 0, 1, 6, 7, 2, 2, 8, 3};
    std::vector<glm::vec3> p = {{0, 0, 0},  {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, -1, 0},
                                {1, -1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 2, 0}, {5, 5, 5}};
    std::string err;
    auto topo = SubdivTopology::create(t, {}, p.size(), BuildOptions{2}, &err);
    if (topo) {
        RefinedMesh m;
        ASSERT_TRUE(topo->refine(p, &m, &err)) << err;
        for (const glm::vec3& q : m.points) ASSERT_TRUE(std::isfinite(q.x + q.y + q.z));
        for (const glm::uvec3& tri : m.triangles)
            ASSERT_LT(std::max({tri.x, tri.y, tri.z}), m.points.size());
    } else {
        EXPECT_FALSE(err.empty());
    }
}

TEST(SubdivTopology, BadTagsAreWarningsAndUnknownTokensUseDefaults) {
    hd::SubdivTags tags;
    tags.creaseIndices = {0, 1, 2};
    tags.creaseLengths = {3};
    tags.creaseSharpnesses = {1, 2, 3};  // neither per crease (1) nor per edge (2)
    tags.cornerIndices = {99};
    tags.cornerSharpnesses = {10};
    tags.interpolateBoundary = "sometimes";
    Cage c = test::cube();
    c.topology.holeIndices = {42};
    Built b = refineCage(c, 1, tags);
    EXPECT_GE(b.topology->warnings().size(), 4u);
    EXPECT_EQ(b.mesh.triangles.size(), 48u);
}

TEST(SubdivTopology, RandomTopologiesNeverCrash) {
    // Deterministic random soup: repeated and out-of-range indices, tiny faces, non-manifold
    // fans, random tags and face-varying channels. Either an error or a consistent result.
    uint32_t state = 12345u;
    auto next = [&state](uint32_t n) {  // xorshift32 (Marsaglia 2003)
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        return state % n;
    };
    const char* schemes[] = {"catmullClark", "loop", "bilinear", "none"};
    const char* boundaries[] = {"none", "edgeOnly", "edgeAndCorner"};
    const char* fvarModes[] = {"none",         "cornersOnly", "cornersPlus1",
                               "cornersPlus2", "boundaries",  "all"};
    int built = 0;
    for (int iter = 0; iter < 1000; ++iter) {
        const int pointCount = 1 + int(next(10));
        hd::MeshTopology t;
        t.scheme = schemes[next(4)];
        if (next(4) == 0) t.orientation = "leftHanded";
        const int faces = 1 + int(next(8));
        for (int f = 0; f < faces; ++f) {
            int n = next(10) == 0 ? int(next(3)) : 3 + int(next(3));
            t.faceVertexCounts.push_back(n);
            for (int k = 0; k < n; ++k)
                t.faceVertexIndices.push_back(next(30) == 0 ? pointCount
                                                            : int(next(uint32_t(pointCount))));
        }
        if (next(3) == 0) t.holeIndices.push_back(int(next(uint32_t(faces + 1))));
        hd::SubdivTags tags;
        tags.interpolateBoundary = boundaries[next(3)];
        tags.faceVaryingLinearInterpolation = fvarModes[next(6)];
        if (next(2)) {
            int len = 2 + int(next(3));
            tags.creaseLengths = {len};
            for (int k = 0; k < len; ++k)
                tags.creaseIndices.push_back(int(next(uint32_t(pointCount))));
            tags.creaseSharpnesses = {float(next(12))};
        }
        if (next(2)) {
            tags.cornerIndices = {int(next(uint32_t(pointCount)))};
            tags.cornerSharpnesses = {float(next(12))};
        }
        BuildOptions o{int(next(3))};
        FaceVaryingChannel ch;
        ch.valueCount = 1 + next(6);
        for (size_t k = 0; k < t.faceVertexIndices.size(); ++k)
            ch.indices.push_back(int(next(uint32_t(ch.valueCount))));
        o.faceVarying = {ch};
        std::vector<glm::vec3> points(static_cast<size_t>(pointCount));
        for (glm::vec3& p : points)
            p = glm::vec3(float(next(100)), float(next(100)), float(next(100))) * 0.01f;

        std::string err;
        auto topo = SubdivTopology::create(t, tags, points.size(), o, &err);
        if (!topo) {
            ASSERT_FALSE(err.empty()) << "iteration " << iter;
            // Only input errors are acceptable, never a failure of our own stencil recording.
            ASSERT_EQ(err.find("stencils"), std::string::npos) << err;
            continue;
        }
        ++built;
        RefinedMesh m;
        ASSERT_TRUE(topo->refine(points, &m, &err)) << err;
        ASSERT_EQ(m.triangleFace.size(), m.triangles.size());
        for (const glm::uvec3& tri : m.triangles)
            ASSERT_LT(std::max({tri.x, tri.y, tri.z}), m.points.size());
        for (int f : m.triangleFace) ASSERT_TRUE(f >= 0 && f < faces);
        for (const glm::vec3& q : m.points) ASSERT_TRUE(std::isfinite(q.x + q.y + q.z)) << iter;
        for (const glm::vec3& q : m.normals) ASSERT_TRUE(std::isfinite(q.x + q.y + q.z)) << iter;
        if (topo->faceVaryingAvailable(0)) {
            std::vector<float> values(ch.valueCount * 2, 0.5f), out;
            ASSERT_TRUE(topo->refineFaceVarying(0, values.data(), ch.valueCount, 2, &out));
            ASSERT_EQ(out.size(), m.triangles.size() * 3 * 2);
            for (float v : out) ASSERT_NEAR(v, 0.5f, 1e-4f);  // weights sum to 1
        }
    }
    EXPECT_GT(built, 250);
}

TEST(SubdivTopology, NgonsAndTrianglesRefineWithOutwardNormals) {
    // Pentagonal prism: two pentagons (extraordinary face centres) and five quads.
    Cage prism;
    for (int ring = 0; ring < 2; ++ring)
        for (int k = 0; k < 5; ++k) {
            float a = 2.0f * 3.14159265f * float(k) / 5.0f;
            prism.points.emplace_back(std::cos(a), std::sin(a), ring == 0 ? -0.5f : 0.5f);
        }
    prism.topology.faceVertexCounts = {5, 5, 4, 4, 4, 4, 4};
    prism.topology.faceVertexIndices = {4, 3, 2, 1, 0, 5, 6, 7, 8, 9};
    for (int k = 0; k < 5; ++k)
        for (int v : {k, (k + 1) % 5, 5 + (k + 1) % 5, 5 + k})
            prism.topology.faceVertexIndices.push_back(v);
    Built b = refineCage(prism, 2);
    EXPECT_EQ(b.mesh.triangles.size(), 2u * (5 + 5 + 5 * 4) * 4);  // n quads per n-gon, then x4
    for (size_t i = 0; i < b.mesh.points.size(); ++i)
        ASSERT_GT(glm::dot(b.mesh.normals[i], b.mesh.points[i]), 0.0f);
    expectNormalsFollowWinding(b.mesh);

    // A cube cut into triangles: both triangle rules give a closed, symmetric, outward surface,
    // and "smooth" differs from "catmullClark".
    Cage tri = test::cube();
    tri.topology.faceVertexCounts.assign(12, 3);
    std::vector<int> idx;
    const std::vector<int> quads = tri.topology.faceVertexIndices;
    for (int f = 0; f < 6; ++f) {
        const int* q = &quads[size_t(4 * f)];
        for (int v : {q[0], q[1], q[2], q[0], q[2], q[3]}) idx.push_back(v);
    }
    tri.topology.faceVertexIndices = idx;
    hd::SubdivTags smoothRule;
    smoothRule.triangleSubdivisionRule = "smooth";
    Built catmark = refineCage(tri, 2), smooth = refineCage(tri, 2, smoothRule);
    ASSERT_EQ(catmark.mesh.points.size(), smooth.mesh.points.size());
    float difference = 0.0f;
    for (size_t i = 0; i < catmark.mesh.points.size(); ++i) {
        difference =
            std::max(difference, glm::length(catmark.mesh.points[i] - smooth.mesh.points[i]));
        ASSERT_GT(glm::dot(catmark.mesh.normals[i], catmark.mesh.points[i]), 0.0f);
        ASSERT_GT(glm::dot(smooth.mesh.normals[i], smooth.mesh.points[i]), 0.0f);
    }
    EXPECT_GT(difference, 1e-3f);
    expectNormalsFollowWinding(catmark.mesh);
    expectNormalsFollowWinding(smooth.mesh);
}

TEST(SubdivTopology, ConcurrentReposingOfOneTopologyMatchesSerial) {
    Cage c = test::grid(24);  // 24*24*16 quads: large enough for the parallel paths
    Built b = refineCage(c, 2);
    std::vector<std::vector<glm::vec3>> poses(4, c.points);
    for (size_t k = 0; k < poses.size(); ++k)
        for (glm::vec3& p : poses[k]) p.z = 0.1f * float(k) * std::sin(p.x + float(k));
    std::vector<RefinedMesh> serial(poses.size()), parallel(poses.size());
    for (size_t k = 0; k < poses.size(); ++k) ASSERT_TRUE(b.topology->refine(poses[k], &serial[k]));
    std::vector<std::thread> threads;
    for (size_t k = 0; k < poses.size(); ++k)
        threads.emplace_back([&, k] { b.topology->refine(poses[k], &parallel[k]); });
    for (auto& t : threads) t.join();
    for (size_t k = 0; k < poses.size(); ++k) {
        EXPECT_EQ(parallel[k].points, serial[k].points);
        EXPECT_EQ(parallel[k].normals, serial[k].normals);
    }
}
