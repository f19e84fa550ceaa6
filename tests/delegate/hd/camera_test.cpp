// Camera: the thin-lens aperture from UsdGeomCamera's fStop, focal length and the stage unit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>

#include "delegate/hd/camera.h"

using principled::hd::Camera;
using principled::hd::Path;

namespace {

// A 50 mm lens as the scene delegate hands it over: the authored 50 divided by 10.
// On a centimetre stage; `tenths` scales the authored lengths for other units (a metre stage
// authors 50 mm as 0.5: Blender's USD export).
Camera fiftyMillimetre(float fStop, float focus, float tenths = 50.0f) {
    Camera c{Path("/cam")};
    c.set(glm::dmat4(1.0), tenths / 10.0f, 3.6f * tenths / 50.0f, 2.4f * tenths / 50.0f);
    c.setDepthOfField(fStop, focus);
    return c;
}

}  // namespace

TEST(Camera, LensRadiusIsFocalLengthOverTwiceTheFNumberInSceneUnits) {
    // f / (2 N) = 50 mm / 4 = 12.5 mm: 1.25 scene units on a centimetre stage (authored 50),
    // 0.0125 on a metre one (authored 0.5), 12.5 on a millimetre one (authored 500).
    EXPECT_FLOAT_EQ(fiftyMillimetre(2.0f, 3.0f).lensRadius(), 1.25f);
    EXPECT_FLOAT_EQ(fiftyMillimetre(2.0f, 3.0f, 0.5f).lensRadius(), 0.0125f);
    EXPECT_FLOAT_EQ(fiftyMillimetre(2.0f, 3.0f, 500.0f).lensRadius(), 12.5f);
    // A near-zero fStop is held to 1000 focus distances (finite ray origins).
    EXPECT_FLOAT_EQ(fiftyMillimetre(1e-30f, 3.0f).lensRadius(), 3000.0f);
}

TEST(Camera, NoLensWithoutAnFStopAFocusDistanceOrAPerspective) {
    EXPECT_EQ(fiftyMillimetre(0.0f, 3.0f).lensRadius(), 0.0f);  // schema fallback fStop
    EXPECT_EQ(fiftyMillimetre(2.0f, 0.0f).lensRadius(), 0.0f);  // schema fallback focus
    EXPECT_EQ(fiftyMillimetre(-1.0f, 3.0f).lensRadius(), 0.0f);
    EXPECT_EQ(fiftyMillimetre(2.0f, std::numeric_limits<float>::infinity()).lensRadius(), 0.0f);
    EXPECT_EQ(fiftyMillimetre(2.0f, 3.0f, 0.0f).lensRadius(), 0.0f);  // no focal length
    EXPECT_EQ(fiftyMillimetre(std::numeric_limits<float>::quiet_NaN(), 3.0f).lensRadius(), 0.0f);
    Camera ortho{Path("/o")};
    ortho.set(glm::dmat4(1.0), 5.0f, 3.6f, 2.4f, Camera::Projection::Orthographic);
    ortho.setDepthOfField(2.0f, 3.0f);
    EXPECT_EQ(ortho.lensRadius(), 0.0f);
}

TEST(Camera, PolygonalApertureIsUniformOverTheInscribedPolygon) {
    // Five blades turned 18 degrees (corners at 18 + 36 + 72 k degrees, as Cycles places them):
    // every sample lies in the pentagon, and the share within a
    // circle of radius 0.6 (inside the inradius cos 36 = 0.809) is its area over the pentagon's,
    // pi 0.36 / ((5/2) sin 72) = 0.4756, as for uniform samples.
    Camera cam{Path("/cam")};
    cam.setAperture(5, 18.0f);
    const float rot = 18.0f * 3.14159265f / 180.0f, step = 2.0f * 3.14159265f / 5.0f;
    const int n = 200000;
    int inner = 0, outside = 0;
    uint32_t state = 12345u;
    auto next = [&] {  // xorshift32: independent of the renderer's sampler
        state ^= state << 13, state ^= state >> 17, state ^= state << 5;
        return float(state >> 8) * 0x1p-24f;
    };
    for (int i = 0; i < n; ++i) {
        glm::vec2 p = cam.apertureSample({next(), next()});
        inner += glm::dot(p, p) < 0.36f;
        // Inside the pentagon: on the inner side of every edge (distance to the centre along
        // each edge normal at most the inradius).
        for (int k = 0; k < 5; ++k) {
            float a = rot + float(k) * step;  // corners at rot + step/2 + k step: edges face rot + k step
            if (p.x * std::cos(a) + p.y * std::sin(a) > std::cos(step / 2.0f) + 1e-5f) {
                ++outside;
                break;
            }
        }
    }
    EXPECT_EQ(outside, 0);
    const double expected = 3.14159265 * 0.36 / (2.5 * std::sin(2.0 * 3.14159265 / 5.0));
    EXPECT_NEAR(double(inner) / n, expected, 0.005);  // standard error 0.0011
    // Round (fewer than 3 blades): the unit disk, share 0.36.
    cam.setAperture(0, 0.0f);
    inner = 0;
    for (int i = 0; i < n; ++i) {
        glm::vec2 p = cam.apertureSample({next(), next()});
        inner += glm::dot(p, p) < 0.36f;
    }
    EXPECT_NEAR(double(inner) / n, 0.36, 0.005);
}

