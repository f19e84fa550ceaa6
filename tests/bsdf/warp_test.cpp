// SPDX-License-Identifier: Apache-2.0
#include "bsdf/warp.h"

#include "testUtil.h"

namespace principled::bsdf {
namespace {

TEST(Warp, CosineHemisphereChi2) {
    Chi2Config cfg;
    cfg.samples = 300000;
    cfg.cosBins = 40;
    cfg.phiBins = 40;
    auto r = chi2Test([](float, glm::vec2 u) -> std::optional<glm::vec3> {
        return squareToCosineHemisphere(u);
    }, [](const glm::vec3& w) { return cosineHemispherePdf(w); }, cfg);
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-3);
}

TEST(Warp, UniformSphereUnitLength) {
    Pcg32 rng(9);
    for (int i = 0; i < 1000; ++i) {
        glm::vec3 w = squareToUniformSphere({rng.uniform(), rng.uniform()});
        EXPECT_NEAR(glm::length(w), 1.0f, 1e-5f);
    }
}

}  // namespace
}  // namespace principled::bsdf
