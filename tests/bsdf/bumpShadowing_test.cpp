// SPDX-License-Identifier: Apache-2.0
// Shadowing of the diffuse lobes by a leaning shading normal (bsdf/bumpShadowing.h) and its use
// through Bsdf::prepare(wo, smoothNormal).
#include "bsdf/bumpShadowing.h"

#include <cmath>

#include "bsdf/bsdf.h"
#include "bsdf/rng.h"
#include "testUtil.h"

namespace principled::bsdf {
namespace {

constexpr float kDeg = 3.14159265f / 180.0f;

// The shading normal (+z) tilted 30 degrees toward +x from the surface normal n0; light 60
// degrees from n0, on the side of the tilt: n.wi = cos 30, n0.wi = cos 60, n0.n = cos 30, so
// G = 0.5 / 0.75 = 2/3 and the smoothed factor is -8/27 + 4/9 + 2/3 = 22/27.
const glm::vec3 kN0(-std::sin(30 * kDeg), 0.0f, std::cos(30 * kDeg));
const glm::vec3 kWi(std::sin(30 * kDeg), 0.0f, std::cos(30 * kDeg));

TEST(BumpShadowing, ClosedFormOfTheTiltedCase) {
    ASSERT_NEAR(glm::dot(kN0, kWi), 0.5f, 1e-6f);
    EXPECT_NEAR(bumpShadowing(kN0, kWi), 22.0f / 27.0f, 1e-5f);
}

TEST(BumpShadowing, NoShadowingWithoutTiltOrAwayFromTheTilt) {
    Pcg32 rng(3);
    for (int i = 0; i < 1000; ++i) {
        glm::vec3 wi = glm::normalize(glm::vec3(2 * rng.uniform() - 1, 2 * rng.uniform() - 1,
                                                rng.uniform() + 1e-3f));
        EXPECT_EQ(bumpShadowing(glm::vec3(0, 0, 1), wi), 1.0f) << i;
        // Light on the side the normal leans away from: n0.wi >= (n.wi)(n0.n), G >= 1.
        if (wi.x < 0.0f) {
            EXPECT_EQ(bumpShadowing(kN0, wi), 1.0f) << i;
        }
    }
}

TEST(BumpShadowing, FallsSmoothlyToZeroAtTheSurfaceHorizon) {
    // Light sweeping from the shading normal toward the surface's horizon (n0.wi = 0, 60
    // degrees from n here): monotone, continuous, 0 at the horizon and beyond it.
    float prev = 1.0f;
    for (int d = 0; d <= 60; ++d) {
        glm::vec3 wi(std::sin(d * kDeg), 0.0f, std::cos(d * kDeg));
        float k = bumpShadowing(kN0, wi);
        EXPECT_LE(k, prev + 1e-6f) << d;
        EXPECT_GE(k, prev - 0.05f) << d;  // no jump larger than a degree's worth
        prev = k;
    }
    EXPECT_NEAR(prev, 0.0f, 1e-5f);
    EXPECT_EQ(bumpShadowing(kN0, glm::normalize(glm::vec3(0.95f, 0.0f, 0.3f))), 0.0f);
}

TEST(BumpShadowing, ScalesOnlyTheDiffuseAndSheenLobesAndKeepsThePdf) {
    MaterialParams p = cliDefaults();
    p.roughness = 0.5f;
    p.sheen = 1.0f;
    p.clearcoat = 1.0f;
    Bsdf b(p, Options{});
    const glm::vec3 wo(0.0f, 0.0f, 1.0f);
    const Bsdf::View plain = b.prepare(wo), bumped = b.prepare(wo, kN0);
    ASSERT_FALSE(plain.bumped);
    ASSERT_TRUE(bumped.bumped);
    LobeValues a, c;
    float pdfA = 0.0f, pdfC = 0.0f;
    glm::vec3 fa = b.eval(plain, kWi, &pdfA, &a);
    glm::vec3 fc = b.eval(bumped, kWi, &pdfC, &c);
    const float k = 22.0f / 27.0f;
    EXPECT_EQ(pdfA, pdfC);
    for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(c[0][i], k * a[0][i], 1e-6f);  // diffuse
        EXPECT_NEAR(c[1][i], k * a[1][i], 1e-6f);  // sheen
        EXPECT_EQ(c[2][i], a[2][i]);                // specular
        EXPECT_EQ(c[3][i], a[3][i]);                // clearcoat
        EXPECT_NEAR(fc[i], fa[i] - (1.0f - k) * (a[0][i] + a[1][i]), 1e-5f);
    }
    ASSERT_GT(a[0].x, 0.0f);
    // The surface normal itself as smoothNormal is no tilt: identical to prepare(wo).
    EXPECT_FALSE(b.prepare(wo, glm::vec3(0, 0, 1)).bumped);
}

TEST(BumpShadowing, SampledValuesMatchEvaluation) {
    MaterialParams p = cliDefaults();
    p.roughness = 0.6f;
    Bsdf b(p, Options{});
    const Bsdf::View v = b.prepare(glm::normalize(glm::vec3(0.2f, 0.1f, 1.0f)), kN0);
    Pcg32 rng(11);
    int shadowed = 0;
    for (int i = 0; i < 2000; ++i) {
        auto s = b.sample(v, rng.uniform(), {rng.uniform(), rng.uniform()});
        if (!s) continue;
        float pdf = 0.0f;
        glm::vec3 f = b.eval(v, s->wi, &pdf);
        ASSERT_NEAR(f.x, s->f.x, 1e-5f * std::max(1.0f, f.x)) << i;
        ASSERT_NEAR(pdf, s->pdf, 1e-5f * std::max(1.0f, pdf)) << i;
        if (bumpShadowing(kN0, s->wi) < 1.0f) ++shadowed;
    }
    EXPECT_GT(shadowed, 100);
}

}  // namespace
}  // namespace principled::bsdf
