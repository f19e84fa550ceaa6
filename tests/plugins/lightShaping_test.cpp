// UsdLux ShapingAPI (delegate/lightShaping.h): the cone falloff curve, and a shaped sphere light
// rendered on a Lambertian plane against the unshaped closed form times the expected factor.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "delegate/lightShaping.h"
#include "plugins/renderSession.h"
#include "tests/support/lambertPlaneScene.h"

using namespace principled;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180.0;

// A Lambert plane y = 0 (albedo a) seen straight down by a tiny orthographic camera at the origin,
// and a sphere light of radius R, radiance L, at (x0, h, 0) aimed straight down (-Y), with the
// given shaping inputs.
std::string scene(double a, double x0, double h, double R, double L, const std::string& shaping) {
    char light[1024];
    std::snprintf(light, sizeof light, R"(
def SphereLight "Spot"
{
    float inputs:radius = %g
    float inputs:intensity = %g
    %s
    double3 xformOp:translate = (%g, %g, 0)
    float xformOp:rotateX = -90
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
}
)",
                  R, L, shaping.c_str(), x0, h);
    return test::planeScene(a, light);
}

double render(const std::string& usda) { return test::planeRadiance(usda, 256); }

}  // namespace

TEST(LightShaping, ConeFalloffIsASmoothstepOverTheSoftFraction) {
    float cone = float(40 * kDeg);
    EXPECT_EQ(embree::coneFalloff(float(39.9 * kDeg), cone, 0.0f), 1.0f);  // hard edge
    EXPECT_EQ(embree::coneFalloff(float(40.1 * kDeg), cone, 0.0f), 0.0f);
    // softness 0.5: full inside 20 degrees, 0.5 at 30 (smoothstep midpoint), 0 from 40.
    EXPECT_EQ(embree::coneFalloff(float(19.9 * kDeg), cone, 0.5f), 1.0f);
    EXPECT_NEAR(embree::coneFalloff(float(30 * kDeg), cone, 0.5f), 0.5f, 1e-5f);
    // 25 degrees is a quarter into the edge: 1 - smoothstep(0.25) = 1 - 0.15625.
    EXPECT_NEAR(embree::coneFalloff(float(25 * kDeg), cone, 0.5f), 0.84375f, 1e-5f);
    EXPECT_EQ(embree::coneFalloff(float(40 * kDeg), cone, 0.5f), 0.0f);
    embree::LightShaping s;
    s.enabled = true;
    s.axis = glm::vec3(0, 0, -1);
    s.coneAngle = float(kPi);
    s.focus = 2.0f;
    glm::vec3 w(std::sin(0.5f), 0.0f, -std::cos(0.5f));
    EXPECT_NEAR(embree::shapingFactor(s, w).x, std::cos(0.5f) * std::cos(0.5f), 1e-5f);
    s.enabled = false;
    EXPECT_EQ(embree::shapingFactor(s, w), glm::vec3(1.0f));
}

TEST(LightShaping, ShapedSphereLightOnAPlane) {
    // The point seen is 22.5 degrees off the light's axis (x0 = h tan 22.5). Unshaped, a small
    // sphere gives E = pi L (R/d)^2 cos(theta_i) (theta_i = 22.5 too) and radiance a E / pi.
    double a = 0.5, h = 3.0, R = 0.05, L = 4000.0, th = 22.5 * kDeg;
    double x0 = h * std::tan(th), d = h / std::cos(th);
    double unshaped = a * L * (R / d) * (R / d) * std::cos(th);
    auto shaped = [&](const std::string& inputs) { return render(scene(a, x0, h, R, L, inputs)); };
    EXPECT_NEAR(shaped(""), unshaped, 0.02 * unshaped);
    EXPECT_NEAR(shaped("float inputs:shaping:cone:angle = 30"), unshaped, 0.02 * unshaped);
    EXPECT_LT(shaped("float inputs:shaping:cone:angle = 20"), 1e-6);
    // softness 0.5 on a 30-degree cone: the edge runs from 15 to 30 degrees, midpoint 22.5.
    double half = shaped("float inputs:shaping:cone:angle = 30\n    float inputs:shaping:cone:softness = 0.5");
    EXPECT_NEAR(half, 0.5 * unshaped, 0.03 * unshaped);
    // focus 2 (cone fallback 90 degrees): cos^2 of the off-axis angle.
    double focused = shaped("float inputs:shaping:focus = 2");
    EXPECT_NEAR(focused, unshaped * std::cos(th) * std::cos(th), 0.02 * unshaped);
}

TEST(LightShaping, IesProfileShapesTheSphereLightOnAPlane) {
    // The same set-up; the point seen is 22.5 degrees off the axis, toward the light's local -X
    // (the light at +x0, aimed down by rotateX -90, keeps world +X as its +X): horizontal angle
    // 180. The profile's plane 180 falls from 100 cd on the axis to 50 at 45 degrees and 0 at 90;
    // every other plane is a fifth of that, so a wrong azimuth reads 0.2 of the expected factor.
    double a = 0.5, h = 3.0, R = 0.05, L = 4000.0, th = 22.5 * kDeg;
    double x0 = h * std::tan(th), d = h / std::cos(th);
    double unshaped = a * L * (R / d) * (R / d) * std::cos(th);
    const std::filesystem::path file =
        std::filesystem::temp_directory_path() / ("principled_ies_" + std::to_string(::getpid()) + ".ies");
    std::ofstream(file) << "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 4 5 1 2 0 0 0\n1 1 10\n0 45 90 180\n"
                           "0 90 180 270 360\n20 10 0 0\n20 10 0 0\n100 50 0 0\n20 10 0 0\n20 10 0 0\n";
    auto shaped = [&](const std::string& more) {
        return render(scene(a, x0, h, R, L, "asset inputs:shaping:ies:file = @" + file.string() + "@\n    " + more));
    };
    // Unnormalized, the profile's peak (100 cd) is the light's own radiance: 75 / 100 here.
    EXPECT_NEAR(shaped(""), 0.75 * unshaped, 0.02 * unshaped);
    // Normalized, its mean over the sphere is. Plane 180 holds a quarter of the azimuths by the
    // bilinear rule (it fades to the neighbouring planes over 90 degrees each way): the mean is
    // the axial profile's, 100 (1 - 2/pi) / 2 on the hemisphere, times (1/4 + 3/4 * 1/5).
    const double mean = 100.0 * (1.0 - 2.0 / kPi) / 2.0 * (0.25 + 0.75 * 0.2);
    EXPECT_NEAR(shaped("bool inputs:shaping:ies:normalize = 1"), 75.0 / mean * unshaped, 0.03 * 75.0 / mean * unshaped);
    // angleScale 0.1: theta_ies = (22.5 - 180) / 1.1 + 180 = 36.82 degrees, I = 59.09 cd.
    const double scaled = 100.0 - 50.0 * ((22.5 - 180.0) / 1.1 + 180.0) / 45.0;
    EXPECT_NEAR(shaped("float inputs:shaping:ies:angleScale = 0.1"), scaled / 100.0 * unshaped, 0.02 * unshaped);
    std::filesystem::remove(file);
}
