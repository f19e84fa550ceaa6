// UsdLux lights against closed-form irradiance on a Lambertian plane (radiance = albedo E / pi),
// rendered through the whole slice from USDA text.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "delegate/colorTemperature.h"
#include "plugins/renderSession.h"
#include "tests/support/sessionRender.h"
#include "tests/support/lambertPlaneScene.h"

using namespace principled;
using principled::test::planeScene;

namespace {

constexpr double kPi = 3.14159265358979323846;

double render(const std::string& usda, int spp, std::map<std::string, std::string> settings = {}) {
    return test::planeRadiance(usda, spp, std::move(settings));
}

// Writes a w x h linear RGB EXR (row 0 = the image's top) into the test's scratch directory.
std::string writeExr(const std::string& name, int w, int h, const std::vector<float>& rgb) {
    auto dir = std::filesystem::temp_directory_path() / "principled_lights_test";
    std::filesystem::create_directories(dir);
    std::string path = (dir / name).string();
    auto out = OIIO::ImageOutput::create(path);
    OIIO::ImageSpec spec(w, h, 3, OIIO::TypeDesc::FLOAT);
    if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::FLOAT, rgb.data())) return "";
    out->close();
    return path;
}

// A black square card (no diffuse, ior 1: no specular but the grazing Schlick term) at height
// y = 1 spanning [-half, half] in x and z, facing down (the camera above sees its back, which a
// single-sided mesh hides from camera rays), for shadow tests; hidden when !visible.
// The disk light of the closed-form tests: radius 1, radiance 10, 2 above the plane, aimed
// down (on-axis E = pi L R^2 / (h^2 + R^2) = 2 pi), with extra inputs.
std::string unitDisk(const std::string& inputs) {
    return R"(
def DiskLight "Disk"
{
    float inputs:radius = 1
    float inputs:intensity = 10
    )" + inputs + R"(
    double3 xformOp:translate = (0, 2, 0)
    float xformOp:rotateX = -90
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
}
)";
}

std::string blackCard(double half, bool visible = true) {
    char points[256];
    std::snprintf(points, sizeof points, "[(%g, 1, %g), (%g, 1, %g), (%g, 1, %g), (%g, 1, %g)]", -half, -half, half,
                  -half, half, half, -half, half);
    return std::string(R"(
def Mesh "Card" (prepend apiSchemas = ["MaterialBindingAPI"])
{
    )") + (visible ? "" : "token visibility = \"invisible\"") + R"(
    uniform token subdivisionScheme = "none"
    int[] faceVertexCounts = [4]
    int[] faceVertexIndices = [0, 1, 2, 3]
    point3f[] points = )" + points + R"(
    rel material:binding = </Black>
}
def Material "Black"
{
    token outputs:surface.connect = </Black/S.outputs:surface>
    def Shader "S"
    {
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor = (0, 0, 0)
        float inputs:ior = 1
        token outputs:surface
    }
}
)";
}

}  // namespace

TEST(Lights, DiskLightOnAxisIrradiance) {
    // A disk of radius R and radiance L at height h: on-axis E = pi L R^2 / (h^2 + R^2).
    double R = 1.0, h = 2.0, L = 10.0, a = 0.5;
    std::string light = R"(
def DiskLight "Disk"
{
    float inputs:radius = 1
    float inputs:intensity = 10
    double3 xformOp:translate = (0, 2, 0)
    float xformOp:rotateX = -90
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
}
)";
    double E = kPi * L * R * R / (h * h + R * R);
    double expected = a * E / kPi;
    EXPECT_NEAR(render(planeScene(a, light), 1024), expected, 0.02 * expected);
}

TEST(Lights, SphereLightIrradianceAndNormalize) {
    // A sphere of radius R, radiance L, centre at distance d along the normal: E = pi L (R/d)^2.
    double R = 0.5, d = 3.0, L = 20.0, a = 0.5;
    std::string light = R"(
def SphereLight "Bulb"
{
    float inputs:radius = 0.5
    float inputs:intensity = 20
    double3 xformOp:translate = (0, 3, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
)";
    double expected = a * L * (R / d) * (R / d);
    EXPECT_NEAR(render(planeScene(a, light, 45.0), 512), expected, 0.02 * expected);
    // normalize = 1 divides the radiance by the area (4 pi R^2).
    std::string normalized = light;
    normalized.insert(normalized.find("float inputs:radius"), "bool inputs:normalize = 1\n    ");
    double area = 4.0 * kPi * R * R;
    EXPECT_NEAR(render(planeScene(a, normalized, 45.0), 512), expected / area, 0.02 * expected / area);
}

TEST(Lights, RectLightMatchesTheDiskOfEqualAreaFarAway) {
    // Far from the light, any small emitter of area A delivers E ~= L A cos / d^2.
    double a = 0.5, L = 100.0, A = 0.04, dist = 10.0;
    std::string light = R"(
def RectLight "Panel"
{
    float inputs:width = 0.2
    float inputs:height = 0.2
    float inputs:intensity = 100
    double3 xformOp:translate = (0, 10, 0)
    float xformOp:rotateX = -90
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
}
)";
    double expected = a * (L * A / (dist * dist)) / kPi;
    EXPECT_NEAR(render(planeScene(a, light), 256), expected, 0.01 * expected);
    // The back of the panel does not emit: flipped, it lights nothing below (the tilted camera
    // does not see the panel itself).
    std::string flipped = light;
    flipped.replace(flipped.find("rotateX = -90"), 13, "rotateX = 90");
    EXPECT_EQ(render(planeScene(a, flipped, 45.0), 16), 0.0);
}

TEST(Lights, DomeTextureIsImportanceSampledAndMatchesTheConstantDome) {
    // A lat-long texture that is 2 in the upper half and 0 below: the upward-facing plane sees
    // radiance 2 over its whole hemisphere, so E = 2 pi and the plane's radiance is 2a.
    const int w = 64, h = 32;
    std::vector<float> px(w * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 3; ++c) px[(y * w + x) * 3 + c] = y < h / 2 ? 2.0f : 0.0f;
    std::string path = writeExr("half.exr", w, h, px);
    ASSERT_FALSE(path.empty());
    double a = 0.5;
    std::string light = "def DomeLight \"Sky\"\n{\n    asset inputs:texture:file = @" + path + "@\n}\n";
    double mis = render(planeScene(a, light), 512);
    double nee = render(planeScene(a, light), 512, {{"mis", "0"}});
    EXPECT_NEAR(mis, 2.0 * a, 0.02 * 2.0 * a);
    EXPECT_NEAR(nee, 2.0 * a, 0.02 * 2.0 * a);
}

