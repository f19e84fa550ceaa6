// SPDX-License-Identifier: Apache-2.0
// The full chi-square grid of issue 4 (label long): roughness {0.05, 0.2, 0.5, 1} x anisotropic
// {0, 0.8} x metallic {0, 1} x clearcoat {0, 1 with gloss 0/0.5/1} x sheen {0, 1} x specTrans
// {0, 0.7}, views at 15/30/60/80/89 degrees, whole mixture (1e6 samples) and each lobe alone
// (3e5 samples, 30 and 80 degrees). Sidak correction over every test in the grid.
#include "bsdf/bsdf.h"

#include "testUtil.h"

namespace principled::bsdf {
namespace {

constexpr int kMaterials = 4 * 2 * 2 * 4 * 2 * 2;
constexpr int kTotalTests = kMaterials * 5 + kMaterials * 3 * 2;  // upper bound of runs

MaterialParams gridMaterial(int index) {
    const float rough[4] = {0.05f, 0.2f, 0.5f, 1.0f};
    MaterialParams p = cliDefaults();
    p.baseColor = {0.8f, 0.6f, 0.4f};
    int i = index;
    p.roughness = rough[i % 4];
    i /= 4;
    p.anisotropic = (i % 2) ? 0.8f : 0.0f;
    i /= 2;
    p.metallic = float(i % 2);
    i /= 2;
    int cc = i % 4;
    i /= 4;
    p.clearcoat = cc == 0 ? 0.0f : 1.0f;
    p.clearcoatGloss = cc == 0 ? 0.0f : 0.5f * float(cc - 1);
    p.sheen = float(i % 2);
    i /= 2;
    p.specTrans = (i % 2) ? 0.7f : 0.0f;
    return p;
}

class Chi2Grid : public ::testing::TestWithParam<int> {};

TEST_P(Chi2Grid, MixtureAndLobes) {
    MaterialParams p = gridMaterial(GetParam());
    Bsdf b(p, Options{});
    Chi2Config cfg;
    cfg.testCount = kTotalTests;
    for (float theta : {15.0f, 30.0f, 60.0f, 80.0f, 89.0f}) {
        auto r = chi2TestBsdf(b, theta, cfg);
        EXPECT_TRUE(r.passed) << "material " << GetParam() << " theta " << theta << ": " << r.message;
    }
    cfg.samples = 300000;
    cfg.cosBins = 60;
    cfg.phiBins = 60;
    for (int k = 0; k < kLobeCount; ++k) {
        if (!(b.lobes() & (1u << k))) continue;
        Options o;
        o.lobeMask = 1u << k;
        Bsdf single(p, o);
        for (float theta : {30.0f, 80.0f}) {
            auto r = chi2TestBsdf(single, theta, cfg);
            EXPECT_TRUE(r.passed) << "material " << GetParam() << " lobe " << k << " theta " << theta
                                  << ": " << r.message;
        }
    }
}

INSTANTIATE_TEST_SUITE_P(Bsdf, Chi2Grid, ::testing::Range(0, kMaterials));

TEST(Chi2GridUe4, Mixture) {
    Chi2Config cfg;
    cfg.testCount = 4 * 2 * 5;
    for (float r : {0.05f, 0.2f, 0.5f, 1.0f})
        for (float m : {0.0f, 1.0f}) {
            MaterialParams p = cliDefaults();
            p.roughness = r;
            p.metallic = m;
            Options o;
            o.model = Model::UE4;
            for (float theta : {15.0f, 30.0f, 60.0f, 80.0f, 89.0f}) {
                auto res = chi2TestBsdf(Bsdf(p, o), theta, cfg);
                EXPECT_TRUE(res.passed) << r << " " << m << " " << theta << ": " << res.message;
            }
        }
}

TEST(StressLong, TenMillion) {
    StressResult r = stressTest(10000000, 99);
    EXPECT_EQ(r.bad, 0u) << r.firstBad;
}

}  // namespace
}  // namespace principled::bsdf
