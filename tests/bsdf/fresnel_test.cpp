// SPDX-License-Identifier: Apache-2.0
#include "bsdf/fresnel.h"

#include <gtest/gtest.h>

namespace principled::bsdf {
namespace {

TEST(Fresnel, SchlickWeightEndpoints) {
    EXPECT_FLOAT_EQ(schlickWeight(1.0f), 0.0f);
    EXPECT_FLOAT_EQ(schlickWeight(0.0f), 1.0f);
    EXPECT_NEAR(schlickWeight(0.5f), 0.03125f, 1e-7f);
    EXPECT_FLOAT_EQ(schlickWeight(1.5f), 0.0f);   // clamped, no negative base
    EXPECT_FLOAT_EQ(schlickWeight(-0.5f), 1.0f);  // clamped
}

TEST(Fresnel, DielectricNormalIncidence) {
    // ((n-1)/(n+1))^2 = 0.04 for n = 1.5
    EXPECT_NEAR(fresnelDielectric(1.0f, 1.5f), 0.04f, 1e-6f);
    EXPECT_NEAR(fresnelDielectric(1.0f, 1.0f / 1.5f), 0.04f, 1e-6f);
    EXPECT_NEAR(fresnelDielectric(0.0f, 1.5f), 1.0f, 1e-6f);
}

TEST(Fresnel, DielectricKnownAngleAndTir) {
    // 45 degrees into glass n = 1.5: Rs = 0.0920, Rp = 0.00847, mean 0.0502.
    EXPECT_NEAR(fresnelDielectric(std::sqrt(0.5f), 1.5f), 0.0502f, 2e-4f);
    // Brewster angle: Rp = 0, R = Rs / 2 = 0.0739 at atan(1.5).
    float cb = std::cos(std::atan(1.5f));
    EXPECT_NEAR(fresnelDielectric(cb, 1.5f), 0.0739f, 3e-4f);
    // Critical angle from inside glass is asin(1/1.5) = 41.8 degrees.
    EXPECT_FLOAT_EQ(fresnelDielectric(std::cos(glm::radians(45.0f)), 1.0f / 1.5f), 1.0f);
    EXPECT_LT(fresnelDielectric(std::cos(glm::radians(40.0f)), 1.0f / 1.5f), 1.0f);
}

TEST(Fresnel, SchlickSGCloseToSchlick) {
    // Karis 2013: "identical for all practical purposes".
    for (float c = 0.0f; c <= 1.0f; c += 0.05f)
        EXPECT_NEAR(schlickFresnelSG(glm::vec3(0.04f), c).x, schlickFresnel(0.04f, c), 0.01f);
}

}  // namespace
}  // namespace principled::bsdf