TEST(Camera, ExposureScaleFollowsTheUsdGeomCameraExposureModel) {
    // responsivity * time * (iso / 100) * 2^exposure / fStop^2 (USD 24 UsdGeomCamera).
    EXPECT_DOUBLE_EQ(Camera::exposureScale(0.0, 1.0, 100.0, 1.0, 1.0), 1.0);  // the fallbacks
    EXPECT_DOUBLE_EQ(Camera::exposureScale(1.0, 1.0, 100.0, 1.0, 1.0), 2.0);  // one stop up
    EXPECT_DOUBLE_EQ(Camera::exposureScale(-2.0, 1.0, 100.0, 1.0, 1.0), 0.25);
    EXPECT_DOUBLE_EQ(Camera::exposureScale(0.0, 0.5, 200.0, 1.0, 1.0), 1.0);  // half the time, twice the ISO
    EXPECT_DOUBLE_EQ(Camera::exposureScale(0.0, 1.0, 100.0, 2.0, 1.0), 0.25);  // f/2 lets in a quarter
    EXPECT_DOUBLE_EQ(Camera::exposureScale(0.0, 1.0 / 125.0, 100.0, 16.0, 1.0), 1.0 / (125.0 * 256.0));
    EXPECT_DOUBLE_EQ(Camera::exposureScale(0.0, 1.0, 100.0, 1.0, 3.0), 3.0);
    EXPECT_DOUBLE_EQ(Camera::exposureScale(0.0, 0.0, 100.0, 1.0, 1.0), 0.0);  // no time: no light
    // Inputs the model has no meaning for give -1 (the camera then keeps 1).
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    EXPECT_EQ(Camera::exposureScale(0.0, 1.0, 100.0, 0.0, 1.0), -1.0);
    EXPECT_EQ(Camera::exposureScale(0.0, 1.0, 100.0, -2.0, 1.0), -1.0);
    EXPECT_EQ(Camera::exposureScale(0.0, -1.0, -100.0, 1.0, 1.0), -1.0);  // a product of two negatives
    EXPECT_EQ(Camera::exposureScale(0.0, 1.0, 100.0, 1.0, -1.0), -1.0);
    EXPECT_EQ(Camera::exposureScale(nan, 1.0, 100.0, 1.0, 1.0), -1.0);
    EXPECT_EQ(Camera::exposureScale(2000.0, 1.0, 100.0, 1.0, 1.0), -1.0);  // 2^2000 overflows
    EXPECT_EQ(Camera::exposureScale(0.0, inf, 100.0, 1.0, 1.0), -1.0);
    EXPECT_GT(Camera::exposureScale(127.0, 1.0, 100.0, 1.0, 1.0), 0.0);  // 2^127 fits a float
    EXPECT_EQ(Camera::exposureScale(128.0, 1.0, 100.0, 1.0, 1.0), -1.0);  // 2^128 does not: the image would go black
    EXPECT_EQ(Camera::exposureScale(0.0, 1.0, 100.0, 1e-30, 1.0), -1.0);
    Camera c{Path("/cam")};
    EXPECT_EQ(c.exposureScale(), 1.0f);
    c.setExposureScale(4.0f);
    EXPECT_EQ(c.exposureScale(), 4.0f);
    c.setExposureScale(-1.0f);
    EXPECT_EQ(c.exposureScale(), 1.0f);
}
