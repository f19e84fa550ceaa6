// SPDX-License-Identifier: Apache-2.0
#include "delegate/subdiv/sharpnessTags.h"

#include <gtest/gtest.h>

#include <limits>

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

TEST(SharpnessTags, InfiniteSharpnessIsOpenSubdivsTenAndEachBadEdgeIsNotAWarning) {
    hd::SubdivTags t;
    t.creaseIndices = {0, 1, 2, 3, 0};
    t.creaseLengths = {5};
    t.creaseSharpnesses = {std::numeric_limits<float>::infinity()};
    std::vector<std::string> w;
    SharpnessTags s = sharpnessTags(t, 4, &w);
    EXPECT_EQ(s.edgeSharpness, (std::vector<float>(4, 10.0f)));
    EXPECT_TRUE(w.empty());
    t.creaseSharpnesses = {std::numeric_limits<float>::quiet_NaN()};
    s = sharpnessTags(t, 4, &w);
    EXPECT_TRUE(s.edgeVertices.empty());
    ASSERT_EQ(w.size(), 1u);  // one for the four edges, naming the first
    EXPECT_NE(w[0].find("4 crease edge(s) ignored; the first: crease 0 edge (0, 1) has sharpness NaN"), std::string::npos) << w[0];
}

TEST(SharpnessTags, BadTagsBecomeWarnings) {
    hd::SubdivTags t;
    t.creaseIndices = {0, 1, 2};
    t.creaseLengths = {3};
    t.creaseSharpnesses = {1, 2, 3, 4};
    t.cornerIndices = {1, 9, 2, 3};
    t.cornerSharpnesses = {10, 10, -1, std::numeric_limits<float>::quiet_NaN()};
    std::vector<std::string> w;
    SharpnessTags s = sharpnessTags(t, 4, &w);
    EXPECT_TRUE(s.edgeVertices.empty());
    // A negative sharpness is smooth (0, as OpenSubdiv reads it); point 9 and NaN are dropped,
    // reported once with the first (one warning for the creases' count, one for the corners).
    EXPECT_EQ(s.cornerVertices, (std::vector<int>{1, 2}));
    EXPECT_EQ(s.cornerSharpness, (std::vector<float>{10.0f, 0.0f}));
    ASSERT_EQ(w.size(), 2u);
    EXPECT_NE(w[1].find("2 corner(s) ignored; the first: corner 1 (point 9)"), std::string::npos) << w[1];
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
