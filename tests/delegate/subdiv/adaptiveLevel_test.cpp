// SPDX-License-Identifier: Apache-2.0
#include "delegate/subdiv/adaptiveLevel.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace principled::subdiv;

namespace {

ScreenMetric camera(float distance) {
    ScreenMetric v;
    v.cameraPosition = glm::vec3(0, 0, distance);
    v.verticalFov = 2.0f * std::atan(0.5f);  // tan(fov/2) = 0.5
    v.imageHeight = 1000;
    v.targetEdgePixels = 1.0f;
    v.maxLevel = 6;
    return v;
}

}  // namespace

TEST(AdaptiveLevel, FollowsTheDocumentedFormula) {
    // Unit cube, 6 faces: A = 6, e0 = 1. Bounding sphere r = sqrt(3)/2.
    // Camera at distance D from the centre: d = D - r, pixels per unit = 1000 / d.
    const glm::vec3 lo(-0.5f), hi(0.5f);
    const float r = std::sqrt(3.0f) / 2.0f;
    for (float d : {8.0f, 20.0f, 100.0f, 400.0f}) {
        int expected = int(std::ceil(std::log2(1000.0f / d)));
        expected = std::max(0, std::min(6, expected));
        EXPECT_EQ(adaptiveLevel(lo, hi, 6, camera(d + r)), expected) << d;
    }
}

TEST(AdaptiveLevel, FarMeshesGetFewerLevelsAndResultsAreClamped) {
    const glm::vec3 lo(-1.0f), hi(1.0f);
    int previous = 100;
    for (float d : {2.0f, 10.0f, 50.0f, 250.0f, 1250.0f, 1e5f}) {
        int level = adaptiveLevel(lo, hi, 24, camera(d));
        EXPECT_LE(level, previous);
        EXPECT_GE(level, 0);
        EXPECT_LE(level, 6);
        previous = level;
    }
    EXPECT_EQ(adaptiveLevel(lo, hi, 24, camera(1.5f)), 6);  // camera inside the sphere
    EXPECT_EQ(adaptiveLevel(lo, hi, 24, camera(1e5f)), 0);
    EXPECT_LT(adaptiveLevel(lo, hi, 24, camera(400.0f)), adaptiveLevel(lo, hi, 24, camera(20.0f)));
    // More coarse faces (shorter cage edges) need fewer levels at the same distance.
    EXPECT_LT(adaptiveLevel(lo, hi, 24 * 64, camera(20.0f)),
              adaptiveLevel(lo, hi, 24, camera(20.0f)));
    ScreenMetric v = camera(20.0f);
    v.maxLevel = 2;
    EXPECT_EQ(adaptiveLevel(lo, hi, 24, v), 2);
    // A coarser target (in pixels) lowers the level.
    ScreenMetric coarse = camera(20.0f);
    coarse.targetEdgePixels = 8.0f;
    EXPECT_EQ(adaptiveLevel(lo, hi, 24, coarse), adaptiveLevel(lo, hi, 24, camera(20.0f)) - 3);
}

TEST(AdaptiveLevel, DegenerateInputGivesZero) {
    EXPECT_EQ(adaptiveLevel(glm::vec3(0), glm::vec3(0), 6, camera(5)), 0);
    EXPECT_EQ(adaptiveLevel(glm::vec3(-1), glm::vec3(1), 0, camera(5)), 0);
    ScreenMetric v = camera(5);
    v.imageHeight = 0;
    EXPECT_EQ(adaptiveLevel(glm::vec3(-1), glm::vec3(1), 6, v), 0);
    v = camera(5);
    v.verticalFov = std::nanf("");
    EXPECT_EQ(adaptiveLevel(glm::vec3(-1), glm::vec3(1), 6, v), 0);
}

TEST(AdaptiveLevel, ObjectPointsUnderATransform) {
    std::vector<glm::vec3> cube = {{-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}, {0.0f, 0.2f, 0.1f}};
    const ScreenMetric v = camera(20.0f);
    EXPECT_EQ(adaptiveLevel(cube, glm::dmat4(1.0), 6, v),
              adaptiveLevel(glm::vec3(-0.5f), glm::vec3(0.5f), 6, v));
    glm::dmat4 away(1.0);
    away[3] = glm::dvec4(0.0, 0.0, -300.0, 1.0);  // translate 300 units further from the camera
    EXPECT_LT(adaptiveLevel(cube, away, 6, v), adaptiveLevel(cube, glm::dmat4(1.0), 6, v));
    glm::dmat4 bigger(4.0);
    bigger[3][3] = 1.0;
    bigger[3] = glm::dvec4(0.0, 0.0, -300.0, 1.0);
    EXPECT_GT(adaptiveLevel(cube, bigger, 6, v), adaptiveLevel(cube, away, 6, v));
    EXPECT_EQ(adaptiveLevel(std::vector<glm::vec3>{}, glm::dmat4(1.0), 6, v), 0);
}
