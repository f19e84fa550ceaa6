// SPDX-License-Identifier: Apache-2.0
#include "bsdf/clearcoat.h"

#include "testUtil.h"

namespace principled::bsdf {
namespace {

Clearcoat coat(float gloss) {
    Clearcoat c;
    c.dist.alpha = glm::mix(0.1f, 0.001f, gloss);
    c.weight = 0.25f;
    return c;
}

// reference/bsdf.md §4.3: clearcoat alone (clearcoat 1, includes the 0.25): 0.008-0.009 at
// mu = 1, 0.013-0.015 at mu = .5, 0.039-0.042 at mu = .1 for gloss 0..1.
TEST(Clearcoat, AlbedoTable) {
    for (float gloss : {0.0f, 0.5f, 1.0f}) {
        EXPECT_NEAR(test::lobeAlbedoSampled(coat(gloss), test::muDirection(1.0f)), 0.0085, 0.0015);
        EXPECT_NEAR(test::lobeAlbedoSampled(coat(gloss), test::muDirection(0.5f)), 0.014, 0.0015);
        EXPECT_NEAR(test::lobeAlbedoSampled(coat(gloss), test::muDirection(0.1f)), 0.0405, 0.003);
    }
}

TEST(Clearcoat, AnalyticNormalIncidence) {
    // wo = wi = n: 0.25 D(1) F0 G(1) / 4 with G = 1.
    Clearcoat c = coat(0.0f);
    glm::vec3 n(0, 0, 1);
    EXPECT_NEAR(c.eval(n, n).x, 0.25f * c.dist.D(1.0f) * 0.04f / 4.0f, 1e-6f);
}

TEST(Clearcoat, ReciprocityAndChi2) {
    Clearcoat c = coat(0.5f);
    Pcg32 rng(19);
    for (int i = 0; i < 500; ++i) {
        glm::vec3 a = test::randomUpper(rng), b = test::randomUpper(rng);
        if (a.z < 1e-2f || b.z < 1e-2f) continue;
        EXPECT_LE(test::relErr(c.eval(a, b).x / b.z, c.eval(b, a).x / a.z), 1e-4f);
    }
    // gloss 1 (alpha 0.001) needs a very fine quadrature: it runs in the long grid.
    for (float gloss : {0.0f, 0.5f}) {
        auto r = test::lobeChi2(coat(gloss), 45.0f, 2);
        EXPECT_TRUE(r.passed) << gloss << " " << r.message;
    }
}

TEST(Clearcoat, RoughCoatsBeyondDisneysRangeSampleAndIntegrateCorrectly) {
    // UsdPreviewSurface clearcoatRoughness up to 1 gives GTR1 alphas up to 1 (Disney's gloss
    // stopped at 0.1): still a distribution its sampling matches, with the coat's albedo at
    // normal incidence bounded by the Fresnel 0.04 of its 0.25 weight.
    for (float alpha : {0.25f, 0.6f, 0.999f, 1.0f}) {
        Clearcoat c;
        c.dist.alpha = alpha;
        c.weight = 0.25f;
        auto r = test::lobeChi2(c, 45.0f, 2);
        EXPECT_TRUE(r.passed) << alpha << " " << r.message;
        const double albedo = test::lobeAlbedoSampled(c, test::muDirection(1.0f));
        EXPECT_GT(albedo, 0.0);
        EXPECT_LT(albedo, 0.25 * 0.05) << alpha;
    }
}

}  // namespace
}  // namespace principled::bsdf
