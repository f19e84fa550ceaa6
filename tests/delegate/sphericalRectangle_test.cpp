// SphericalRectangle (delegate/sphericalRectangle.h): the solid angle against the closed form
// for a centred square, and samples on the rectangle.
#include <gtest/gtest.h>

#include <cmath>

#include "delegate/sphericalRectangle.h"

using namespace principled::embree;

TEST(SphericalRectangle, SolidAngleMatchesTheClosedFormAndSamplesLieOnTheRectangle) {
    // A square of side 2a centred h below the point: 4 asin(a^2 / (a^2 + h^2)).
    for (const float a : {0.01f, 0.5f, 3.0f})
        for (const float h : {0.05f, 1.0f, 40.0f}) {
            const SphericalRectangle r(glm::vec3(0.0f), glm::vec3(-a, -a, -h), glm::vec3(2 * a, 0, 0), glm::vec3(0, 2 * a, 0));
            ASSERT_TRUE(r.valid());
            const double exact = 4.0 * std::asin(double(a) * a / (double(a) * a + double(h) * h));
            EXPECT_NEAR(r.solidAngle(), exact, 1e-6 + 1e-4 * exact) << a << " " << h;
            for (const glm::vec2 u : {glm::vec2(0.0f), glm::vec2(0.5f), glm::vec2(0.999f, 0.001f), glm::vec2(0.3f, 0.8f)}) {
                const glm::vec3 x = r.sample(u.x, u.y);
                EXPECT_NEAR(x.z, -h, 1e-4f * h);
                EXPECT_LE(std::abs(x.x), a * 1.0001f);
                EXPECT_LE(std::abs(x.y), a * 1.0001f);
            }
            // The centre of the map is the point straight below for a symmetric square.
            const glm::vec3 c = r.sample(0.5f, 0.5f);
            EXPECT_NEAR(c.x, 0.0f, 1e-3f * a);
            EXPECT_NEAR(c.y, 0.0f, 1e-3f * a);
        }
    // In the plane: not valid.
    EXPECT_FALSE(SphericalRectangle(glm::vec3(5, 0, 0), glm::vec3(0.0f), glm::vec3(1, 0, 0), glm::vec3(0, 1, 0)).valid());
}
