// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/timeSamples.h"

#include <gtest/gtest.h>

#include <cmath>

namespace principled::usd {
namespace {

TEST(TimeSamples, LinearInterpolationAndHolding) {
    std::map<double, Value> s{{10, Value::number("float", 0, {})},
                              {20, Value::number("float", 10, {})}};
    EXPECT_EQ(*evaluateTimeSamples(s, 15).getDouble(), 5.0);
    EXPECT_EQ(*evaluateTimeSamples(s, 10).getDouble(), 0.0);
    EXPECT_EQ(*evaluateTimeSamples(s, 0).getDouble(), 0.0);    // held before the first
    EXPECT_EQ(*evaluateTimeSamples(s, 99).getDouble(), 10.0);  // held after the last
    EXPECT_EQ(*evaluateTimeSamples(s, 20).getDouble(), 10.0);
}

TEST(TimeSamples, NonInterpolableTypesAreHeld) {
    std::map<double, Value> ints{{0, Value::number("int", 0, {})},
                                 {10, Value::number("int", 10, {})}};
    EXPECT_EQ(*evaluateTimeSamples(ints, 9.9).getDouble(), 0.0);
    std::map<double, Value> bools{{0, Value::number("bool", 0, {})},
                                  {1, Value::number("bool", 1, {})}};
    EXPECT_EQ(*evaluateTimeSamples(bools, 0.5).getBool(), false);
    std::map<double, Value> tokens{{0, Value::string("token", "a", {})},
                                   {1, Value::string("token", "b", {})}};
    EXPECT_EQ(*evaluateTimeSamples(tokens, 0.7).getString(), "a");
    EXPECT_EQ(*evaluateTimeSamples(tokens, 1).getString(), "b");
}

TEST(TimeSamples, VectorsMatricesArrays) {
    std::map<double, Value> v{{0, Value::tuple("double3", {0, 0, 0}, {})},
                              {2, Value::tuple("double3", {2, 4, 6}, {})}};
    EXPECT_EQ(*evaluateTimeSamples(v, 1).getTuple(), (std::vector<double>{1, 2, 3}));
    std::vector<double> a(16, 0.0), b(16, 2.0);
    std::map<double, Value> m{{0, Value::tuple("matrix4d", a, {})},
                              {1, Value::tuple("matrix4d", b, {})}};
    EXPECT_EQ((*evaluateTimeSamples(m, 0.25).getTuple())[5], 0.5);
    std::map<double, Value> arr{{0, Value::numberArray("point3f", 3, {0, 0, 0, 1, 1, 1}, {})},
                                {1, Value::numberArray("point3f", 3, {2, 2, 2, 3, 3, 3}, {})}};
    EXPECT_EQ(*evaluateTimeSamples(arr, 0.5).numbers(), (std::vector<double>{1, 1, 1, 2, 2, 2}));
    // Different array lengths cannot blend: held.
    std::map<double, Value> uneven{{0, Value::numberArray("float", 1, {0}, {})},
                                   {1, Value::numberArray("float", 1, {1, 1}, {})}};
    EXPECT_EQ(evaluateTimeSamples(uneven, 0.5).size(), 1u);
}

TEST(TimeSamples, QuaternionsSlerp) {
    // 0 and 90 degrees about z, (real, i, j, k): halfway is 45 degrees.
    double h = std::sqrt(0.5);
    std::map<double, Value> q{{0, Value::tuple("quatf", {1, 0, 0, 0}, {})},
                              {1, Value::tuple("quatf", {h, 0, 0, h}, {})}};
    auto mid = *evaluateTimeSamples(q, 0.5).getTuple();
    EXPECT_NEAR(mid[0], std::cos(M_PI / 8), 1e-12);
    EXPECT_NEAR(mid[3], std::sin(M_PI / 8), 1e-12);
    EXPECT_NEAR(mid[0] * mid[0] + mid[3] * mid[3], 1.0, 1e-12);
}

TEST(TimeSamples, NoneSamplesBlockUntilTheNextSample) {
    std::map<double, Value> s{{0, Value::number("float", 1, {})},
                              {10, Value::none("float", false, {})},
                              {20, Value::number("float", 3, {})}};
    EXPECT_EQ(*evaluateTimeSamples(s, 5).getDouble(), 1.0);  // no blend into a block
    EXPECT_TRUE(evaluateTimeSamples(s, 15).isNone());
    EXPECT_EQ(*evaluateTimeSamples(s, 20).getDouble(), 3.0);
}

}  // namespace
}  // namespace principled::usd
