// PortalSet (delegate/portalSampling.h): its density over directions is a distribution for points
// that receive through a portal, sample() draws from it, and points on the outer side of every
// portal get none.
#include <gtest/gtest.h>

#include <cmath>

#include "delegate/portalSampling.h"
#include "delegate/sampler.h"

using namespace principled::embree;

namespace {

constexpr float kPi = 3.14159265358979323846f;

// Two windows in the ceiling y = 2 of a room, light passing down (-Y): 1 x 1 at the origin and
// 2 x 0.5 at x = 3; a wall window at x = -4 passing light along +X.
PortalSet windows() {
    return PortalSet({{glm::vec3(0, 2, 0), glm::vec3(0.5f, 0, 0), glm::vec3(0, 0, 0.5f), glm::vec3(0, -1, 0), 1.0f},
                      {glm::vec3(3, 2, 0), glm::vec3(1.0f, 0, 0), glm::vec3(0, 0, 0.25f), glm::vec3(0, -1, 0), 1.0f},
                      {glm::vec3(-4, 1, 0), glm::vec3(0, 0.5f, 0), glm::vec3(0, 0, 0.5f), glm::vec3(1, 0, 0), 1.0f}});
}

}  // namespace

TEST(PortalSampling, DensityIntegratesToOneAndSamplesAgreeWithIt) {
    const PortalSet set = windows();
    for (const glm::vec3 p : {glm::vec3(0.2f, 0.0f, 0.1f), glm::vec3(2.0f, 1.5f, -1.0f), glm::vec3(-3.9f, 0.3f, 0.2f)}) {
        ASSERT_GT(set.weight(p), 0.0f);
        // Integral of pdf over the sphere by uniform directions (Sobol): 1.
        const int n = 1 << 18;
        double integral = 0.0;
        for (int i = 0; i < n; ++i) {
            Sampler s(SamplerKind::Sobol, 7, 0, uint32_t(i));
            const glm::vec2 u = s.next2D();
            const float z = 1.0f - 2.0f * u.x, r = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = 2.0f * kPi * u.y;
            integral += set.pdf(p, glm::vec3(r * std::cos(phi), z, r * std::sin(phi))) * (4.0 * kPi) / n;
        }
        EXPECT_NEAR(integral, 1.0, 0.02) << p.x;
        // E[f / pdf] over sample() is the integral of f over the directions it covers, for any f:
        // checked for f = 1 (the solid angle) and a lopsided f, against the same integrals over
        // uniform directions; every sample's reported pdf equals pdf() at its direction.
        auto f = [](const glm::vec3& w) { return (1.5 + w.x) * (1.5 + w.x) * (1.2 - w.z); };
        double solidAngle = 0.0, weighted = 0.0;
        const int m = 1 << 16;
        for (int i = 0; i < m; ++i) {
            Sampler s(SamplerKind::Sobol, 8, 0, uint32_t(i));
            glm::vec3 wi;
            float pdf;
            ASSERT_TRUE(set.sample(p, s.next2D(), &wi, &pdf));
            ASSERT_NEAR(pdf, set.pdf(p, wi), 1e-4f * pdf);
            solidAngle += 1.0 / pdf / m;
            weighted += f(wi) / pdf / m;
        }
        // The same solid angle by integrating the indicator pdf > 0 over uniform directions.
        double covered = 0.0, coveredF = 0.0;
        for (int i = 0; i < n; ++i) {
            Sampler s(SamplerKind::Sobol, 9, 0, uint32_t(i));
            const glm::vec2 u = s.next2D();
            const float z = 1.0f - 2.0f * u.x, r = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = 2.0f * kPi * u.y;
            const glm::vec3 w(r * std::cos(phi), z, r * std::sin(phi));
            if (set.pdf(p, w) > 0.0f) {
                covered += 4.0 * kPi / n;
                coveredF += f(w) * 4.0 * kPi / n;
            }
        }
        EXPECT_NEAR(solidAngle, covered, 0.02 * covered) << p.x;
        EXPECT_NEAR(weighted, coveredF, 0.02 * coveredF) << p.x;
    }
}

TEST(PortalSampling, PointsOutsideEveryPortalReceiveNone) {
    const PortalSet set = windows();
    const glm::vec3 above(0.0f, 3.0f, 0.0f);  // above the ceiling windows, behind the wall one
    EXPECT_EQ(set.weight(glm::vec3(-5.0f, 3.0f, 0.0f)), 0.0f);
    EXPECT_GT(set.weight(above), 0.0f);  // the wall window passes +X: x = 0 is on its inner side
    glm::vec3 wi;
    float pdf;
    EXPECT_FALSE(set.sample(glm::vec3(-5.0f, 3.0f, 0.0f), glm::vec2(0.3f, 0.6f), &wi, &pdf));
    EXPECT_EQ(set.pdf(glm::vec3(-5.0f, 3.0f, 0.0f), glm::vec3(0, 1, 0)), 0.0f);
    // A zero-area portal is dropped.
    EXPECT_TRUE(PortalSet({{glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0.0f), glm::vec3(0, -1, 0), 0.0f}}).empty());
}
