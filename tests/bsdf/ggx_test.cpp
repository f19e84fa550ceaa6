// SPDX-License-Identifier: Apache-2.0
#include "bsdf/ggx.h"

#include "testUtil.h"

namespace principled::bsdf {
namespace {

// Integral of D(m) cos(theta_m) over the hemisphere is 1 (projected microfacet area).
TEST(Ggx, DistributionNormalised) {
    for (glm::vec2 a : {glm::vec2(0.5f, 0.5f), glm::vec2(0.2f, 0.05f), glm::vec2(1.0f, 1.0f)}) {
        Ggx g{a.x, a.y};
        double s = integratePdf([&](const glm::vec3& m) { return g.pdfClassic(m); }, 40, 40);
        EXPECT_NEAR(s, 1.0, 2e-3) << a.x << " " << a.y;
    }
}

TEST(Ggx, AnalyticValues) {
    Ggx g{0.5f, 0.5f};
    EXPECT_NEAR(g.D({0, 0, 1}), 1.0f / (kPi * 0.25f), 1e-5f);  // 1 / (pi a^2)
    // Isotropic GGX D at 45 deg: a^2 / (pi (cos^2 (a^2 - 1) + 1)^2) = 0.25 / (pi 0.625^2).
    glm::vec3 h = glm::normalize(glm::vec3(1, 0, 1));
    EXPECT_NEAR(g.D(h), 0.25f / (kPi * 0.625f * 0.625f), 1e-5f);
    // Smith G1 at 60 deg: 2 / (1 + sqrt(1 + a^2 tan^2)) = 2 / (1 + sqrt(1.75)).
    glm::vec3 w = directionFromAngles(60.0f, 0.0f);
    EXPECT_NEAR(g.G1(w), 2.0f / (1.0f + std::sqrt(1.75f)), 1e-5f);
    EXPECT_FLOAT_EQ(g.G1({1, 0, 0}), 0.0f);
    EXPECT_FLOAT_EQ(g.G1({0, 0, 1}), 1.0f);
    EXPECT_FLOAT_EQ(g.D({0, 0, -1}), 0.0f);
}

TEST(Ggx, DisneyAlphaAspect) {
    glm::vec2 a = disneyAlpha(0.5f, 0.0f);
    EXPECT_FLOAT_EQ(a.x, 0.25f);
    EXPECT_FLOAT_EQ(a.y, 0.25f);
    a = disneyAlpha(1.0f, 1.0f);  // aspect sqrt(0.1): ratio 10:1
    EXPECT_NEAR(a.x / a.y, 10.0f, 1e-4f);
    a = disneyAlpha(0.0f, 0.0f);
    EXPECT_FLOAT_EQ(a.x, 1e-3f);  // reference floor
}

// Visible normals: density integrates to 1 for any view, and sampling matches the density.
TEST(Ggx, VisibleNormalsChi2) {
    int tests = 0;
    struct Case { float ax, ay, theta; };
    std::vector<Case> cases = {{0.5f, 0.5f, 30}, {0.3f, 0.06f, 60}, {1.0f, 1.0f, 80}, {0.1f, 0.1f, 85}};
    for (const auto& c : cases) {
        Ggx g{c.ax, c.ay};
        glm::vec3 wo = directionFromAngles(c.theta, 20.0f);
        Chi2Config cfg;
        cfg.samples = 300000;
        cfg.cosBins = 50;
        cfg.phiBins = 50;
        cfg.testCount = int(cases.size()) * 2;
        auto r = chi2Test([&](float, glm::vec2 u) -> std::optional<glm::vec3> {
            return g.sampleVisible(wo, u);
        }, [&](const glm::vec3& m) { return g.pdfVisible(wo, m); }, cfg);
        EXPECT_TRUE(r.passed) << r.message;
        EXPECT_NEAR(r.pdfIntegral, 1.0, 3e-3);
        auto rc = chi2Test([&](float, glm::vec2 u) -> std::optional<glm::vec3> {
            return g.sampleClassic(u);
        }, [&](const glm::vec3& m) { return g.pdfClassic(m); }, cfg);
        EXPECT_TRUE(rc.passed) << rc.message;
        tests += 2;
    }
}

}  // namespace
}  // namespace principled::bsdf
