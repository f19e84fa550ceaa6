// SPDX-License-Identifier: Apache-2.0
#include "delegate/subdiv/sharpnessTags.h"

#include <gtest/gtest.h>

using namespace principled;
using namespace principled::subdiv;

TEST(SharpnessTags, PerCreaseAndPerEdgeSharpness) {
    hd::SubdivTags t;
    t.creaseIndices = {0, 1, 2, 5, 6};
    t.creaseLengths = {3, 2};
    t.creaseSharpnesses = {2.0f, 4.0f};  // per crease
    std::vector<std::string> w;
    SharpnessTags s = sharpnessTags(t, 8, &w);
    EXPECT_TRUE(w.empty());
    EXPECT_EQ(s.edgeVertices, (std::vector<int>{0, 1, 1, 2, 5, 6}));
    EXPECT_EQ(s.edgeSharpness, (std::vector<float>{2, 2, 4}));
    t.creaseSharpnesses = {1.0f, 3.0f, 4.0f};  // per edge
    s = sharpnessTags(t, 8, &w);
    EXPECT_TRUE(w.empty());
    EXPECT_EQ(s.edgeSharpness, (std::vector<float>{1, 3, 4}));
}

TEST(SharpnessTags, BadTagsBecomeWarnings) {
    hd::SubdivTags t;
    t.creaseIndices = {0, 1, 2};
    t.creaseLengths = {3};
    t.creaseSharpnesses = {1, 2, 3, 4};
    t.cornerIndices = {1, 9, 2};
    t.cornerSharpnesses = {10, 10, -1};
    std::vector<std::string> w;
    SharpnessTags s = sharpnessTags(t, 4, &w);
    EXPECT_TRUE(s.edgeVertices.empty());
    EXPECT_EQ(s.cornerVertices, (std::vector<int>{1}));
    EXPECT_EQ(w.size(), 3u);
    t = {};
    t.creaseIndices = {0, 1, 7};
    t.creaseLengths = {3};
    t.creaseSharpnesses = {1};
    w.clear();
    s = sharpnessTags(t, 4, &w);
    EXPECT_EQ(s.edgeVertices, (std::vector<int>{0, 1}));  // only the bad edge is dropped
    EXPECT_EQ(w.size(), 1u);
    t.creaseLengths = {1, 2};
    w.clear();
    s = sharpnessTags(t, 4, &w);
    EXPECT_TRUE(s.edgeVertices.empty());
    EXPECT_EQ(w.size(), 1u);
}