TEST(Lights, DomeMisCompensationKeepsTheMeanAndCutsTheNoise) {
    // A lat-long sky of radiance 0.5 over a ground of 0.1, with a 2 x 2-texel sun of 400.
    // The plane's radiance is a E / pi with E summed exactly over the texels (nearest-texel
    // lookup: piecewise constant): texel rows [t0, t1] from the +Y pole give
    // L * dphi * (sin^2 t1 - sin^2 t0) / 2 when above the horizon.
    const int w = 64, h = 32;
    std::vector<float> px(w * h * 3);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            float v = y < h / 2 ? 0.5f : 0.1f;
            if ((y == 7 || y == 8) && (x == 20 || x == 21)) v = 400.0f;
            for (int c = 0; c < 3; ++c) px[(y * w + x) * 3 + c] = v;
        }
    std::string path = writeExr("sunsky.exr", w, h, px);
    ASSERT_FALSE(path.empty());
    double E = 0.0;
    for (int y = 0; y < h / 2; ++y) {
        const double t0 = kPi * y / h, t1 = kPi * (y + 1) / h;
        const double band = (2.0 * kPi / w) * 0.5 * (std::sin(t1) * std::sin(t1) - std::sin(t0) * std::sin(t0));
        for (int x = 0; x < w; ++x) E += px[(y * w + x) * 3] * band;
    }
    const double a = 0.5, expected = a * E / kPi;
    std::string light = "def DomeLight \"Sky\"\n{\n    asset inputs:texture:file = @" + path + "@\n}\n";
    const std::string scene = planeScene(a, light);
    // The mean: compensated (the default), the whole map with MIS, NEE alone (which must sample
    // the whole map) and BSDF sampling alone.
    // Tolerances: over seeds 0-9 the first three came within +0.017 % to +0.047 % of the texel
    // sum and BSDF sampling alone within 0.55 %; a light pdf that differs between NEE and the
    // MIS weight of escaped rays is biased by about 0.9 % here.
    EXPECT_NEAR(render(scene, 1024), expected, 0.003 * expected);
    EXPECT_NEAR(render(scene, 4096, {{"misCompensation", "0"}}), expected, 0.004 * expected);
    EXPECT_NEAR(render(scene, 4096, {{"mis", "0"}}), expected, 0.004 * expected);
    EXPECT_NEAR(render(scene, 16384, {{"nee", "0"}}), expected, 0.03 * expected);
    // The noise: per-pixel variance over 16 pixels x 8 seeds at 16 spp. The sky, below the mean,
    // is left to cosine sampling, which fits it exactly; NEE spends its samples on the sun.
    auto variance = [&](std::map<std::string, std::string> settings) {
        double sum = 0.0, squares = 0.0;
        int n = 0;
        for (int seed = 0; seed < 8; ++seed)
            for (double v : test::planePixels(scene, 16, settings, 0, seed)) {
                sum += v;
                squares += v * v;
                ++n;
            }
        return (squares - sum * sum / n) / (n - 1);
    };
    const double compensated = variance({}), whole = variance({{"misCompensation", "0"}});
    EXPECT_LT(compensated, 0.7 * whole) << "compensated " << compensated << ", whole map " << whole;
}

namespace {

// side x side sphere lamps (radius 0.3, three strengths) 0.6 above a Lambertian floor on a grid
// of the given pitch centred on the origin, seen from above by an orthographic camera of the
// given width, with a dim dome and a white wall across the middle (so paths bounce: the MIS
// weights of later vertices use their own picks).
// With coneDeg > 0 the lamps are spot lights aimed straight down from `height` (ShapingAPI cone).
std::string lampGridScene(int side, double pitch, double width, double coneDeg = 0.0, double height = 0.6) {
    std::string lamps = R"(def DomeLight "Sky"
{
    float inputs:intensity = 0.05
}
def Mesh "Wall"
{
    uniform token subdivisionScheme = "none"
    int[] faceVertexCounts = [4]
    int[] faceVertexIndices = [0, 1, 2, 3]
    point3f[] points = [(-100, 0, 0.5), (100, 0, 0.5), (100, 1.5, 0.5), (-100, 1.5, 0.5)]
    uniform bool doubleSided = 1
}
)";
    const double first = -0.5 * pitch * (side - 1);
    for (int k = 0; k < side * side; ++k) {
        char buf[768];
        if (coneDeg > 0.0)
            std::snprintf(buf, sizeof buf, R"(def SphereLight "L%d" (prepend apiSchemas = ["ShapingAPI"])
{
    float inputs:radius = 0.3
    float inputs:intensity = %d
    float inputs:shaping:cone:angle = %g
    double3 xformOp:translate = (%g, %g, %g)
    float xformOp:rotateX = -90
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
}
)",
                          k, 20 * (1 + k % 3), coneDeg, first + pitch * (k / side), height, first + pitch * (k % side));
        else
            std::snprintf(buf, sizeof buf, R"(def SphereLight "L%d"
{
    float inputs:radius = 0.3
    float inputs:intensity = %d
    double3 xformOp:translate = (%g, %g, %g)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
)",
                          k, 20 * (1 + k % 3), first + pitch * (k / side), height, first + pitch * (k % side));
        lamps += buf;
    }
    char camera[512];
    std::snprintf(camera, sizeof camera, R"(def Camera "Cam"
{
    token projection = "orthographic"
    float horizontalAperture = %g
    float verticalAperture = %g
    float2 clippingRange = (0.001, 1000)
    double3 xformOp:translate = (0, 20, 0)
    float xformOp:rotateX = -90
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
}
)",
                  width * 10.0, width * 10.0);  // apertures in tenths of a scene unit
    return std::string(R"(#usda 1.0
def Mesh "Floor" (prepend apiSchemas = ["MaterialBindingAPI"])
{
    uniform token subdivisionScheme = "none"
    int[] faceVertexCounts = [4]
    int[] faceVertexIndices = [0, 1, 2, 3]
    point3f[] points = [(-100, 0, -100), (-100, 0, 100), (100, 0, 100), (100, 0, -100)]
    rel material:binding = </Mat>
}
def Material "Mat"
{
    token outputs:surface.connect = </Mat/S.outputs:surface>
    def Shader "S"
    {
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor = (0.5, 0.5, 0.5)
        float inputs:roughness = 0.6
        token outputs:surface
    }
}
)") + camera + lamps;
}

