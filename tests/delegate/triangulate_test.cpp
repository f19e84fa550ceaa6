#include "delegate/triangulate.h"

#include <gtest/gtest.h>

using namespace principled;

TEST(Triangulate, FansQuadsAndNgons) {
    hd::MeshTopology t;
    t.faceVertexCounts = {4, 5, 3};
    t.faceVertexIndices = {0, 1, 2, 3, 0, 1, 2, 3, 4, 2, 3, 4};
    embree::Triangulation out;
    std::string err;
    ASSERT_TRUE(embree::triangulate(t, 5, &out, &err)) << err;
    ASSERT_EQ(out.triangles.size(), 2u + 3u + 1u);
    EXPECT_EQ(out.triangles[0], glm::uvec3(0, 1, 2));
    EXPECT_EQ(out.triangles[1], glm::uvec3(0, 2, 3));
    EXPECT_EQ(out.triangleFace, (std::vector<int>{0, 0, 1, 1, 1, 2}));
    EXPECT_EQ(out.corners[5], glm::uvec3(9, 10, 11));
    EXPECT_EQ(out.skippedFaces, 0);
}

TEST(Triangulate, LeftHandedFlipsWindingAndHolesAreSkipped) {
    hd::MeshTopology t;
    t.faceVertexCounts = {3, 3};
    t.faceVertexIndices = {0, 1, 2, 2, 1, 0};
    t.orientation = hd::Token("leftHanded");
    t.holeIndices = {1};
    embree::Triangulation out;
    std::string err;
    ASSERT_TRUE(embree::triangulate(t, 3, &out, &err));
    ASSERT_EQ(out.triangles.size(), 1u);
    EXPECT_EQ(out.triangles[0], glm::uvec3(0, 2, 1));
    EXPECT_EQ(out.skippedFaces, 0);  // a hole is not a problem
}

TEST(Triangulate, BadFacesAreSkippedAndCounted) {
    hd::MeshTopology t;
    t.faceVertexCounts = {3, 2, 3};
    t.faceVertexIndices = {0, 1, 2, 0, 1, 0, 1, 99};
    embree::Triangulation out;
    std::string err;
    ASSERT_TRUE(embree::triangulate(t, 3, &out, &err));
    EXPECT_EQ(out.triangles.size(), 1u);
    EXPECT_EQ(out.skippedFaces, 2);
    EXPECT_NE(out.firstProblem.find("face 1"), std::string::npos);
}

TEST(Triangulate, InconsistentCountsAreAnError) {
    hd::MeshTopology t;
    t.faceVertexCounts = {4};
    t.faceVertexIndices = {0, 1, 2};
    embree::Triangulation out;
    std::string err;
    EXPECT_FALSE(embree::triangulate(t, 4, &out, &err));
    EXPECT_NE(err.find("sum to 4"), std::string::npos);
    t.faceVertexCounts = {-1};
    EXPECT_FALSE(embree::triangulate(t, 4, &out, &err));
}

namespace {

// Total area of the triangles (unsigned, in the xy plane) and the signed sum (winding).
std::pair<double, double> areas(const embree::Triangulation& t, const std::vector<glm::vec3>& p) {
    double total = 0, signedSum = 0;
    for (const glm::uvec3& tri : t.triangles) {
        const glm::vec3 a = p[tri.x], b = p[tri.y], c = p[tri.z];
        const double s = 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
        total += std::abs(s);
        signedSum += s;
    }
    return {total, signedSum};
}

bool covers(const embree::Triangulation& t, const std::vector<glm::vec3>& p, glm::vec2 q) {
    for (const glm::uvec3& tri : t.triangles) {
        const glm::vec2 a(p[tri.x]), b(p[tri.y]), c(p[tri.z]);
        auto side = [&](glm::vec2 u, glm::vec2 v) { return (v.x - u.x) * (q.y - u.y) - (v.y - u.y) * (q.x - u.x); };
        const float s0 = side(a, b), s1 = side(b, c), s2 = side(c, a);
        if ((s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0)) return true;
    }
    return false;
}

}  // namespace

