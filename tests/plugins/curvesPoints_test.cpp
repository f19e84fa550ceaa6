// UsdGeomPoints and UsdGeomBasisCurves through the whole slice from USDA text: where their
// spheres and tubes are (an orthographic camera looking down -Z at the XY plane), which
// authored element each hit reports, per-curve colours, every basis and wrap, and bad input.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "plugins/renderSession.h"

using namespace principled;

namespace {

// Renders `prims` under an orthographic camera at z = 10 that sees the square [-2, 2]^2 of the
// XY plane in 64 x 64 pixels (1/16 unit each) and returns its AOVs.
struct Frame {
    std::map<std::string, std::vector<float>> f;
    std::map<std::string, std::vector<int32_t>> i;
    std::vector<std::string> warnings;
    // The pixel that sees world point (x, y).
    static int pixel(double x, double y) {
        int px = int((x + 2.0) / 4.0 * 64.0), py = int((2.0 - y) / 4.0 * 64.0);
        return py * 64 + px;
    }
};

Frame render(const std::string& prims) {
    std::string usda = "#usda 1.0\n" + prims + R"(
def Camera "Cam"
{
    token projection = "orthographic"
    float horizontalAperture = 40
    float verticalAperture = 40
    double3 xformOp:translate = (0, 0, 10)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
)";
    host::SessionOptions o;
    o.width = o.height = 64;
    o.samplesPerPixel = 1;
    o.aovs = {"alpha", "primId", "elementId", "albedo", "normal"};
    auto s = host::RenderSession::openString(usda, "curves.usda", o);
    while (!s->step()) {
    }
    Frame fr;
    for (const auto& img : s->aovs()) {
        size_t n = size_t(s->width()) * s->height() * img.components;
        if (img.name == "primId" || img.name == "elementId")
            fr.i[img.name].assign(static_cast<const int32_t*>(img.pixels), static_cast<const int32_t*>(img.pixels) + n);
        else
            fr.f[img.name].assign(static_cast<const float*>(img.pixels), static_cast<const float*>(img.pixels) + n);
    }
    fr.warnings = s->takeWarnings();
    return fr;
}

bool covered(const Frame& fr, double x, double y) { return fr.f.at("alpha")[Frame::pixel(x, y)] > 0.5f; }

}  // namespace

TEST(Points, EachPointIsASphereOfItsWidthReportingItsAuthoredIndex) {
    // The first point is NaN (skipped with a warning): the sphere at the origin is point 1.
    Frame fr = render(R"(
def Points "Dots"
{
    point3f[] points = [(nan, 0, 0), (0, 0, 0), (1.5, 1.5, 0)]
    float[] widths = [1, 2, 0.5] (interpolation = "vertex")
    color3f[] primvars:displayColor = [(1, 0, 0), (0, 1, 0), (0, 0, 1)] (interpolation = "vertex")
}
)");
    EXPECT_TRUE(covered(fr, 0.1, 0.1));
    EXPECT_TRUE(covered(fr, 0.85, 0.1));   // inside radius 1
    EXPECT_FALSE(covered(fr, 1.2, 0.1));   // outside it
    EXPECT_TRUE(covered(fr, 1.55, 1.55));  // the small sphere
    int c = Frame::pixel(0.1, 0.1);
    EXPECT_EQ(fr.i.at("elementId")[c], 1);
    EXPECT_EQ(fr.i.at("elementId")[Frame::pixel(1.55, 1.55)], 2);
    EXPECT_NEAR(fr.f.at("albedo")[3 * c + 1], 1.0f, 1e-5f);  // its own (vertex) colour
    EXPECT_NEAR(fr.f.at("albedo")[3 * c + 0], 0.0f, 1e-5f);
    EXPECT_GT(fr.f.at("normal")[3 * c + 2], 0.95f);  // the sphere's front faces the camera
    ASSERT_EQ(fr.warnings.size(), 1u);
    EXPECT_NE(fr.warnings[0].find("/Dots"), std::string::npos) << fr.warnings[0];
}

