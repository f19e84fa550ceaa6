// Camera: the thin-lens aperture from UsdGeomCamera's fStop, focal length and the stage unit.
#include <gtest/gtest.h>

#include <limits>

#include "delegate/hd/camera.h"

using principled::hd::Camera;
using principled::hd::Path;

namespace {

// A 50 mm lens as the scene delegate hands it over: the authored 50 divided by 10.
Camera fiftyMillimetre(float fStop, float focus, float metersPerUnit) {
    Camera c{Path("/cam")};
    c.set(glm::dmat4(1.0), 5.0f, 3.6f, 2.4f);
    c.setDepthOfField(fStop, focus, metersPerUnit);
    return c;
}

}  // namespace

TEST(Camera, LensRadiusIsFocalLengthOverTwiceTheFNumberInSceneUnits) {
    // f / (2 N) = 50 mm / 4 = 12.5 mm: 1.25 scene units on a centimetre stage, 0.0125 on a metre one.
    EXPECT_FLOAT_EQ(fiftyMillimetre(2.0f, 3.0f, 0.01f).lensRadius(), 1.25f);
    EXPECT_FLOAT_EQ(fiftyMillimetre(2.0f, 3.0f, 1.0f).lensRadius(), 0.0125f);
    EXPECT_FLOAT_EQ(fiftyMillimetre(2.0f, 3.0f, 0.001f).lensRadius(), 12.5f);
    // A near-zero fStop is held to 1000 focus distances (finite ray origins).
    EXPECT_FLOAT_EQ(fiftyMillimetre(1e-30f, 3.0f, 0.01f).lensRadius(), 3000.0f);
}

TEST(Camera, NoLensWithoutAnFStopAFocusDistanceOrAPerspective) {
    EXPECT_EQ(fiftyMillimetre(0.0f, 3.0f, 0.01f).lensRadius(), 0.0f);  // schema fallback fStop
    EXPECT_EQ(fiftyMillimetre(2.0f, 0.0f, 0.01f).lensRadius(), 0.0f);  // schema fallback focus
    EXPECT_EQ(fiftyMillimetre(-1.0f, 3.0f, 0.01f).lensRadius(), 0.0f);
    EXPECT_EQ(fiftyMillimetre(2.0f, std::numeric_limits<float>::infinity(), 0.01f).lensRadius(), 0.0f);
    EXPECT_EQ(fiftyMillimetre(2.0f, 3.0f, 0.0f).lensRadius(), 0.0f);
    EXPECT_EQ(fiftyMillimetre(std::numeric_limits<float>::quiet_NaN(), 3.0f, 0.01f).lensRadius(), 0.0f);
    Camera ortho{Path("/o")};
    ortho.set(glm::dmat4(1.0), 5.0f, 3.6f, 2.4f, Camera::Projection::Orthographic);
    ortho.setDepthOfField(2.0f, 3.0f);
    EXPECT_EQ(ortho.lensRadius(), 0.0f);
}
