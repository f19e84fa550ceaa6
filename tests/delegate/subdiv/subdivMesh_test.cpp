// SPDX-License-Identifier: Apache-2.0
#include "delegate/subdiv/subdivMesh.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "tests/delegate/subdiv/subdivTestMeshes.h"

using namespace principled;
using namespace principled::subdiv;

TEST(SubdivMesh, RebuildsOnlyWhenTopologyOrOptionsChange) {
    test::Cage c = test::cube();
    SubdivMesh prim;
    std::string err;
    const uint64_t before = SubdivTopology::refinerBuildCount();
    ASSERT_TRUE(prim.update(c.topology, {}, c.points, BuildOptions{2}, &err)) << err;
    EXPECT_TRUE(prim.rebuiltLastUpdate());
    EXPECT_EQ(prim.mesh().triangles.size(), 2u * 6u * 16u);
    EXPECT_EQ(SubdivTopology::refinerBuildCount(), before + 1);

    // New pose: re-posed, not rebuilt.
    for (glm::vec3& p : c.points) p *= 2.0f;
    ASSERT_TRUE(prim.update(c.topology, {}, c.points, BuildOptions{2}, &err));
    EXPECT_FALSE(prim.rebuiltLastUpdate());
    EXPECT_EQ(SubdivTopology::refinerBuildCount(), before + 1);
    float extent = 0.0f;
    for (const glm::vec3& p : prim.mesh().points) extent = std::max(extent, p.x);
    EXPECT_NEAR(extent, 34.0f / 81.0f * 2.0f, 1e-5f);  // the face-centre limit, scaled

    // Level, tags or topology change: rebuilt.
    ASSERT_TRUE(prim.update(c.topology, {}, c.points, BuildOptions{1}, &err));
    EXPECT_TRUE(prim.rebuiltLastUpdate());
    hd::SubdivTags tags;
    tags.cornerIndices = {0};
    tags.cornerSharpnesses = {10};
    ASSERT_TRUE(prim.update(c.topology, tags, c.points, BuildOptions{1}, &err));
    EXPECT_TRUE(prim.rebuiltLastUpdate());
    c.topology.holeIndices = {3};
    ASSERT_TRUE(prim.update(c.topology, tags, c.points, BuildOptions{1}, &err));
    EXPECT_TRUE(prim.rebuiltLastUpdate());
    EXPECT_EQ(prim.mesh().triangles.size(), 2u * 5u * 4u);
    EXPECT_EQ(SubdivTopology::refinerBuildCount(), before + 4);

    // Bad topology: an error and an empty state; a good update afterwards recovers.
    hd::MeshTopology bad = c.topology;
    bad.faceVertexIndices[0] = 99;
    EXPECT_FALSE(prim.update(bad, tags, c.points, BuildOptions{1}, &err));
    EXPECT_EQ(prim.topology(), nullptr);
    EXPECT_TRUE(prim.mesh().points.empty());
    EXPECT_TRUE(prim.update(c.topology, tags, c.points, BuildOptions{1}, &err));
}