TEST(BasisCurves, LinearCurveIsATubeOfItsWidthWithPerCurveColours) {
    // Two horizontal linear curves of width 0.5 at y = 1 and y = -1, uniform colours.
    Frame fr = render(R"(
def BasisCurves "Lines"
{
    uniform token type = "linear"
    int[] curveVertexCounts = [2, 3]
    point3f[] points = [(-1.5, 1, 0), (1.5, 1, 0), (-1.5, -1, 0), (0, -1, 0), (1.5, -1, 0)]
    float[] widths = [0.5]
    color3f[] primvars:displayColor = [(1, 0, 0), (0, 0, 1)] (interpolation = "uniform")
}
)");
    EXPECT_TRUE(covered(fr, 0.1, 1.1));
    EXPECT_FALSE(covered(fr, 0.1, 1.4));  // radius 0.25
    EXPECT_FALSE(covered(fr, 0.1, 0.1));
    EXPECT_TRUE(covered(fr, -1.0, -0.9));
    EXPECT_EQ(fr.i.at("elementId")[Frame::pixel(0.1, 1.1)], 0);
    EXPECT_EQ(fr.i.at("elementId")[Frame::pixel(0.6, -0.9)], 1);
    EXPECT_NEAR(fr.f.at("albedo")[3 * Frame::pixel(0.1, 1.1) + 0], 1.0f, 1e-5f);
    EXPECT_NEAR(fr.f.at("albedo")[3 * Frame::pixel(0.6, -0.9) + 2], 1.0f, 1e-5f);
    EXPECT_TRUE(fr.warnings.empty());
}

TEST(BasisCurves, PinnedCatmullRomReachesItsEndsAndNonperiodicBSplineDoesNot) {
    // Collinear control points along y = 0 from x = -1.5 to 1.5: the pinned curve spans them;
    // a nonperiodic B-spline of the same points stops short of both ends (it starts at
    // (P0 + 4 P1 + P2) / 6 = -0.75 for points 0.75 apart), so x = -1.4 is not covered.
    const char* points = "point3f[] points = [(-1.5, Y, 0), (-0.75, Y, 0), (0, Y, 0), (0.75, Y, 0), (1.5, Y, 0)]";
    auto curve = [&](const char* name, const char* basis, const char* wrap, const char* y) {
        std::string p = points;
        for (size_t k; (k = p.find('Y')) != std::string::npos;) p.replace(k, 1, y);
        return std::string("def BasisCurves \"") + name + "\"\n{\n    uniform token type = \"cubic\"\n" +
               "    uniform token basis = \"" + basis + "\"\n    uniform token wrap = \"" + wrap + "\"\n" +
               "    int[] curveVertexCounts = [5]\n    " + p + "\n    float[] widths = [0.3]\n}\n";
    };
    Frame fr = render(curve("Pinned", "catmullRom", "pinned", "1") + curve("Open", "bspline", "nonperiodic", "-1"));
    EXPECT_TRUE(covered(fr, -1.4, 1.05));
    EXPECT_TRUE(covered(fr, 1.4, 1.05));
    EXPECT_TRUE(covered(fr, 0.1, -0.95));
    EXPECT_FALSE(covered(fr, -1.4, -0.95));
    EXPECT_TRUE(fr.warnings.empty());
}

TEST(BasisCurves, PeriodicBezierClosesTheLoop) {
    // A periodic cubic Bezier square of 12 points: 4 straight segments, the last one from
    // (-1, 1) back to the first point (-1, -1), so the left edge x = -1 is drawn.
    Frame fr = render(R"(
def BasisCurves "Loop"
{
    uniform token type = "cubic"
    uniform token basis = "bezier"
    uniform token wrap = "periodic"
    int[] curveVertexCounts = [12]
    point3f[] points = [(-1, -1, 0), (-0.3, -1, 0), (0.3, -1, 0), (1, -1, 0), (1, -0.3, 0), (1, 0.3, 0),
                        (1, 1, 0), (0.3, 1, 0), (-0.3, 1, 0), (-1, 1, 0), (-1, 0.3, 0), (-1, -0.3, 0)]
    float[] widths = [0.3]
}
)");
    EXPECT_TRUE(covered(fr, -1.0, 0.1));
    EXPECT_TRUE(covered(fr, 1.0, 0.1));
    EXPECT_TRUE(covered(fr, 0.1, -1.0));
    EXPECT_FALSE(covered(fr, 0.1, 0.1));
}

TEST(BasisCurves, InconsistentCountsAreAWarningNotACrash) {
    Frame fr = render(R"(
def BasisCurves "Bad"
{
    uniform token type = "linear"
    int[] curveVertexCounts = [2, 5000000]
    point3f[] points = [(0, 0, 0), (1, 0, 0)]
}
def BasisCurves "TooShort"
{
    uniform token type = "cubic"
    int[] curveVertexCounts = [3, -2]
    point3f[] points = [(0, 0, 0), (1, 0, 0), (2, 0, 0)]
}
)");
    for (float a : fr.f.at("alpha")) EXPECT_EQ(a, 0.0f);
    ASSERT_GE(fr.warnings.size(), 2u);
    std::string all;
    for (const auto& w : fr.warnings) all += w + "\n";
    EXPECT_NE(all.find("/Bad"), std::string::npos) << all;
    EXPECT_NE(all.find("/TooShort"), std::string::npos) << all;
}