// The spatial pick against the power-only pick on a lamp grid: the same image mean, and per-pixel
// variance at most maxVarianceRatio of the power-only pick's.
void expectSpatialPickKeepsTheMeanAndCutsTheNoise(const std::string& usda, double maxVarianceRatio) {
    // The image's red values (32 x 32) for a seed, spp and pick.
    auto image = [&](int spp, int seed, const char* spatial) {
        host::SessionOptions o;
        o.width = o.height = 32;
        o.samplesPerPixel = spp;
        o.seed = seed;
        o.settings = {{"spatialLightPick", spatial}, {"maxDepth", "2"}};
        auto session = host::RenderSession::openString(usda, "lamps.usda", o);
        while (!session->step()) {
        }
        std::vector<double> v(32 * 32);
        for (int i = 0; i < 32 * 32; ++i) v[i] = session->color()[4 * i];
        return v;
    };
    auto mean = [](const std::vector<double>& v) {
        double m = 0.0;
        for (double x : v) m += x / double(v.size());
        return m;
    };
    // The means agree; the power-only pick is the noisy one (its image mean's standard error at
    // 1024 spp is about 0.4 %), so the tolerance is 1.5 %.
    const double spatialMean = mean(image(256, 1, "1")), globalMean = mean(image(1024, 2, "0"));
    EXPECT_NEAR(spatialMean, globalMean, 0.015 * globalMean);
    // Per-pixel variance over 6 seeds at 8 spp.
    auto variance = [&](const char* spatial) {
        std::vector<std::vector<double>> runs;
        for (int seed = 0; seed < 6; ++seed) runs.push_back(image(8, seed, spatial));
        double sum = 0.0;
        for (int i = 0; i < 32 * 32; ++i) {
            double m = 0.0, q = 0.0;
            for (const auto& r : runs) m += r[i] / 6.0;
            for (const auto& r : runs) q += (r[i] - m) * (r[i] - m) / 5.0;
            sum += q / (32.0 * 32.0);
        }
        return sum;
    };
    const double spatialVar = variance("1"), globalVar = variance("0");
    EXPECT_LT(spatialVar, maxVarianceRatio * globalVar) << "spatial " << spatialVar << ", by power " << globalVar;
}

}  // namespace

TEST(Lights, SpatialPickKeepsTheMeanAndCutsTheNoiseAmongManyLamps) {
    // Sixteen lamps on a 4 x 4 grid of pitch 5. Picked by power alone, a floor point mostly
    // samples lamps far away; weighed by 1 / d^2 (delegate/lightPick.h) it samples the ones next
    // to it.
    expectSpatialPickKeepsTheMeanAndCutsTheNoise(lampGridScene(4, 5.0, 20.0), 0.2);
}

TEST(Lights, TreePickKeepsTheMeanAndCutsTheNoiseAmongHundredsOfLamps) {
    // 144 lamps (12 x 12, pitch 4): more than LightPick::kMaxLights, so the local lamps are
    // picked through a LightTree (delegate/lightTree.h); the camera sees the middle 20 x 20.
    expectSpatialPickKeepsTheMeanAndCutsTheNoise(lampGridScene(12, 4.0, 20.0), 0.1);
}

TEST(Lights, SpotsWhoseConesMissThePointAreNotPicked) {
    // Sixteen spots 3 above the floor, cones of 25 degrees: each floor point lies in at most one
    // cone. Weighed by 1 / d^2 alone, the pick spends most samples on the nearest spots whose
    // cones miss the point; the reach test (delegate/lightPick.h) gives those weight 0.
    // Measured: 0.0046 of the power pick's variance, 0.022 without the cone test.
    expectSpatialPickKeepsTheMeanAndCutsTheNoise(lampGridScene(4, 5.0, 20.0, 25.0, 3.0), 0.01);
}

