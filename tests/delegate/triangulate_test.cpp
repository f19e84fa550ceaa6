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
