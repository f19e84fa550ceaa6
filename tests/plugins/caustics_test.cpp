// SPDX-License-Identifier: Apache-2.0
// Caustic light tracing (delegate/causticScene.h): light from small lights through sharp lobes
// onto what the camera sees. Checked against a closed form (a plane mirror and a delta sun, which
// path tracing alone cannot render at all) and against path tracing alone where both can (the
// split of path space must not change the mean), and for what it costs where it has nothing to do.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "delegate/causticScene.h"
#include "delegate/renderDelegate.h"
#include "plugins/renderSession.h"
#include "tests/support/seedStatistics.h"

using namespace principled;

namespace {

std::unique_ptr<host::RenderSession> run(const std::string& usda, host::SessionOptions o) {
    auto s = host::RenderSession::openString(usda, "caustics.usda", o);
    while (!s->step()) {
    }
    return s;
}

// Mean red value over the central half of the image (both axes).
double centreMean(host::RenderSession& s) {
    const float* c = s.color();
    const int w = s.width(), h = s.height();
    double sum = 0.0;
    int n = 0;
    for (int y = h / 4; y < 3 * h / 4; ++y)
        for (int x = w / 4; x < 3 * w / 4; ++x, ++n) sum += c[4 * (y * w + x)];
    return sum / n;
}

std::vector<float> red(host::RenderSession& s) {
    std::vector<float> r(size_t(s.width()) * s.height());
    for (size_t i = 0; i < r.size(); ++i) r[i] = s.color()[4 * i];
    return r;
}

// A UsdPreviewSurface material `look` with the given input lines.
std::string material(const std::string& look, const std::string& inputs) {
    return "def Material \"" + look + R"("
{
    token outputs:surface.connect = </)" + look + R"(/S.outputs:surface>
    def Shader "S"
    {
        uniform token info:id = "UsdPreviewSurface"
)" + inputs + R"(
        token outputs:surface
    }
}
)";
}

// A one-quad mesh `name` with corners `points` (USDA tuple list) bound to a new
// UsdPreviewSurface material `look` with the given input lines.
std::string quad(const std::string& name, const std::string& points, const std::string& look,
                 const std::string& inputs) {
    return "def Mesh \"" + name + R"(" (prepend apiSchemas = ["MaterialBindingAPI"])
{
    uniform token subdivisionScheme = "none"
    int[] faceVertexCounts = [4]
    int[] faceVertexIndices = [0, 1, 2, 3]
    point3f[] points = [)" + points + R"(]
    rel material:binding = </)" + look + R"(>
}
)" + material(look, inputs);
}

const char* kChromeInputs = R"(        color3f inputs:diffuseColor = (1, 1, 1)
        float inputs:metallic = 1
        float inputs:roughness = 0)";

// A grey wall (z = 3, facing -z) seen head-on by a camera at z = 1, and `rest`.
std::string wallScene(const std::string& rest) {
    return "#usda 1.0\n" +
           quad("Wall", "(-2, -2, 3), (-2, 2, 3), (2, 2, 3), (2, -2, 3)", "Grey", R"(        color3f inputs:diffuseColor = (0.5, 0.5, 0.5)
        float inputs:roughness = 1
        float inputs:specular = 0)") + R"(
def Camera "Cam"
{
    double3 xformOp:translate = (0, 0, 1)
    float xformOp:rotateY = 180
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateY"]
}
)" + rest;
}

// A 1 x 1 perfect mirror at the origin tilted 45 degrees (normal (0, 1, 1) / sqrt 2): a sun
// shining down -y is reflected along +z onto the wall, its irradiance unchanged (F = 1 for a
// white metal).
const std::string kMirrorAndSun = quad("Mirror", "(-0.5, -0.35355, 0.35355), (0.5, -0.35355, 0.35355), (0.5, 0.35355, -0.35355), (-0.5, 0.35355, -0.35355)", "Chrome", kChromeInputs) + R"(
def DistantLight "Sun"
{
    float inputs:angle = 0
    float inputs:intensity = 2
    float xformOp:rotateX = -90
    uniform token[] xformOpOrder = ["xformOp:rotateX"]
}
)";