TEST(Lights, PortalsKeepTheMeanAndCutTheNoiseOfASkyThroughAWindow) {
    // A closed 4 x 2 x 4 room under a constant sky, lit through a 1 x 1 opening in its ceiling;
    // a tiny orthographic camera inside looks down at the floor below the opening. Without the
    // portal, next-event estimation draws cosine directions of which ~8 % leave through the
    // opening; with it, half of the samples go through (delegate/portalSampling.h). The portal
    // guides sampling only: the same image mean.
    auto quad = [](const char* name, const char* pts) {
        return std::string("def Mesh \"") + name + "\"\n{\n    uniform token subdivisionScheme = \"none\"\n"
               "    int[] faceVertexCounts = [4]\n    int[] faceVertexIndices = [0, 1, 2, 3]\n"
               "    point3f[] points = [" + pts + "]\n    uniform bool doubleSided = 1\n"
               "    rel material:binding = </Mat>\n}\n";
    };
    std::string room = std::string(R"(#usda 1.0
def DomeLight "Sky"
{
    float inputs:intensity = 1
}
def Material "Mat"
{
    token outputs:surface.connect = </Mat/S.outputs:surface>
    def Shader "S"
    {
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor = (0.5, 0.5, 0.5)
        float inputs:roughness = 1
        token outputs:surface
    }
}
def Camera "Cam"
{
    token projection = "orthographic"
    float horizontalAperture = 0.01
    float verticalAperture = 0.01
    float2 clippingRange = (0.001, 10)
    double3 xformOp:translate = (0, 1.9, 0)
    float xformOp:rotateX = -90
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
}
)") + quad("Floor", "(-2, 0, -2), (-2, 0, 2), (2, 0, 2), (2, 0, -2)") +
                       quad("WallA", "(-2, 0, -2), (2, 0, -2), (2, 2, -2), (-2, 2, -2)") +
                       quad("WallB", "(-2, 0, 2), (2, 0, 2), (2, 2, 2), (-2, 2, 2)") +
                       quad("WallC", "(-2, 0, -2), (-2, 0, 2), (-2, 2, 2), (-2, 2, -2)") +
                       quad("WallD", "(2, 0, -2), (2, 0, 2), (2, 2, 2), (2, 2, -2)") +
                       // The ceiling around the opening [-0.5, 0.5]^2.
                       quad("CeilN", "(-2, 2, -2), (2, 2, -2), (2, 2, -0.5), (-2, 2, -0.5)") +
                       quad("CeilS", "(-2, 2, 0.5), (2, 2, 0.5), (2, 2, 2), (-2, 2, 2)") +
                       quad("CeilW", "(-2, 2, -0.5), (-0.5, 2, -0.5), (-0.5, 2, 0.5), (-2, 2, 0.5)") +
                       quad("CeilE", "(0.5, 2, -0.5), (2, 2, -0.5), (2, 2, 0.5), (0.5, 2, 0.5)");
    // The portal fills the opening; rotateX -90 turns its light direction (-Z) to -Y.
    const std::string portal = room + R"(def PortalLight "Window"
{
    float inputs:width = 1
    float inputs:height = 1
    double3 xformOp:translate = (0, 2, 0)
    float xformOp:rotateX = -90
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
}
)";
    auto stats = [](const std::string& usda, int spp, int seeds) {
        double sum = 0.0, squares = 0.0;
        int n = 0;
        for (int seed = 0; seed < seeds; ++seed)
            for (double v : test::planePixels(usda, spp, {{"shadingModel", "ue4"}}, 3, seed)) {
                sum += v;
                squares += v * v;
                ++n;
            }
        const double mean = sum / n;
        return std::pair<double, double>(mean, (squares - sum * mean) / (n - 1));
    };
    const auto [meanPortal, varPortal] = stats(portal, 64, 16);
    const auto [meanPlain, varPlain] = stats(room, 64, 16);
    const auto [reference, unusedVar] = stats(room, 2048, 4);
    (void)unusedVar;
    EXPECT_NEAR(meanPortal, reference, 0.03 * reference);
    EXPECT_NEAR(meanPlain, reference, 0.05 * reference);
    // Measured: variance 7.3e-7 against 4.0e-5; escaped rays weighed without the portals'
    // density (the MIS pdf NEE did not use) made the mean 46 % high.
    EXPECT_LT(varPortal, 0.1 * varPlain) << "portal " << varPortal << ", without " << varPlain;
}

TEST(Lights, MisWeightsOfLightsBehindAPartlyPresentSheetAreTakenFromTheVertex) {
    // A floor lit by a sphere lamp through a sheet of opacity 0.5. A BSDF sample from the floor
    // that passes through the sheet and hits the lamp must be MIS-weighted with the density NEE
    // had at the floor point, not at the sheet (where the ray restarted): measured, that mistake
    // made the MIS image 15 % brighter than NEE alone (5.12 against 4.47).
    const std::string lamp = R"(
def SphereLight "Lamp"
{
    float inputs:radius = 0.3
    float inputs:intensity = 40
    double3 xformOp:translate = (0, 0.6, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
def Mesh "Sheet" (prepend apiSchemas = ["MaterialBindingAPI"])
{
    uniform token subdivisionScheme = "none"
    int[] faceVertexCounts = [4]
    int[] faceVertexIndices = [0, 1, 2, 3]
    point3f[] points = [(-3, 0.3, -3), (-3, 0.3, 3), (3, 0.3, 3), (3, 0.3, -3)]
    rel material:binding = </Veil>
}
def Material "Veil"
{
    token outputs:surface.connect = </Veil/S.outputs:surface>
    def Shader "S"
    {
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor = (0.2, 0.2, 0.2)
        float inputs:opacity = 0.5
        token outputs:surface
    }
}
)";
    // planeScene's tiny camera looks at the floor's origin, under the lamp, through the sheet.
    const std::string scene = planeScene(0.5, lamp, 30.0);
    const double mis = render(scene, 2048, {{"maxDepth", "1"}}), nee = render(scene, 2048, {{"maxDepth", "1"}, {"mis", "0"}});
    ASSERT_GT(nee, 0.0);
    EXPECT_NEAR(mis, nee, 0.02 * nee);
}

TEST(Lights, BlackbodyHasUnitLuminanceAndTheRightHue) {
    for (float k : {2000.0f, 3000.0f, 6500.0f, 10000.0f}) {
        glm::vec3 c = embree::blackbodyColor(k);
        EXPECT_NEAR(0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z, 1.0f, 0.02f) << k;
    }
    glm::vec3 warm = embree::blackbodyColor(3000.0f), d65 = embree::blackbodyColor(6500.0f),
              cool = embree::blackbodyColor(12000.0f);
    EXPECT_GT(warm.x, warm.z * 2.0f);
    EXPECT_NEAR(d65.x / d65.z, 1.0f, 0.1f);  // 6500 K is close to the D65 white
    EXPECT_GT(cool.z, cool.x);
}

TEST(Lights, EmissiveQuadMatchesTheRectLightUnderEveryStrategy) {
    // A 1x1 emissive quad of radiance 5, 1 unit above the plane, delivers the same irradiance
    // as a RectLight of the same size and radiance (emission is found by NEE as a mesh light
    // and by BSDF sampling, MIS-weighted).
    double a = 0.5;
    std::string rect = R"(
def RectLight "Panel"
{
    float inputs:width = 1
    float inputs:height = 1
    float inputs:intensity = 5
    double3 xformOp:translate = (0, 1, 0)
    float xformOp:rotateX = -90
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
}
)";
    std::string quad = R"(
def Mesh "Emitter" (prepend apiSchemas = ["MaterialBindingAPI"])
{
    uniform token subdivisionScheme = "none"
    int[] faceVertexCounts = [4]
    int[] faceVertexIndices = [0, 1, 2, 3]
    point3f[] points = [(-0.5, 1, -0.5), (0.5, 1, -0.5), (0.5, 1, 0.5), (-0.5, 1, 0.5)]
    rel material:binding = </Glow>
}
def Material "Glow"
{
    token outputs:surface.connect = </Glow/S.outputs:surface>
    def Shader "S"
    {
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor = (0, 0, 0)
        color3f inputs:emissiveColor = (5, 5, 5)
        token outputs:surface
    }
}
)";
    double reference = render(planeScene(a, rect, 45.0), 1024);
    ASSERT_GT(reference, 0.0);
    for (auto [nee, mis] : {std::pair{"1", "1"}, {"1", "0"}, {"0", "1"}}) {
        double v = render(planeScene(a, quad, 45.0), nee[0] == '0' ? 4096 : 1024, {{"nee", nee}, {"mis", mis}});
        EXPECT_NEAR(v, reference, 0.03 * reference) << "nee " << nee << " mis " << mis;
    }
}

