// SPDX-License-Identifier: Apache-2.0
#include "bsdf/gtr1.h"

#include "testUtil.h"

namespace principled::bsdf {
namespace {

TEST(Gtr1, Normalised) {
    for (float a : {0.1f, 0.05f, 0.01f}) {
        Gtr1 g{a};
        double s = integratePdf([&](const glm::vec3& m) { return g.pdf(m); }, 40, 20);
        EXPECT_NEAR(s, 1.0, 3e-3) << a;
    }
}

TEST(Gtr1, PeakValue) {
    // D(1) = (a^2 - 1) / (pi ln(a^2) a^2); reference/bsdf.md §4.4: about 2.3e4 at a = 0.001.
    Gtr1 g{0.001f};
    EXPECT_NEAR(g.D(1.0f) / 2.3e4f, 1.0f, 0.01f);
    EXPECT_FLOAT_EQ(Gtr1{1.0f}.D(0.3f), kInvPi);
}

TEST(Gtr1, SamplingChi2) {
    for (float a : {0.1f, 0.02f}) {
        Gtr1 g{a};
        Chi2Config cfg;
        cfg.samples = 300000;
        cfg.cosBins = 60;
        cfg.phiBins = 30;
        cfg.testCount = 2;
        auto r = chi2Test([&](float, glm::vec2 u) -> std::optional<glm::vec3> { return g.sample(u); },
                          [&](const glm::vec3& m) { return g.pdf(m); }, cfg);
        EXPECT_TRUE(r.passed) << r.message;
    }
}

}  // namespace
}  // namespace principled::bsdf
