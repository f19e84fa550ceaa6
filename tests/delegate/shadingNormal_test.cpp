#include "delegate/shadingNormal.h"

#include <gtest/gtest.h>

#include <cmath>

#include "bsdf/rng.h"

using namespace principled::embree;

namespace {

constexpr float kDeg = 3.14159265f / 180.0f;

float mirrorHeight(const glm::vec3& ng, const glm::vec3& wo, const glm::vec3& n) {
    return glm::dot(2.0f * glm::dot(n, wo) * n - wo, ng);
}

}  // namespace

TEST(ShadingNormal, ValidNormalsAreKept) {
    glm::vec3 ng(0, 0, 1), wo = glm::normalize(glm::vec3(0.3f, -0.5f, 0.8f));
    EXPECT_EQ(validReflectionNormal(ng, wo, ng), ng);
    glm::vec3 n = glm::normalize(glm::vec3(0.1f, -0.2f, 1.0f));  // leaning toward the viewer
    EXPECT_EQ(validReflectionNormal(ng, wo, n), n);
}

TEST(ShadingNormal, GrazingTiltIsBentUntilTheMirrorDirectionGrazes) {
    // A plane whose normal map tilts 40 degrees away from a camera 51.3 degrees above it: the
    // mirror direction about the mapped normal points into the surface. The rule keeps the tilt
    // plane and bends the normal to 2a = psi + acos(0.01), a = 25.4 degrees here.
    glm::vec3 ng(0, 0, 1), wo = glm::normalize(glm::vec3(0, -4, 5));
    glm::vec3 n(0, std::sin(40 * kDeg), std::cos(40 * kDeg));
    ASSERT_LT(mirrorHeight(ng, wo, n), 0.0f);
    glm::vec3 b = validReflectionNormal(ng, wo, n);
    EXPECT_NEAR(std::acos(b.z) / kDeg, 25.38f, 0.05f);
    EXPECT_NEAR(b.x, 0.0f, 1e-6f);
    EXPECT_GT(b.y, 0.0f);
    EXPECT_NEAR(mirrorHeight(ng, wo, b), 0.01f, 1e-4f);
}

TEST(ShadingNormal, EveryResultIsUnitAndValid) {
    principled::bsdf::Pcg32 rng(7);
    int bent = 0;
    for (int i = 0; i < 20000; ++i) {
        auto dir = [&] {
            glm::vec3 v(2 * rng.uniform() - 1, 2 * rng.uniform() - 1, 2 * rng.uniform() - 1);
            return glm::normalize(v + glm::vec3(0, 0, 1e-3f));
        };
        glm::vec3 ng = dir(), wo = dir(), n = dir();
        if (glm::dot(wo, ng) < 1e-3f) wo = glm::normalize(wo - 2.0f * glm::dot(wo, ng) * ng + 1e-2f * ng);
        if (glm::dot(n, ng) < 0.0f) n = -n;
        glm::vec3 b = validReflectionNormal(ng, wo, n);
        ASSERT_TRUE(std::isfinite(b.x) && std::isfinite(b.y) && std::isfinite(b.z));
        ASSERT_NEAR(glm::length(b), 1.0f, 1e-4f);
        float threshold = std::min(0.9f * glm::dot(wo, ng), 0.01f);
        ASSERT_GE(mirrorHeight(ng, wo, b), threshold - 2e-3f) << i;
        ASSERT_GE(glm::dot(b, ng), -1e-5f);
        if (b != n) {
            ++bent;
            // Bent within the plane of n and ng, and never past ng.
            EXPECT_NEAR(glm::dot(b, glm::cross(n, ng)), 0.0f, 1e-3f);
            EXPECT_GE(glm::dot(b, ng) + 1e-5f, glm::dot(n, ng));
        }
    }
    EXPECT_GT(bent, 1000);
}
