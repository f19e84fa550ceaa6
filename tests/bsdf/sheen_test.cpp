// SPDX-License-Identifier: Apache-2.0
#include "bsdf/sheen.h"

#include "testUtil.h"

namespace principled::bsdf {
namespace {

TEST(Sheen, AnalyticValues) {
    Sheen s{glm::vec3(1.0f)};
    glm::vec3 n(0, 0, 1);
    EXPECT_NEAR(s.eval(n, n).x, 0.0f, 1e-7f);  // theta_d = 0: no sheen
    // wo at 60, wi at 0: theta_d = 30, (1 - cos 30)^5 times cos_i = 1.
    float w = std::pow(1.0f - std::cos(glm::radians(30.0f)), 5.0f);
    EXPECT_NEAR(s.eval(directionFromAngles(60, 0), n).x, w, 1e-6f);
}

TEST(Sheen, ReciprocityAndChi2) {
    Sheen s{glm::vec3(1.0f)};
    Pcg32 rng(13);
    for (int i = 0; i < 500; ++i) {
        glm::vec3 a = test::randomUpper(rng), b = test::randomUpper(rng);
        if (a.z < 1e-3f || b.z < 1e-3f) continue;
        EXPECT_NEAR(s.eval(a, b).x / b.z, s.eval(b, a).x / a.z, 1e-5f);
    }
    auto r = test::lobeChi2(s, 80.0f);
    EXPECT_TRUE(r.passed) << r.message;
}

}  // namespace
}  // namespace principled::bsdf
