// SPDX-License-Identifier: Apache-2.0
#include "bsdf/lambert.h"

#include "testUtil.h"

namespace principled::bsdf {
namespace {

TEST(Lambert, WhiteFurnaceIsOne) {
    Lambert l{glm::vec3(1.0f)};
    for (float mu : {1.0f, 0.5f, 0.05f}) {
        EXPECT_NEAR(test::lobeAlbedoSampled(l, test::muDirection(mu)), 1.0, 1e-4);  // exact per sample
        EXPECT_NEAR(test::lobeAlbedoUniform(l, test::muDirection(mu)), 1.0, 0.01);
    }
}

TEST(Lambert, AnalyticValueAndReciprocity) {
    Lambert l{glm::vec3(0.5f)};
    glm::vec3 wo = directionFromAngles(30, 0), wi = directionFromAngles(60, 90);
    EXPECT_NEAR(l.eval(wo, wi).x, 0.5f / kPi * 0.5f, 1e-6f);
    EXPECT_NEAR(l.eval(wo, wi).x / wi.z, l.eval(wi, wo).x / wo.z, 1e-6f);
    EXPECT_FLOAT_EQ(l.eval(wo, -wi).x, 0.0f);
}

TEST(Lambert, Chi2) {
    auto r = test::lobeChi2(Lambert{glm::vec3(1.0f)}, 45.0f);
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 2e-3);
}

}  // namespace
}  // namespace principled::bsdf