TEST(Lights, RectLightTextureReadsUprightAndUnmirroredFromTheLitSide) {
    // A 2x2 texture (red, green / blue, white) on a 2x2 RectLight at the origin (emitting along
    // -Z), seen head-on from its lit side by an orthographic camera at z = -5 whose frame is the
    // light's seen from the front (right = -X, up = +Y): the image must look like the file,
    // each quadrant at radiance intensity * texel.
    std::string tex = writeExr("quadrants.exr", 2, 2, {1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1});
    ASSERT_FALSE(tex.empty());
    std::string usda = R"(#usda 1.0
def RectLight "Panel"
{
    float inputs:width = 2
    float inputs:height = 2
    float inputs:intensity = 3
    asset inputs:texture:file = @)" + tex + R"(@
}
def Camera "Cam"
{
    token projection = "orthographic"
    float horizontalAperture = 20
    float verticalAperture = 20
    double3 xformOp:translate = (0, 0, -5)
    float xformOp:rotateY = 180
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateY"]
}
)";
    host::SessionOptions o;
    o.width = o.height = 4;
    o.samplesPerPixel = 4;
    o.settings["lightCameraVisibility"] = "1";  // lights are hidden from camera rays by default
    auto s = host::RenderSession::openString(usda, "rect_texture.usda", o);
    while (!s->step()) {
    }
    const float* c = s->color();
    auto px = [&](int x, int y) { return glm::vec3(c[4 * (y * 4 + x)], c[4 * (y * 4 + x) + 1], c[4 * (y * 4 + x) + 2]); };
    const glm::vec3 expected[2][2] = {{{3, 0, 0}, {0, 3, 0}}, {{0, 0, 3}, {3, 3, 3}}};  // [row][column]
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            for (int k = 0; k < 3; ++k)
                EXPECT_NEAR(px(x, y)[k], expected[y / 2][x / 2][k], 1e-4) << "pixel " << x << "," << y;
}

TEST(Lights, LightShapesAreHiddenFromCameraRaysUnlessAsked) {
    // Cycles, Karma and hdEmbree do not draw sphere/rect/disk lights for camera rays; with
    // lightCameraVisibility = 1 the camera sees the emitting shape at its radiance.
    std::string usda = R"(#usda 1.0
def SphereLight "Bulb"
{
    float inputs:radius = 1
    float inputs:intensity = 7
}
def Camera "Cam"
{
    token projection = "orthographic"
    float horizontalAperture = 5
    float verticalAperture = 5
    double3 xformOp:translate = (0, 0, 5)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
)";
    for (const char* visible : {"0", "1"}) {
        host::SessionOptions o;
        o.width = o.height = 4;
        o.samplesPerPixel = 1;
        o.settings["defaultLighting"] = "0";
        if (visible[0] == '1') o.settings["lightCameraVisibility"] = "1";
        auto s = host::RenderSession::openString(usda, "bulb.usda", o);
        while (!s->step()) {
        }
        const float* c = s->color();
        // The centre pixels look straight at the sphere.
        EXPECT_NEAR(c[4 * (1 * 4 + 1)], visible[0] == '1' ? 7.0f : 0.0f, 1e-3f) << "visible " << visible;
    }
}

TEST(Lights, RectLightTextureScalesTheIrradianceItDelivers) {
    // The far-field panel of RectLightMatchesTheDiskOfEqualAreaFarAway with a uniform 0.25
    // texture delivers a quarter of the irradiance (NEE weights each sample by its texel).
    std::string tex = writeExr("quarter.exr", 4, 4, std::vector<float>(48, 0.25f));
    ASSERT_FALSE(tex.empty());
    double a = 0.5, L = 100.0, A = 0.04, dist = 10.0;
    std::string light = R"(
def RectLight "Panel"
{
    float inputs:width = 0.2
    float inputs:height = 0.2
    float inputs:intensity = 100
    asset inputs:texture:file = @)" + tex + R"(@
    double3 xformOp:translate = (0, 10, 0)
    float xformOp:rotateX = -90
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
}
)";
    double expected = 0.25 * a * (L * A / (dist * dist)) / kPi;
    EXPECT_NEAR(render(planeScene(a, light), 256), expected, 0.01 * expected);
}