// The same sun shining straight at the wall (along +z).
const char* kSunOnWall = R"(
def DistantLight "Sun"
{
    float inputs:angle = 0
    float inputs:intensity = 2
    float xformOp:rotateY = 180
    uniform token[] xformOpOrder = ["xformOp:rotateY"]
}
)";

}  // namespace

TEST(Caustics, PlaneMirrorReflectsADeltaSunOntoAWallAtFullIrradiance) {
    // A delta sun seen through a perfect mirror: no path-tracing strategy can find it (a BSDF
    // sample never hits a delta light, the shadow ray toward the sun is blocked by nothing but
    // misses the mirror's reflection), so without light tracing the wall stays black. With it,
    // the lit patch must equal the wall lit directly by the same sun at the same angle.
    host::SessionOptions o;
    o.width = o.height = 32;
    o.samplesPerPixel = 64;
    auto direct = run(wallScene(kSunOnWall), o);
    const double expected = centreMean(*direct);
    ASSERT_GT(expected, 0.05);
    auto caustic = run(wallScene(kMirrorAndSun), o);
    EXPECT_NEAR(centreMean(*caustic) / expected, 1.0, 0.03) << centreMean(*caustic) << " vs " << expected;
    o.settings = {{"caustics", "0"}};
    auto off = run(wallScene(kMirrorAndSun), o);
    EXPECT_EQ(centreMean(*off), 0.0);
    // Every pass must carry its share, the first too (it traces fewer light paths): at 16 spp a
    // first pass without light tracing would leave the patch 1/16 dark.
    o.samplesPerPixel = 16;
    o.settings = {{"causticPaths", "2"}};
    auto few = run(wallScene(kMirrorAndSun), o);
    EXPECT_NEAR(centreMean(*few) / expected, 1.0, 0.03) << centreMean(*few) << " vs " << expected;
}

namespace {

const std::string kTopCamera = R"(
def Camera "Cam"
{
    double3 xformOp:translate = (0, 5, 0)
    float xformOp:rotateX = -90
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
}
)";

// A floor under a 10-degree sun (45 degrees high by default), with a ball of material `ball` on it, seen
// from straight above (the ball's shadow and caustic in view).
std::string ballOnFloor(const std::string& ball, int sunElevation = 45, const std::string& camera = kTopCamera) {
    return R"(#usda 1.0
def Mesh "Floor" (prepend apiSchemas = ["MaterialBindingAPI"])
{
    uniform token subdivisionScheme = "none"
    int[] faceVertexCounts = [4]
    int[] faceVertexIndices = [0, 1, 2, 3]
    point3f[] points = [(-3, 0, -3), (-3, 0, 3), (3, 0, 3), (3, 0, -3)]
    rel material:binding = </Looks/Floor>
}
def Scope "Looks" {
def Material "Floor"
{
    token outputs:surface.connect = </Looks/Floor/S.outputs:surface>
    def Shader "S"
    {
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor = (0.6, 0.6, 0.6)
        float inputs:roughness = 0.9
        token outputs:surface
    }
}
}
def Sphere "Ball" (prepend apiSchemas = ["MaterialBindingAPI"])
{
    double radius = 0.5
    double3 xformOp:translate = (0, 0.5, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
    rel material:binding = </BallLook>
}
)" + material("BallLook", ball) + R"(def DistantLight "Sun"
{
    float inputs:angle = 10
    float inputs:intensity = 20
    float3 xformOp:rotateXYZ = ()" + std::to_string(-sunElevation) + R"(, 30, 0)
    uniform token[] xformOpOrder = ["xformOp:rotateXYZ"]
}

)" + camera;
}