TEST(Triangulate, ConcaveFacesAreEarClippedInTheirPlane) {
    // A "C" (8 corners, notch opening to +x, area 3 x 3 - 2 x 1 = 7): fanned from corner 0 it
    // covered the notch; ear-clipped, its triangles tile the C exactly, with the authored
    // winding. A dart (concave quad) likewise. Then the same C tilted out of the xy plane.
    std::vector<glm::vec3> c = {{0, 0, 0}, {3, 0, 0}, {3, 1, 0}, {1, 1, 0}, {1, 2, 0}, {3, 2, 0}, {3, 3, 0}, {0, 3, 0}};
    hd::MeshTopology t;
    t.faceVertexCounts = {8};
    t.faceVertexIndices = {0, 1, 2, 3, 4, 5, 6, 7};
    embree::Triangulation out;
    std::string err;
    ASSERT_TRUE(embree::triangulate(t, c.size(), &out, &err, c.data())) << err;
    EXPECT_EQ(out.triangles.size(), 6u);
    auto [total, signedSum] = areas(out, c);
    EXPECT_NEAR(total, 7.0, 1e-5);
    EXPECT_NEAR(signedSum, 7.0, 1e-5);  // counter-clockwise, as authored
    EXPECT_FALSE(covers(out, c, {2.0f, 1.5f})) << "the notch is filled";
    EXPECT_TRUE(covers(out, c, {0.5f, 1.5f}));
    // Fanned (no points), the notch was covered: the case above fails without ear clipping.
    embree::Triangulation fan;
    ASSERT_TRUE(embree::triangulate(t, c.size(), &fan, &err));
    EXPECT_TRUE(covers(fan, c, {2.0f, 1.5f}));

    std::vector<glm::vec3> dart = {{0, 0, 0}, {2, 1, 0}, {4, 0, 0}, {2, 3, 0}};  // reflex at 1
    t.faceVertexCounts = {4};
    t.faceVertexIndices = {1, 2, 3, 0};  // starts at the reflex corner's neighbour... then fans badly
    ASSERT_TRUE(embree::triangulate(t, dart.size(), &out, &err, dart.data()));
    EXPECT_NEAR(areas(out, dart).first, 4.0, 1e-5);  // 4 x 3 / 2 - 4 x 1 / 2
    EXPECT_NEAR(areas(out, dart).second, 4.0, 1e-5);

    // Convex faces keep the fan from corner 0 (images of convex meshes do not change).
    std::vector<glm::vec3> square = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    t.faceVertexIndices = {0, 1, 2, 3};
    ASSERT_TRUE(embree::triangulate(t, square.size(), &out, &err, square.data()));
    EXPECT_EQ(out.triangles[0], glm::uvec3(0, 1, 2));
    EXPECT_EQ(out.triangles[1], glm::uvec3(0, 2, 3));

    // The C tilted 60 degrees about x: the same tiling in its own plane.
    std::vector<glm::vec3> tilted;
    for (const glm::vec3& p : c) tilted.push_back({p.x, 0.5f * p.y, 0.8660254f * p.y});
    t.faceVertexCounts = {8};
    t.faceVertexIndices = {0, 1, 2, 3, 4, 5, 6, 7};
    ASSERT_TRUE(embree::triangulate(t, tilted.size(), &out, &err, tilted.data()));
    double area3 = 0;
    for (const glm::uvec3& tri : out.triangles)
        area3 += 0.5 * glm::length(glm::cross(tilted[tri.y] - tilted[tri.x], tilted[tri.z] - tilted[tri.x]));
    EXPECT_NEAR(area3, 7.0, 1e-4);
}

TEST(Triangulate, HoleIndicesThatNameNoFaceAreCounted) {
    hd::MeshTopology t;
    t.faceVertexCounts = {3};
    t.faceVertexIndices = {0, 1, 2};
    t.holeIndices = {7, -1, 0};
    embree::Triangulation out;
    std::string err;
    ASSERT_TRUE(embree::triangulate(t, 3, &out, &err));
    EXPECT_EQ(out.badHoles, 2);
    EXPECT_TRUE(out.triangles.empty());
}

TEST(Triangulate, DartsAndSelfTouchingRingsStayInsideTheirFace) {
    std::string err;
    embree::Triangulation out;
    hd::MeshTopology t;
    // A dart whose reflex corner is 1: the fan's diagonal (0, 2) would lie outside.
    std::vector<glm::vec3> dart = {{0, 0, 0}, {2, 1, 0}, {4, 0, 0}, {2, 3, 0}};
    t.faceVertexCounts = {4};
    t.faceVertexIndices = {0, 1, 2, 3};
    ASSERT_TRUE(embree::triangulate(t, dart.size(), &out, &err, dart.data()));
    EXPECT_NEAR(areas(out, dart).first, 4.0, 1e-5);
    EXPECT_NEAR(areas(out, dart).second, 4.0, 1e-5);
    // Two unit squares touching at (1, 1), one ring passing that point twice: every triangle
    // inside (areas sum to 2, not 3 with one outside and one inverted).
    std::vector<glm::vec3> bow = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {2, 1, 0}, {2, 2, 0}, {1, 2, 0}, {1, 1, 0}, {0, 1, 0}};
    t.faceVertexCounts = {8};
    t.faceVertexIndices = {0, 1, 2, 3, 4, 5, 6, 7};
    ASSERT_TRUE(embree::triangulate(t, bow.size(), &out, &err, bow.data()));
    EXPECT_NEAR(areas(out, bow).first, 2.0, 1e-5);
    EXPECT_FALSE(covers(out, bow, {0.5f, 1.5f}));
    EXPECT_FALSE(covers(out, bow, {1.5f, 0.5f}));
}