TEST(Lights, ShadowDisabledLightsReachThroughOccluders) {
    // A disk light (R = 1, L = 10, h = 2) over the plane, a black 1.2 x 1.2 card at height 1
    // between them; the camera looks at the origin from 60 degrees off vertical, past the card.
    // UsdLux ShadowAPI shadow:enable = 0: the card casts no shadow, the closed form holds.
    auto scene = [](const std::string& shadowInput, bool card = true) {
        return planeScene(0.5, unitDisk(shadowInput) + R"(
def SphereLight "Bulb"
{
    float inputs:radius = 0.1
    float inputs:intensity = 50
    )" + shadowInput + R"(
    double3 xformOp:translate = (0, 1.6, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
)" + blackCard(0.6, card),
                          60.0);
    };
    // Disk: E = pi L R^2 / (h^2 + R^2); sphere (radius r, radiance Ls, distance d): E = pi Ls (r/d)^2.
    const double a = 0.5;
    const double E = kPi * 10.0 * 1.0 / (4.0 + 1.0) + kPi * 50.0 * (0.1 / 1.6) * (0.1 / 1.6);
    const double expected = a * E / kPi;
    const double lit = render(scene("bool inputs:shadow:enable = 0"), 1024);
    EXPECT_NEAR(lit, expected, 0.03 * expected);
    // Nothing in the way: BSDF-sampled hits on the lights must not add to NEE's full weight.
    EXPECT_NEAR(render(scene("bool inputs:shadow:enable = 0", false), 1024), expected, 0.03 * expected);
    // Without MIS the same light arrives (it is NEE's alone either way).
    EXPECT_NEAR(render(scene("bool inputs:shadow:enable = 0"), 1024, {{"mis", "0"}}), expected, 0.03 * expected);
    // Shadowed (the default), the card takes nearly all of both lights.
    EXPECT_LT(render(scene(""), 256), 0.25 * expected);
}

TEST(Lights, DiffuseAndSpecularMultipliersScaleTheirLobesUnderEveryStrategy) {
    // UsdLux LightAPI inputs:diffuse / inputs:specular on a disk light (R = 1, L = 10, h = 2)
    // over the Lambertian plane: the diffuse multiplier scales the closed form, the specular one
    // leaves it (the plane has no specular lobe); NEE alone, BSDF sampling alone and MIS agree.
    auto scene = [](const std::string& inputs) {
        return planeScene(0.5, unitDisk(inputs) + R"(
)");
    };
    const double expected = 0.5 * 10.0 * 1.0 / (4.0 + 1.0);  // a E / pi
    for (const auto& strategy : std::vector<std::map<std::string, std::string>>{{}, {{"mis", "0"}}, {{"nee", "0"}}}) {
        const int spp = strategy.count("nee") ? 4096 : 1024;
        EXPECT_NEAR(render(scene("float inputs:diffuse = 0.25"), spp, strategy), 0.25 * expected, 0.03 * 0.25 * expected);
        EXPECT_NEAR(render(scene("float inputs:specular = 0"), spp, strategy), expected, 0.03 * expected);
    }
    // Only the plane's grazing Schlick specular (ior 1: F0 = 0) is left.
    EXPECT_LT(render(scene("float inputs:diffuse = 0"), 64), 1e-3 * expected);
}

TEST(Lights, LightLinkingLightsOnlyTheLinkedPrimsUnderEveryStrategy) {
    // UsdLux collection:lightLink on a disk light (R = 1, L = 10, h = 2) over the plane: linked
    // (the schema's includeRoot = true, or the plane included explicitly) it gives the closed
    // form; with the plane excluded, or only another prim included, nothing (NEE skips the
    // light, BSDF rays that reach it add nothing).
    auto scene = [](const std::string& link) {
        return planeScene(0.5, unitDisk(link) + R"(
def Sphere "Other" { double radius = 0.1
    double3 xformOp:translate = (30, 1, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"] }
)");
    };
    const double expected = 0.5 * 10.0 * 1.0 / (4.0 + 1.0);
    const std::string onlyPlane = "uniform bool collection:lightLink:includeRoot = 0\n    rel collection:lightLink:includes = </Plane>";
    const std::string onlyOther = "uniform bool collection:lightLink:includeRoot = 0\n    rel collection:lightLink:includes = </Other>";
    const std::string allButPlane = "rel collection:lightLink:excludes = </Plane>";
    for (const auto& strategy : std::vector<std::map<std::string, std::string>>{{}, {{"mis", "0"}}, {{"nee", "0"}}}) {
        const int spp = strategy.count("nee") ? 4096 : 1024;
        EXPECT_NEAR(render(scene(onlyPlane), spp, strategy), expected, 0.03 * expected);
        EXPECT_LT(render(scene(onlyOther), 256, strategy), 1e-3 * expected);
        EXPECT_LT(render(scene(allButPlane), 256, strategy), 1e-3 * expected);
    }
    EXPECT_NEAR(render(scene(""), 1024), expected, 0.03 * expected);
}

TEST(Lights, PointLightsCarryTheSpherePowerAndZeroRadiusReadsAsNormalized) {
    // A SphereLight at height h = 2 over the plane. treatAsPoint keeps the sphere's power
    // (radiant intensity I = L pi r^2; E = I / h^2 straight below); radius 0 is read as
    // normalized (I = L / 4, the r -> 0 limit of a normalized sphere), not as black. Spot
    // shaping still applies to a point.
    auto scene = [](const std::string& inputs) {
        return planeScene(0.5, R"(
def SphereLight "Bulb"
{
    float inputs:intensity = 40
    )" + inputs + R"(
    double3 xformOp:translate = (0, 2, 0)
    float xformOp:rotateX = -90
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
}
)");
    };
    const double a = 0.5, h = 2.0;
    const double sphere = a * (40.0 * kPi * 0.3 * 0.3) / (h * h) / kPi;  // a E / pi
    EXPECT_NEAR(render(scene("float inputs:radius = 0.3\n    bool treatAsPoint = 1"), 64), sphere, 1e-3 * sphere);
    EXPECT_NEAR(render(scene("float inputs:radius = 0.3"), 1024), sphere, 0.02 * sphere);  // the real sphere agrees
    const double zero = a * (40.0 / 4.0) / (h * h) / kPi;
    EXPECT_NEAR(render(scene("float inputs:radius = 0"), 64), zero, 1e-3 * zero);
    EXPECT_NEAR(render(scene("float inputs:radius = 0.3\n    bool treatAsPoint = 1\n    bool inputs:normalize = 1"), 64),
                zero, 1e-3 * zero);
    // A 30-degree cone straight down (the light looks along its -Z) lights the point below.
    EXPECT_NEAR(render(scene("float inputs:radius = 0\n    float inputs:shaping:cone:angle = 30"), 64), zero, 1e-3 * zero);
}

TEST(Lights, AShadowlessTexturedDomeIgnoresOccludersWithMisCompensation) {
    // MIS compensation leaves the dome's dim texels to BSDF rays, which an occluder blocks; a
    // dome without shadows is therefore sampled whole: under a black card over the whole plane
    // compensation on and off agree (they differed by the dim half's 9 %), and both match the
    // open plane up to the light the card's grazing specular sends back (~1.5 %).
    std::vector<float> rgb(64 * 32 * 3);
    for (int y = 0; y < 32; ++y)
        for (int x = 0; x < 64; ++x)
            for (int c = 0; c < 3; ++c) rgb[3 * (y * 64 + x) + c] = x < 32 ? 10.0f : 1.0f;
    const std::string tex = writeExr("halves.exr", 64, 32, rgb);
    ASSERT_FALSE(tex.empty());
    auto scene = [&](bool card) {
        return planeScene(0.5, R"(
def DomeLight "Sky"
{
    asset inputs:texture:file = @)" + tex + R"(@
    token inputs:texture:format = "latlong"
    bool inputs:shadow:enable = 0
}
)" + (card ? blackCard(40.0) : std::string()), 60.0);
    };
    // The card faces away from the camera, which sees the plane through its back.
    const double open = render(scene(false), 2048);
    const double covered = render(scene(true), 2048, {{"misCompensation", "0"}, {"backfaceCulling", "1"}});
    EXPECT_NEAR(render(scene(true), 2048, {{"backfaceCulling", "1"}}), covered, 0.005 * covered);
    EXPECT_NEAR(covered, open, 0.03 * open);
}

TEST(Lights, ShadowLinkingLetsTheLightThroughPrimsOutsideTheCollection) {
    // UsdLux collection:shadowLink: the black card between the disk light and the plane casts
    // the light's shadow only while it is in the collection (the schema's includeRoot = true).
    // Excluded, the plane gets the closed form with and without MIS; named in a collection that
    // leaves out the root, it shadows as by default.
    auto scene = [](const std::string& link) {
        return planeScene(0.5, unitDisk(link) + R"(
)" + blackCard(0.6), 60.0);
    };
    const double expected = 0.5 * 10.0 * 1.0 / (4.0 + 1.0);
    const std::string excluded = "rel collection:shadowLink:excludes = </Card>";
    for (const auto& strategy : std::vector<std::map<std::string, std::string>>{{}, {{"mis", "0"}}})
        EXPECT_NEAR(render(scene(excluded), 1024, strategy), expected, 0.03 * expected);
    EXPECT_LT(render(scene(""), 256), 0.25 * expected);
    EXPECT_LT(render(scene("uniform bool collection:shadowLink:includeRoot = 0\n    rel collection:shadowLink:includes = </Card>"), 256),
              0.25 * expected);
}

namespace {
// A glossy plane (roughness 0.4, ior 1.5) seen at 45 degrees; the diffuse and specular AOV
// means of a 4 x 4 render.
std::map<std::string, double> lobeAovMeans(const std::string& lights, int spp, std::map<std::string, std::string> settings) {
    const std::string usda = planeScene(0.5, lights, 45.0, 1.5, 0.4);
    host::SessionOptions o;
    o.width = o.height = 4;
    o.samplesPerPixel = spp;
    o.aovs = {"diffuse", "specular"};
    o.settings = std::move(settings);
    auto s = host::RenderSession::openString(usda, "glossy.usda", o);
    while (!s->step()) {
    }
    std::map<std::string, double> out;
    for (const auto& a : s->aovs()) {
        if (a.isInt) continue;
        double sum = 0;
        for (int i = 0; i < 16; ++i) sum += static_cast<const float*>(a.pixels)[a.components * i];
        out[a.name] = sum / 16;
    }
    return out;
}
}  // namespace

TEST(Lights, LobeAovsFollowTheMultipliersOfTheLightTheyShow) {
    // inputs:diffuse = 0 on a disk light over a glossy plane: the diffuse AOV is 0 whether the
    // light is found by NEE or by BSDF sampling (it was 0.20 with BSDF sampling alone).
    const std::string light = R"(
def DiskLight "Disk"
{
    float inputs:radius = 3
    float inputs:intensity = 10
    float inputs:diffuse = 0
    double3 xformOp:translate = (0, 4, -4)
    float xformOp:rotateX = -135
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
}
)";
    for (const auto& st : std::vector<std::map<std::string, std::string>>{{}, {{"mis", "0"}}, {{"nee", "0"}}}) {
        auto m = lobeAovMeans(light, st.count("nee") ? 4096 : 1024, st);
        EXPECT_LT(m["diffuse"], 1e-3 * m["specular"]);
        EXPECT_GT(m["specular"], 0.3);
    }
}

TEST(Lights, AZeroScaleSphereLightStaysDark) {
    // Scaling a sphere light to nothing hides it (a zero radius authored is a point; a zero
    // scale is not).
    const std::string l = R"(
def SphereLight "Bulb"
{
    float inputs:radius = 0.5
    float inputs:intensity = 40
    double3 xformOp:translate = (0, 2, 0)
    float3 xformOp:scale = (0, 0, 0)
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:scale"]
}
)";
    EXPECT_LT(render(planeScene(0.5, l, 45.0), 64), 1e-6);
}

namespace {
// Two instances (or PointInstancer placements) of a unit quad at x = -2 and x = 2, lit by a
// head-on sun linked to `target`; the red sums of the left and right halves of a 48 x 36 image.
std::pair<double, double> linkedHalves(const std::string& scene) {
    host::SessionOptions o;
    o.width = 48;
    o.height = 36;
    o.samplesPerPixel = 4;
    auto s = host::RenderSession::openString(scene, "linked.usda", o);
    while (!s->step()) {
    }
    const float* c = s->color();
    double l = 0, r = 0;
    for (int y = 0; y < 36; ++y)
        for (int x = 0; x < 48; ++x) (x < 24 ? l : r) += c[4 * (y * 48 + x)];
    return {l, r};
}
const char* kLinkedHead = R"(#usda 1.0
def Xform "Proto" ( active = false )
{
    def Mesh "Quad"
    {
        uniform token subdivisionScheme = "none"
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
    }
}
def Camera "Cam"
{
    float focalLength = 18.15
    float horizontalAperture = 20.955
    float verticalAperture = 15.2908
    double3 xformOp:translate = (0, 0, 10)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
)";
std::string linkedSun(const std::string& target) {
    return R"(
def DistantLight "Sun"
{
    float inputs:intensity = 3
    float inputs:angle = 0
    uniform bool collection:lightLink:includeRoot = 0
    rel collection:lightLink:includes = <)" + target + R"(>
}
)";
}
}  // namespace

