// Dome texture formats: where directions land in mirroredBall and angular images, and the
// resampling into lat-long checked against a known environment.
#include "delegate/environmentFormat.h"

#include <gtest/gtest.h>

#include <cmath>

#include "delegate/lightSampling.h"

using namespace principled::embree;

namespace {
void expectAt(DomeFormat f, glm::vec3 d, glm::vec2 uv) {
    const glm::vec2 p = domeImagePosition(f, glm::normalize(d));
    EXPECT_NEAR(p.x, uv.x, 1e-5f) << d.x << "," << d.y << "," << d.z;
    EXPECT_NEAR(p.y, uv.y, 1e-5f) << d.x << "," << d.y << "," << d.z;
}
}  // namespace

TEST(EnvironmentFormat, TokensNameTheFormats) {
    EXPECT_EQ(domeFormatFromToken("automatic"), DomeFormat::LatLong);
    EXPECT_EQ(domeFormatFromToken("latlong"), DomeFormat::LatLong);
    EXPECT_EQ(domeFormatFromToken("mirroredBall"), DomeFormat::MirroredBall);
    EXPECT_EQ(domeFormatFromToken("angular"), DomeFormat::Angular);
    EXPECT_FALSE(domeFormatFromToken("cubeMapVerticalCross"));
    EXPECT_FALSE(domeFormatFromToken("latLong"));  // tokens are case sensitive
}

TEST(EnvironmentFormat, BallAndAngularPutPlusZAtTheCentreAndPlusYUp) {
    for (DomeFormat f : {DomeFormat::MirroredBall, DomeFormat::Angular}) {
        expectAt(f, {0, 0, 1}, {0.5f, 0.5f});  // the lat-long map's centre direction
    }
    // Angular: the radius is the angle from +Z over pi (90 degrees: half way to the rim).
    expectAt(DomeFormat::Angular, {1, 0, 0}, {0.75f, 0.5f});
    expectAt(DomeFormat::Angular, {0, 1, 0}, {0.5f, 0.25f});  // up is up (v counts down)
    expectAt(DomeFormat::Angular, {-1, 0, 0}, {0.25f, 0.5f});
    expectAt(DomeFormat::Angular, {1, 0, -1}, {0.5f + 0.5f * 0.75f, 0.5f});  // 135 degrees
    // Mirrored ball: a direction 90 degrees off +Z is reflected where the normal is 45 degrees
    // off: sin 45 of the radius.
    expectAt(DomeFormat::MirroredBall, {1, 0, 0}, {0.5f + 0.5f * 0.70710678f, 0.5f});
    expectAt(DomeFormat::MirroredBall, {0, 1, 0}, {0.5f, 0.5f - 0.5f * 0.70710678f});
    // Straight back (-Z) is the rim of both.
    for (DomeFormat f : {DomeFormat::MirroredBall, DomeFormat::Angular}) {
        const glm::vec2 p = domeImagePosition(f, {0, 0, -1});
        EXPECT_NEAR(glm::length(p - glm::vec2(0.5f)), 0.5f, 1e-5f);
        const glm::vec2 q = domeImagePosition(f, glm::normalize(glm::vec3(0.001f, 0, -1)));
        EXPECT_NEAR(glm::length(q - glm::vec2(0.5f)), 0.5f, 1e-3f);
    }
}

TEST(EnvironmentFormat, ResampledMapsMatchTheEnvironmentTheyWereMadeFrom) {
    // A smooth environment f(d) written as 256^2 angular and mirrored-ball images (each texel
    // the value at the direction its centre shows, from the formats' forward definitions:
    // angle = radius x pi, and the view reflected off the ball's normal), resampled to lat-long,
    // equals f at the lat-long texels (away from the -Z rim, where the images squeeze a whole
    // ring into one circle).
    auto f = [](const glm::vec3& d) { return glm::vec3(0.5f + 0.5f * d.x, 0.5f + 0.5f * d.y, 0.5f + 0.5f * d.z); };
    const int n = 256;
    for (DomeFormat format : {DomeFormat::Angular, DomeFormat::MirroredBall}) {
        EnvironmentMap img;
        img.width = img.height = n;
        img.texels.assign(size_t(n) * n, glm::vec3(0.0f));
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                // Disc position of the texel centre, and the direction it shows.
                const float dx = 2.0f * (float(x) + 0.5f) / n - 1.0f, dy = 1.0f - 2.0f * (float(y) + 0.5f) / n;
                const float r = std::sqrt(dx * dx + dy * dy);
                if (r > 1.0f) continue;
                glm::vec3 d;
                if (format == DomeFormat::Angular) {
                    const float a = r * 3.14159265f;
                    d = r > 0 ? glm::vec3(dx / r * std::sin(a), dy / r * std::sin(a), std::cos(a)) : glm::vec3(0, 0, 1);
                } else {
                    const glm::vec3 nrm(dx, dy, std::sqrt(std::max(0.0f, 1.0f - r * r)));
                    d = 2.0f * nrm.z * nrm - glm::vec3(0, 0, 1);  // the view (0,0,-1) reflected
                }
                img.texels[size_t(y) * n + size_t(x)] = f(d);
            }
        const EnvironmentMap ll = resampleToLatLong(img, format);
        ASSERT_EQ(ll.width, 2 * n);
        ASSERT_EQ(ll.height, n);
        double worst = 0.0;
        for (int y = 0; y < ll.height; ++y)
            for (int x = 0; x < ll.width; ++x) {
                const glm::vec3 d = latLongToDirection({(x + 0.5f) / ll.width, (y + 0.5f) / ll.height});
                if (d.z < -0.5f) continue;  // near the rim
                const glm::vec3 e = ll.texels[size_t(y) * ll.width + size_t(x)] - f(d);
                worst = std::max(worst, double(std::max({std::abs(e.x), std::abs(e.y), std::abs(e.z)})));
            }
        EXPECT_LT(worst, 0.02) << int(format);
    }
}

TEST(EnvironmentFormat, ResampledSizeFollowsTheImagesArea) {
    // About as many texels as the image: a 1 x 4096 strip gives 128 x 64, not 8192 x 4096.
    EnvironmentMap strip;
    strip.width = 1;
    strip.height = 4096;
    strip.texels.assign(4096, glm::vec3(1.0f));
    const EnvironmentMap ll = resampleToLatLong(strip, DomeFormat::Angular);
    EXPECT_EQ(ll.height, 64);
    EXPECT_EQ(ll.width, 128);
    EnvironmentMap square;
    square.width = square.height = 256;
    square.texels.assign(256 * 256, glm::vec3(0.5f));
    const EnvironmentMap sq = resampleToLatLong(square, DomeFormat::MirroredBall);
    EXPECT_EQ(sq.height, 256);
    EXPECT_EQ(sq.width, 512);
    EXPECT_NEAR(sq.texels[size_t(100) * 512 + 200].x, 0.5f, 1e-6f);
}
