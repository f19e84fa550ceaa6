#include "delegate/renderBuffer.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace principled;

TEST(RenderBuffer, MultiSampledAveragesAndNeverResolvesNaN) {
    embree::EmbreeRenderBuffer b(hd::Path("/b"));
    ASSERT_TRUE(b.allocate(2, 1, hd::Format::Float32Vec4, true));
    float s1[4] = {1, 2, 3, 1}, s2[4] = {3, 4, 5, 0}, bad[4] = {NAN, INFINITY, 0, 0};
    b.addSample(0, 0, s1);
    b.addSample(0, 0, s2);
    b.addSample(1, 0, bad);
    b.resolve();
    const float* p = static_cast<const float*>(b.map());
    EXPECT_FLOAT_EQ(p[0], 2.0f);
    EXPECT_FLOAT_EQ(p[1], 3.0f);
    EXPECT_FLOAT_EQ(p[3], 0.5f);
    for (int i = 4; i < 8; ++i) EXPECT_TRUE(std::isfinite(p[i]));
    EXPECT_EQ(b.sampleCount(0, 0), 2);
}

TEST(RenderBuffer, SingleSampledKeepsTheFirstSample) {
    embree::EmbreeRenderBuffer ids(hd::Path("/ids"));
    ASSERT_TRUE(ids.allocate(1, 1, hd::Format::Int32, true));
    EXPECT_FALSE(ids.isMultiSampled());  // IDs are never averaged
    ids.addSample(0, 0, 7);
    ids.addSample(0, 0, 9);
    EXPECT_EQ(static_cast<const int32_t*>(ids.map())[0], 7);
    ids.clear();
    EXPECT_EQ(static_cast<const int32_t*>(ids.map())[0], -1);
}

TEST(RenderBuffer, RejectsBadSizes) {
    embree::EmbreeRenderBuffer b(hd::Path("/b"));
    EXPECT_FALSE(b.allocate(0, 4, hd::Format::Float32, true));
    EXPECT_FALSE(b.allocate(4, 4, hd::Format::Invalid, true));
    EXPECT_FALSE(b.allocate(1 << 15, 1 << 15, hd::Format::Float32, true));
}
