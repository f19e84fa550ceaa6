// The sampling distributions of a lat-long dome (delegate/environmentSampling.h): the
// MIS-compensated one leaves texels at or below the mean to BSDF sampling, and next-event
// estimation and the MIS weight of escaped rays see the same density for either distribution.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "delegate/environmentSampling.h"
#include "delegate/lightSampling.h"
#include "delegate/sampler.h"

using namespace principled;
using namespace principled::embree;

namespace {

constexpr double kPi = 3.14159265358979323846;

// 32 x 16: a sky whose radiance grows toward the zenith, a dark ground and a 2 x 2 sun.
std::shared_ptr<EnvironmentMap> sunSky() {
    auto env = std::make_shared<EnvironmentMap>();
    env->width = 32;
    env->height = 16;
    env->texels.resize(32 * 16);
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x)
            env->texels[size_t(y) * 32 + x] = y < 8 ? glm::vec3(1.0f - 0.1f * float(y)) : glm::vec3(0.05f);
    for (int y : {3, 4})
        for (int x : {10, 11}) env->texels[size_t(y) * 32 + x] = glm::vec3(300.0f);
    prepareEnvironmentSampling(*env);
    return env;
}

double luminance(const glm::vec3& c) { return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z; }

}  // namespace

TEST(EnvironmentSampling, CompensatedDensityIsTheExcessOverTheMean) {
    auto env = sunSky();
    ASSERT_TRUE(env->latLong);
    ASSERT_FALSE(env->compensated.empty());
    // The mean luminance over the sphere (sin-weighted rows), computed here independently.
    double num = 0.0, den = 0.0;
    for (int y = 0; y < 16; ++y) {
        const double s = std::sin(kPi * (y + 0.5) / 16);
        for (int x = 0; x < 32; ++x) num += luminance(env->texels[size_t(y) * 32 + x]) * s;
        den += 32 * s;
    }
    const double mean = num / den;
    // Density per unit (u, v) area: proportional to max(0, L - mean) sin(theta), normalised.
    double total = 0.0;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x)
            total += std::max(0.0, luminance(env->texels[size_t(y) * 32 + x]) - mean) * std::sin(kPi * (y + 0.5) / 16);
    total /= 32.0 * 16.0;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x) {
            const glm::vec2 uv((x + 0.5f) / 32.0f, (y + 0.5f) / 16.0f);
            const double want = std::max(0.0, luminance(env->texels[size_t(y) * 32 + x]) - mean) *
                                std::sin(kPi * (y + 0.5) / 16) / total;
            EXPECT_NEAR(env->compensated.pdf(uv), want, 1e-4 * std::max(1.0, want)) << x << ", " << y;
        }
    // The sky near the horizon and the ground are below the mean: light sampling leaves them.
    EXPECT_EQ(env->compensated.pdf({0.5f, 7.5f / 16.0f}), 0.0f);
    EXPECT_EQ(env->compensated.pdf({0.5f, 12.5f / 16.0f}), 0.0f);
    EXPECT_GT(env->plain().pdf({0.5f, 12.5f / 16.0f}), 0.0f);
}

TEST(EnvironmentSampling, NearConstantMapKeepsThePlainDistribution) {
    auto env = std::make_shared<EnvironmentMap>();
    env->width = 8;
    env->height = 4;
    env->texels.assign(32, glm::vec3(0.7f));
    prepareEnvironmentSampling(*env);
    EXPECT_TRUE(env->compensated.empty());
    EXPECT_EQ(&env->sampling(true), &env->plain());
}

TEST(EnvironmentSampling, LightSampleAndEscapedRayAgreeOnTheDensity) {
    // For every direction next-event estimation draws, the pdf it reports equals the pdf the
    // integrator's MIS weight gets for an escaped ray along that direction, with and without
    // compensation; and the sampled radiance is the map's.
    LightRecord light;
    light.kind = LightRecord::Kind::Dome;
    auto env = sunSky();
    light.environment = env;
    const glm::vec3 p(0.0f), ng(0.0f, 1.0f, 0.0f);
    for (bool compensated : {false, true}) {
        int samples = 0, inSun = 0;
        for (uint32_t i = 0; i < 4096; ++i) {
            Sampler s(SamplerKind::Sobol, 7, 0, i);
            LightSample ls;
            if (!sampleLight(light, p, ng, s.next2D(), &ls, compensated)) continue;
            ++samples;
            glm::vec3 Le;
            float pdf = 0.0f;
            ASSERT_TRUE(environmentRadiance(light, p, ls.wi, ng, &Le, &pdf, compensated));
            EXPECT_NEAR(pdf, ls.pdf, 1e-3f * ls.pdf) << "compensated " << compensated;
            EXPECT_EQ(Le, ls.Li);
            inSun += Le.x > 100.0f;
        }
        EXPECT_GT(samples, 4000);
        // Compensation sends every sample to the sun here (the whole sky lies below the mean;
        // measured 4096 of 4096, against 3681 of 4096 with the plain distribution).
        if (compensated)
            EXPECT_EQ(inSun, samples);
        else
            EXPECT_LT(inSun, samples * 19 / 20);
    }
}