// Light tracing on and off must render the same image in the mean (over seeds); the caustic's
// noise must drop with it. Returns {on, off}.
std::pair<test::SeedStats, test::SeedStats> onAndOff(const std::string& scene, int spp) {
    auto stats = [&](const char* caustics) {
        return test::seedStatistics(
            [&](int seed) {
                host::SessionOptions o;
                o.width = o.height = 24;
                o.samplesPerPixel = spp;
                o.seed = seed;
                o.settings = {{"caustics", caustics}};
                return red(*run(scene, o));
            },
            0, 8);
    };
    return {stats("1"), stats("0")};
}

::testing::AssertionResult sameMean(const test::SeedStats& a, const test::SeedStats& b) {
    const double tol = 4.0 * std::hypot(a.se, b.se) + 2e-3 * std::abs(b.mean);
    if (std::abs(a.mean - b.mean) < tol) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure() << a.mean << " +- " << a.se << " vs " << b.mean << " +- " << b.se;
}

}  // namespace

TEST(Caustics, GlossyMetalCausticHasTheMeanOfPathTracingAndLessNoise) {
    // A low sun: the floor gets about as much light from the ball as from the sun itself.
    const auto [on, off] = onAndOff(ballOnFloor(R"(
        color3f inputs:diffuseColor = (0.95, 0.8, 0.5)
        float inputs:metallic = 1
        float inputs:roughness = 0.08)", 12), 64);
    EXPECT_TRUE(sameMean(on, off));
    EXPECT_LT(on.pixelVar, 0.7 * off.pixelVar) << on.pixelVar << " vs " << off.pixelVar;
}

TEST(Caustics, SmoothGlassCausticHasTheMeanOfPathTracing) {
    // Refraction through a delta lobe both ways (the light path samples it from the light's side).
    const auto [on, off] = onAndOff(ballOnFloor(R"(
        color3f inputs:diffuseColor = (1, 1, 1)
        float inputs:roughness = 0
        float inputs:specTrans = 1)"), 64);
    EXPECT_TRUE(sameMean(on, off));
    EXPECT_LT(on.pixelVar, off.pixelVar) << on.pixelVar << " vs " << off.pixelVar;
}

TEST(Caustics, RoughGlassCausticHasTheMeanOfPathTracing) {
    // A rough (but sharp) refraction: the light path's density picks the direction, the value is
    // the camera path's BTDF, which is not symmetric.
    const auto [on, off] = onAndOff(ballOnFloor(R"(
        color3f inputs:diffuseColor = (1, 1, 1)
        float inputs:roughness = 0.09
        float inputs:specTrans = 1)"), 64);
    EXPECT_TRUE(sameMean(on, off));
}

TEST(Caustics, CausticsSeenInAMirrorHaveTheMeanOfPathTracing) {
    // The glass ball's caustic seen only in a tilted mirror the camera looks into (camera ->
    // mirror -> floor -> glass -> sun): light tracing cannot connect through the mirror, the
    // photons' density at the floor vertex takes that light instead.
    const std::string mirror = quad("Mirror", "(-3, 4, -1), (3, 4, -1), (3, 6, 1), (-3, 6, 1)", "Chrome", kChromeInputs) + R"(
def Camera "Cam"
{
    double3 xformOp:translate = (0, 5, 4)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
)";
    const auto [on, off] = onAndOff(ballOnFloor(R"(
        color3f inputs:diffuseColor = (1, 1, 1)
        float inputs:roughness = 0
        float inputs:specTrans = 1)", 45, mirror), 256);
    EXPECT_TRUE(sameMean(on, off));
    EXPECT_LT(on.pixelVar, off.pixelVar) << on.pixelVar << " vs " << off.pixelVar;
}

TEST(Caustics, GlassCausticOfAMeshLightHasTheMeanOfPathTracing) {
    // An emissive quad (a mesh light, two-sided) instead of the sun: light paths start on its
    // triangles, and the path tracer leaves their share when its rays hit the quad.
    std::string scene = ballOnFloor(R"(
        color3f inputs:diffuseColor = (1, 1, 1)
        float inputs:roughness = 0
        float inputs:specTrans = 1)");
    const std::string sun = "float inputs:intensity = 20";
    ASSERT_NE(scene.find(sun), std::string::npos);
    scene.replace(scene.find(sun), sun.size(), "float inputs:intensity = 0");
    // Wound so that its normal points up, away from the ball: only its back lights the scene.
    scene += quad("Lamp", "(1.2, 1.8, 0.3), (1.8, 1.8, 0.3), (1.8, 1.8, -0.3), (1.2, 1.8, -0.3)", "LampLook",
                  R"(        color3f inputs:diffuseColor = (0, 0, 0)
        color3f inputs:emissiveColor = (40, 40, 40))");
    host::SessionOptions o;
    o.width = o.height = 16;
    o.samplesPerPixel = 4;
    EXPECT_EQ(run(scene, o)->stats().at("causticLights"), 1.0);
    const auto [on, off] = onAndOff(scene, 64);
    EXPECT_TRUE(sameMean(on, off));
    EXPECT_LT(on.pixelVar, off.pixelVar) << on.pixelVar << " vs " << off.pixelVar;
}

TEST(Caustics, ScenesWithoutSharpLobesRenderExactlyAsWithout) {
    // A rough metal ball: nothing is sharp, light tracing has nothing to do and the image is
    // bit-identical (no sample streams change).
    const std::string scene = ballOnFloor(R"(
        color3f inputs:diffuseColor = (0.9, 0.9, 0.9)
        float inputs:metallic = 1
        float inputs:roughness = 0.3)");
    host::SessionOptions o;
    o.width = o.height = 16;
    o.samplesPerPixel = 8;
    auto on = run(scene, o);
    o.settings = {{"caustics", "0"}};
    auto off = run(scene, o);
    EXPECT_EQ(red(*on), red(*off));
}

TEST(Caustics, TheLightPathBudgetFollowsWhereTheNoiseIs) {
    // delegate/causticBudget.h: a glass ball's caustic in view, on an otherwise smooth image,
    // gets more light paths than causticPaths; the same ball seen by a camera that looks away
    // from it gets the fewest (its light paths reach no pixel). Passes of 1, 2, 4, 8 samples:
    // the budget is free from the third (the first two measure).
    const std::string glass = R"(
        color3f inputs:diffuseColor = (1, 1, 1)
        float inputs:roughness = 0
        float inputs:specTrans = 1)";
    const std::string skyCamera = R"(
def Camera "Cam"
{
    double3 xformOp:translate = (0, 5, 0)
    float xformOp:rotateX = 90
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
}
)";
    auto paths = [&](const std::string& scene, const char* adaptive) {
        host::SessionOptions o;
        o.width = o.height = 24;
        o.samplesPerPixel = 15;
        o.settings = {{"causticAdaptive", adaptive}};
        return run(scene, o)->stats().at("causticPaths");
    };
    const double P = 24 * 24, base = 0.125;
    const double fixedInView = paths(ballOnFloor(glass), "0");
    EXPECT_NEAR(fixedInView, base * P * (0.125 + 2 + 4 + 8), 4.0);
    // More than causticPaths, and not at the 4x bound either (it was picked, not clamped).
    const double inView = paths(ballOnFloor(glass), "1");
    EXPECT_GT(inView, 1.5 * fixedInView);
    EXPECT_LT(inView, 0.9 * base * P * (0.125 + 2 + (4 + 8) * 4.0));
    const double away = paths(ballOnFloor(glass, 45, skyCamera), "1");
    EXPECT_NEAR(away, base * P * (0.125 + 2 + (4 + 8) / 16.0), 4.0);
}

TEST(Caustics, TheVarianceAovCountsTheLightTracedShare) {
    // The variance AOV (the variance of a pixel's mean luminance, the adaptive sampler's input)
    // must include the light-traced share's noise: summed over the image it must match the
    // variance of the pixel means over independent seeds. Independent samples, so that
    // the per-sample estimate holds (Sobol points converge faster than it assumes).
    const std::string scene = ballOnFloor(R"(
        color3f inputs:diffuseColor = (1, 1, 1)
        float inputs:roughness = 0
        float inputs:specTrans = 1)");
    constexpr int kSeeds = 16, kSize = 24;
    std::vector<double> sum(kSize * kSize, 0.0), squares(kSize * kSize, 0.0);
    double aov = 0.0;
    for (int seed = 0; seed < kSeeds; ++seed) {
        host::SessionOptions o;
        o.width = o.height = kSize;
        o.samplesPerPixel = 32;
        o.seed = seed;
        o.sampler = "independent";
        o.aovs = {"variance"};
        o.settings = {{"causticPaths", "0.02"}, {"causticAdaptive", "0"}};  // the light-traced share dominates
        auto s = run(scene, o);
        const float* c = s->color();
        for (int p = 0; p < kSize * kSize; ++p) {
            const double l = 0.2126 * c[4 * p] + 0.7152 * c[4 * p + 1] + 0.0722 * c[4 * p + 2];
            sum[p] += l;
            squares[p] += l * l;
        }
        for (const auto& a : s->aovs())
            if (a.name == "variance")
                for (int p = 0; p < kSize * kSize; ++p) aov += static_cast<const float*>(a.pixels)[p] / kSeeds;
    }
    double empirical = 0.0;
    for (int p = 0; p < kSize * kSize; ++p)
        empirical += (squares[p] - sum[p] * sum[p] / kSeeds) / (kSeeds - 1);
    ASSERT_GT(empirical, 0.0);
    // Measured 0.88 (0.56 without the light-traced term; 1.00 with caustics off). What is
    // left is the photons' share: merged at camera vertices, it is in the samples, but
    // correlated within a pass (one photon map), which a per-sample variance does not see.
    EXPECT_NEAR(aov / empirical, 1.0, 0.25) << aov << " vs " << empirical;
}

TEST(Caustics, AStoppedPixelsVarianceStaysAsItWas) {
    // Adaptive sampling stops pixels; their estimate, light-traced share included, no longer
    // changes, and neither may the variance AOV they show (the light paths' frame statistics
    // go on growing without them).
    host::SessionOptions o;
    o.width = o.height = 24;
    o.samplesPerPixel = 256;
    o.noiseThreshold = 0.05f;
    o.aovs = {"variance", "sampleCount"};
    auto s = host::RenderSession::openString(ballOnFloor(R"(
        color3f inputs:diffuseColor = (1, 1, 1)
        float inputs:roughness = 0
        float inputs:specTrans = 1)"), "caustics.usda", o);
    std::vector<float> variance, count;
    int stoppedChecked = 0;
    while (!s->step()) {
        const float *v = nullptr, *c = nullptr;
        for (const auto& a : s->aovs()) {
            if (a.name == "variance") v = static_cast<const float*>(a.pixels);
            if (a.name == "sampleCount") c = static_cast<const float*>(a.pixels);
        }
        ASSERT_TRUE(v && c);
        for (size_t p = 0; p < variance.size(); ++p)
            if (c[p] == count[p] && c[p] >= 16) {  // stopped before this pass
                EXPECT_EQ(v[p], variance[p]) << "pixel " << p;
                ++stoppedChecked;
            }
        variance.assign(v, v + o.width * o.height);
        count.assign(c, c + o.width * o.height);
    }
    EXPECT_GT(stoppedChecked, 100);
}

TEST(CausticScene, EmittedRaysCountOverlappingTargetsOnce) {
    // A delta sun straight down on two mirror balls (r = 0.5, centres 0.6 apart): light paths
    // start uniformly in either ball's disc, and their weights must add up to the sun's
    // irradiance times the area of the union of the discs (the overlap counted once; with the
    // density of one disc alone it would count twice).
    const std::string scene = R"(#usda 1.0
def Sphere "A" (prepend apiSchemas = ["MaterialBindingAPI"]) { double radius = 0.5  rel material:binding = </Chrome> }
def Sphere "B" (prepend apiSchemas = ["MaterialBindingAPI"])
{
    double radius = 0.5
    double3 xformOp:translate = (0.6, 0, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
    rel material:binding = </Chrome>
}
)" + material("Chrome", kChromeInputs) + R"(def DistantLight "Sun"
{
    float inputs:angle = 0
    float inputs:intensity = 2
    float xformOp:rotateX = -90
    uniform token[] xformOpOrder = ["xformOp:rotateX"]
}
def Camera "Cam" { double3 xformOp:translate = (0, 0, 5)  uniform token[] xformOpOrder = ["xformOp:translate"] }
)";
    host::SessionOptions o;
    o.width = o.height = 8;
    o.samplesPerPixel = 1;
    auto s = run(scene, o);
    const embree::SceneSnapshot& snap = s->delegate()->snapshot();
    const embree::CausticScene caustics(snap, s->delegate()->integratorSettings().bsdf, 0.1f);
    ASSERT_TRUE(caustics.active());
    ASSERT_EQ(caustics.targets().size(), 2u);
    ASSERT_EQ(snap.lights.size(), 1u);
    const double irradiance = snap.lights[0].irradiance.x;
    const double r = caustics.targets()[0].radius, d = 0.6;
    // Two discs of radius r, centres d apart: 2 pi r^2 minus the lens 2 r^2 acos(d / 2r) - (d / 2) sqrt(4 r^2 - d^2).
    const double lens = 2.0 * r * r * std::acos(d / (2.0 * r)) - 0.5 * d * std::sqrt(4.0 * r * r - d * d);
    const double expected = irradiance * (2.0 * M_PI * r * r - lens);
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const int n = 200000;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        embree::EmittedRay ray;
        if (caustics.sampleEmission(snap, u(rng), u(rng), {u(rng), u(rng)}, {u(rng), u(rng)}, &ray)) {
            sum += ray.weight.x;
            EXPECT_LT(std::abs(ray.direction.y + 1.0f), 1e-5f);
        }
    }
    EXPECT_NEAR(sum / n / expected, 1.0, 0.01) << sum / n << " vs " << expected;
}

TEST(CausticScene, EmittedRaysOfASphereLightCarryItsFluxTowardTheTarget) {
    // A small sphere light (radius a, radiance L) 20 above a mirror ball (radius r): the flux it
    // sends into the ball's cone is pi^2 L a^2 r^2 / D^2 up to (r / D)^2; light paths only go
    // there, so their mean weight is that flux.
    const std::string scene = R"(#usda 1.0
def Sphere "A" (prepend apiSchemas = ["MaterialBindingAPI"]) { double radius = 0.5  rel material:binding = </Chrome> }
)" + material("Chrome", kChromeInputs) + R"(def SphereLight "Lamp"
{
    float inputs:radius = 0.05
    float inputs:intensity = 3
    double3 xformOp:translate = (0, 20, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
def Camera "Cam" { double3 xformOp:translate = (0, 0, 5)  uniform token[] xformOpOrder = ["xformOp:translate"] }
)";
    host::SessionOptions o;
    o.width = o.height = 8;
    o.samplesPerPixel = 1;
    auto s = run(scene, o);
    const embree::SceneSnapshot& snap = s->delegate()->snapshot();
    const embree::CausticScene caustics(snap, s->delegate()->integratorSettings().bsdf, 0.1f);
    ASSERT_TRUE(caustics.active());
    ASSERT_EQ(snap.lights.size(), 1u);
    const double L = snap.lights[0].radiance.x, a = snap.lights[0].radius, r = caustics.targets()[0].radius;
    const double expected = M_PI * M_PI * L * a * a * r * r / (20.0 * 20.0);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const int n = 200000;
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        embree::EmittedRay ray;
        if (caustics.sampleEmission(snap, u(rng), u(rng), {u(rng), u(rng)}, {u(rng), u(rng)}, &ray)) sum += ray.weight.x;
    }
    EXPECT_NEAR(sum / n / expected, 1.0, 0.01) << sum / n << " vs " << expected;
}
