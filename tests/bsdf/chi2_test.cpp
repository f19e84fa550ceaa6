// SPDX-License-Identifier: Apache-2.0
#include "bsdf/chi2.h"

#include "testUtil.h"

namespace principled::bsdf {
namespace {

TEST(Chi2, GammaQKnownValues) {
    // Chi-square tail: dof 1, x = 3.841 -> p = 0.05; dof 10, x = 23.209 -> p = 0.01.
    EXPECT_NEAR(gammaQ(0.5, 3.841459 / 2), 0.05, 1e-5);
    EXPECT_NEAR(gammaQ(5.0, 23.209 / 2), 0.01, 1e-4);
    // Exponential: Q(1, x) = e^-x.
    EXPECT_NEAR(gammaQ(1.0, 2.0), std::exp(-2.0), 1e-12);
    // Large dof: mean of chi-square(5000) is 5000 -> p ~ 0.5.
    EXPECT_NEAR(gammaQ(2500.0, 2500.0), 0.5, 0.01);
}

// The test must be able to fail: a sampler that does not match its pdf is rejected.
TEST(Chi2, DetectsMismatchedPdf) {
    Chi2Config cfg;
    cfg.samples = 200000;
    cfg.cosBins = 40;
    cfg.phiBins = 40;
    auto uniformHemisphere = [](float, glm::vec2 u) -> std::optional<glm::vec3> {
        glm::vec3 w = squareToUniformSphere(u);
        return glm::vec3(w.x, w.y, std::abs(w.z));
    };
    auto r = chi2Test(uniformHemisphere, [](const glm::vec3& w) { return cosineHemispherePdf(w); }, cfg);
    EXPECT_FALSE(r.passed) << r.message;
    auto ok = chi2Test(uniformHemisphere, [](const glm::vec3& w) {
        return w.z > 0.0f ? 0.5f * kInvPi : 0.0f;
    }, cfg);
    EXPECT_TRUE(ok.passed) << ok.message;
}

TEST(Chi2, DetectsSamplesWherePdfIsZero) {
    Chi2Config cfg;
    cfg.samples = 100000;
    cfg.cosBins = 20;
    cfg.phiBins = 20;
    auto r = chi2Test([](float, glm::vec2 u) -> std::optional<glm::vec3> {
        return squareToUniformSphere(u);
    }, [](const glm::vec3& w) { return w.z > 0.0f ? 0.25f * kInvPi : 0.0f; }, cfg);
    EXPECT_FALSE(r.passed) << r.message;
}

}  // namespace
}  // namespace principled::bsdf
