// SPDX-License-Identifier: Apache-2.0
#include "bsdf/disneyDiffuse.h"

#include "testUtil.h"

namespace principled::bsdf {
namespace {

TEST(DisneyDiffuse, AnalyticValues) {
    DisneyDiffuse d{glm::vec3(1.0f), 0.5f, 0.0f};
    glm::vec3 n(0, 0, 1);
    // Normal incidence both ways: FL = FV = 0, Fd = 1 -> 1/pi.
    EXPECT_NEAR(d.eval(n, n).x, kInvPi, 1e-6f);
    // wo at 60 deg, wi at normal: cos theta_d = cos 30, Fd90 = 0.5 + 2 0.5 0.75 = 1.25,
    // FV = 0.5^5, Fd = 1 + 0.25 / 32.
    glm::vec3 wo = directionFromAngles(60, 0);
    EXPECT_NEAR(d.eval(wo, n).x, kInvPi * (1.0f + 0.25f / 32.0f), 1e-6f);
    // Subsurface 1 at normal incidence: Fss = 1, ss = 1.25 (1/2 - 0.5) + 1.25 0.5 = 0.625.
    DisneyDiffuse s{glm::vec3(1.0f), 0.5f, 1.0f};
    EXPECT_NEAR(s.eval(n, n).x, kInvPi * 0.625f, 1e-6f);
}

TEST(DisneyDiffuse, Reciprocity) {
    DisneyDiffuse d{glm::vec3(1.0f), 0.7f, 0.4f};
    Pcg32 rng(11);
    for (int i = 0; i < 1000; ++i) {
        glm::vec3 a = test::randomUpper(rng), b = test::randomUpper(rng);
        if (a.z < 1e-3f || b.z < 1e-3f) continue;
        EXPECT_NEAR(d.eval(a, b).x / b.z, d.eval(b, a).x / a.z, 1e-5f);
    }
}

// reference/bsdf.md §4.3, Burley diffuse alone and the Hanrahan-Krueger subsurface alone.
TEST(DisneyDiffuse, AlbedoTables) {
    const float mus[6] = {1.0f, 0.7f, 0.5f, 0.3f, 0.1f, 0.02f};
    const float burley[3][6] = {{0.976f, 0.975f, 0.961f, 0.894f, 0.688f, 0.535f},
                                {1.006f, 1.005f, 1.008f, 1.020f, 1.023f, 1.011f},
                                {1.036f, 1.035f, 1.057f, 1.151f, 1.380f, 1.518f}};
    const float ss[2][6] = {{0.749f, 0.912f, 1.060f, 1.199f, 1.076f, 0.758f},
                            {0.760f, 0.932f, 1.098f, 1.310f, 1.495f, 1.504f}};
    const float rough[3] = {0.0f, 0.5f, 1.0f};
    for (int r = 0; r < 3; ++r)
        for (int m = 0; m < 6; ++m) {
            DisneyDiffuse d{glm::vec3(1.0f), rough[r], 0.0f};
            EXPECT_NEAR(test::lobeAlbedoSampled(d, test::muDirection(mus[m]), 200000), burley[r][m], 0.01)
                << "roughness " << rough[r] << " mu " << mus[m];
        }
    for (int r = 0; r < 2; ++r)
        for (int m = 0; m < 6; ++m) {
            DisneyDiffuse d{glm::vec3(1.0f), rough[2 * r], 1.0f};
            EXPECT_NEAR(test::lobeAlbedoSampled(d, test::muDirection(mus[m]), 200000), ss[r][m], 0.01)
                << "subsurface, roughness " << rough[2 * r] << " mu " << mus[m];
        }
}

TEST(DisneyDiffuse, Chi2) {
    auto r = test::lobeChi2(DisneyDiffuse{glm::vec3(1.0f), 0.5f, 0.5f}, 70.0f);
    EXPECT_TRUE(r.passed) << r.message;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 2e-3);
}

}  // namespace
}  // namespace principled::bsdf