TEST(Lights, LightLinksReachOneInstanceOfAPrototype) {
    auto scene = [](const std::string& target) {
        return std::string(kLinkedHead) + linkedSun(target) + R"(
def Xform "I0" ( instanceable = true  references = </Proto>  active = true )
{
    double3 xformOp:translate = (-2, 0, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
def Xform "I1" ( instanceable = true  references = </Proto>  active = true )
{
    double3 xformOp:translate = (2, 0, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
)";
    };
    const auto [l0, r0] = linkedHalves(scene("/I0"));
    EXPECT_GT(l0, 1.0);
    EXPECT_EQ(r0, 0.0);
    const auto [l1, r1] = linkedHalves(scene("/I1"));
    EXPECT_EQ(l1, 0.0);
    EXPECT_GT(r1, 1.0);
}

TEST(Lights, LightLinksHoldingAPointInstancerReachItsOutsidePrototypes) {
    const std::string scene = std::string(kLinkedHead) + linkedSun("/PI") + R"(
def PointInstancer "PI"
{
    rel prototypes = [</Prototypes/Quad>]
    point3f[] positions = [(-2, 0, 0), (2, 0, 0)]
    int[] protoIndices = [0, 0]
}
def Xform "Prototypes" ( active = true )
{
    token visibility = "invisible"
    def Mesh "Quad"
    {
        uniform token subdivisionScheme = "none"
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
    }
}
)";
    const auto [l, r] = linkedHalves(scene);
    EXPECT_GT(l, 1.0);
    EXPECT_GT(r, 1.0);
}

TEST(Lights, ShadowLinkedLightsPassAnyNumberOfIgnoredPrims) {
    // 80 stacked black cards between the disk light and the plane, all left out of its shadow
    // link: the closed form within 3 % (the cards' grazing specular sends a little back; the
    // layer cap for partly present surfaces used to cut the light off at 64).
    std::string cards;
    for (int i = 0; i < 80; ++i) {
        char c[512];
        std::snprintf(c, sizeof c, R"(
    def Mesh "C%d"
    {
        uniform token subdivisionScheme = "none"
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(-0.6, %g, -0.6), (0.6, %g, -0.6), (0.6, %g, 0.6), (-0.6, %g, 0.6)]
        rel material:binding = </Black>
    }
)", i, 0.5 + 0.01 * i, 0.5 + 0.01 * i, 0.5 + 0.01 * i, 0.5 + 0.01 * i);
        cards += c;
    }
    const std::string scene = planeScene(0.5, R"(
def DiskLight "Disk"
{
    float inputs:radius = 1
    float inputs:intensity = 10
    rel collection:shadowLink:excludes = </Cards>
    double3 xformOp:translate = (0, 2, 0)
    float xformOp:rotateX = -90
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
}
def Xform "Cards"
{
)" + cards + "}\n" + blackCard(0.01, false), 60.0);  // blackCard: the Black material
    const double expected = 0.5 * 10.0 * 1.0 / (4.0 + 1.0);
    EXPECT_NEAR(render(scene, 256), expected, 0.03 * expected);
}

TEST(Lights, ASunOfHalfADegreeDeliversItsFullIrradianceAndInvisibleLightsStayOff) {
    // The fallback distant light (angle 0.53 degrees, intensity 50000): E = L pi sin^2(0.265
    // degrees) on a plane facing it; a Lambert plane of albedo 0.5 shows 0.5 E / pi. 1 - cos of
    // the half angle in float lost 0.25 % of it.
    const double half = 0.5 * 0.53 * 3.14159265358979 / 180.0;
    const double E = 50000.0 * 3.14159265358979 * std::sin(half) * std::sin(half);
    const double lit = render(test::planeScene(0.5, R"(
def DistantLight "Sun" { float xformOp:rotateX = -90
    uniform token[] xformOpOrder = ["xformOp:rotateX"] }
)"), 16);
    EXPECT_NEAR(lit, 0.5 * E / 3.14159265358979, 2e-4 * lit);
    // A scene whose only light is switched off is dark: no default dome stands in for it.
    const double off = render(test::planeScene(0.5, R"(
def DistantLight "Sun" { token visibility = "invisible" }
)"), 4);
    EXPECT_EQ(off, 0.0);
}

TEST(Lights, InvalidLightValuesAreReported) {
    host::SessionOptions o;
    o.width = o.height = 2;
    o.samplesPerPixel = 1;
    auto s = host::RenderSession::openString(R"(#usda 1.0
def SphereLight "Neg" { float inputs:intensity = -3
    float inputs:radius = -1 }
def SphereLight "Squashed" { float inputs:radius = 0.5
    float3 xformOp:scale = (2, 1, 1)
    uniform token[] xformOpOrder = ["xformOp:scale"] }
)",
                                             "bad.usda", o);
    s->step();
    std::string all;
    for (const auto& w : s->takeWarnings()) all += w + "\n";
    EXPECT_NE(all.find("/Neg: negative intensity"), std::string::npos) << all;
    EXPECT_NE(all.find("bad.usda:2:"), std::string::npos) << "the delegate's warnings say where: " << all;
    EXPECT_NE(all.find("radius is negative"), std::string::npos) << all;
    EXPECT_NE(all.find("/Squashed: non-uniform scale"), std::string::npos) << all;
}

TEST(Lights, AnEmissiveSphereIsLightEnoughForNoDefaultDome) {
    // A scene lit only by an emissive Sphere prim got the white default dome (only triangle
    // emitters counted): its background was 1 where Cycles' is black.
    const std::string usda = R"(#usda 1.0
def Camera "Cam" { double3 xformOp:translate = (0, 0, 10)
    uniform token[] xformOpOrder = ["xformOp:translate"] }
def Sphere "Bulb" (prepend apiSchemas = ["MaterialBindingAPI"]) {
    double radius = 0.5
    rel material:binding = </Glow>
}
def Material "Glow" {
    token outputs:surface.connect = </Glow/S.outputs:surface>
    def Shader "S" {
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:emissiveColor = (4, 4, 4)
        token outputs:surface
    }
}
)";
    auto s = test::renderUsda(usda, 16, 16, 1);
    EXPECT_EQ(s->stats()["defaultLight"], 0.0);
    EXPECT_EQ(test::aovAt(*s, "color", 0, 0), glm::vec3(0.0f));  // the corner sees the background
    EXPECT_GT(test::aovAt(*s, "color", 8, 8).x, 3.5f);           // the bulb itself
}
