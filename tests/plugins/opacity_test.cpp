// Shadows of partly present surfaces (UsdPreviewSurface opacity and opacityThreshold cutouts):
// a Lambert plane under a 45-degree distant light, with blocker quads above it that throw
// their shadow on the spot the camera sees. Direct light only, so each expected value is the
// unblocked radiance times the product of (1 - presence) of the blockers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "plugins/renderSession.h"
#include "tests/support/lambertPlaneScene.h"
#include "tests/support/sessionRender.h"

using namespace principled;

namespace {

// A 4 x 4 quad at height y, centred at x = -y: the light travels along (1, -1, 0), so its
// shadow covers the origin. The camera's rays (straight down at x = 0) miss it.
std::string blocker(const std::string& name, double y, const std::string& opacity) {
    char buf[1024];
    std::snprintf(buf, sizeof buf, R"(
def Mesh "%s" (prepend apiSchemas = ["MaterialBindingAPI"])
{
    uniform token subdivisionScheme = "none"
    int[] faceVertexCounts = [4]
    int[] faceVertexIndices = [0, 1, 2, 3]
    point3f[] points = [(%g, %g, -2), (%g, %g, 2), (%g, %g, 2), (%g, %g, -2)]
    rel material:binding = </%sMat>
}
def Material "%sMat"
{
    token outputs:surface.connect = </%sMat/S.outputs:surface>
    def Shader "S"
    {
        uniform token info:id = "UsdPreviewSurface"
        %s
        token outputs:surface
    }
}
)",
                  name.c_str(), -y - 2, y, -y - 2, y, -y + 2, y, -y + 2, y, name.c_str(), name.c_str(),
                  name.c_str(), opacity.c_str());
    return buf;
}

const std::string kPlane = test::planeScene(0.5, R"(
def DistantLight "Sun"
{
    float inputs:intensity = 2
    float inputs:angle = 0  # a delta light: intensity is the irradiance it delivers head-on
    # Its local -Z: down by rotateX, then tilted toward +X by rotateZ, so it travels (1, -1, 0).
    float xformOp:rotateX = -90
    float xformOp:rotateZ = 45
    uniform token[] xformOpOrder = ["xformOp:rotateZ", "xformOp:rotateX"]
}
)");

// Direct light only (maxDepth 1): the blockers' own reflections stay out.
double render(const std::string& usda) { return test::planeRadiance(usda, 4, {}, 1); }

}  // namespace

TEST(Opacity, UnblockedPlaneSeesTheLight) {
    // Lambert radiance albedo E cos(45) / pi: the reference the other tests divide by.
    double lit = render(kPlane);
    EXPECT_NEAR(lit, 0.5 * 2.0 * std::sqrt(0.5) / 3.14159265358979, 2e-3);
}

TEST(Opacity, OpaqueBlockerCastsAFullShadow) {
    EXPECT_NEAR(render(kPlane + blocker("B", 5, "")), 0.0, 1e-6);
}

TEST(Opacity, PartialOpacityLetsOneMinusOpacityThrough) {
    double lit = render(kPlane);
    double shadowed = render(kPlane + blocker("B", 5, "float inputs:opacity = 0.25"));
    EXPECT_NEAR(shadowed / lit, 0.75, 1e-3);
}

TEST(Opacity, StackedLayersMultiply) {
    double lit = render(kPlane);
    double shadowed = render(kPlane + blocker("A", 5, "float inputs:opacity = 0.5") +
                             blocker("B", 10, "float inputs:opacity = 0.6"));
    EXPECT_NEAR(shadowed / lit, 0.5 * 0.4, 1e-3);
}

TEST(Opacity, CutoutBelowThresholdCastsNoShadowAndAboveAFullOne) {
    double lit = render(kPlane);
    double below = render(kPlane +
                          blocker("B", 5, "float inputs:opacity = 0.2\n        float inputs:opacityThreshold = 0.5"));
    EXPECT_NEAR(below / lit, 1.0, 1e-3);
    double above = render(kPlane +
                          blocker("B", 5, "float inputs:opacity = 0.8\n        float inputs:opacityThreshold = 0.5"));
    EXPECT_NEAR(above, 0.0, 1e-6);
}

namespace {

// A quad filling the view of a camera looking down at it, under a white dome (L = 1): returns
// the mean colour (red) and, with lobe AOVs, the diffuse and specular parts.
struct QuadLight {
    double color = 0, diffuse = 0, specular = 0, alpha = 0;
};

// A camera looking down at the origin from z = 10 (2 x 2 scene units of view) under a white dome.
const std::string kDomeAndCamera = R"(#usda 1.0
def Camera "Cam" {
    float horizontalAperture = 2
    float verticalAperture = 2
    double3 xformOp:translate = (0, 0, 10)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
def DomeLight "Sky" { }
)";
QuadLight quadUnderDome(const std::string& surfaceInputs) {
    const std::string usda = kDomeAndCamera + test::quadMesh("Quad", "(-5, -5, 0), (5, -5, 0), (5, 5, 0), (-5, 5, 0)",
                                                             "rel material:binding = </Mat>") +
                             R"(def Material "Mat" {
    token outputs:surface.connect = </Mat/S.outputs:surface>
    def Shader "S" {
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:diffuseColor = (0.5, 0.5, 0.5)
        float inputs:roughness = 0.3
        )" + surfaceInputs + R"(
        token outputs:surface
    }
}
)";
    auto s = test::renderUsda(usda, 4, 4, 1024, {"diffuse", "specular"});
    QuadLight q;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            q.color += test::aovAt(*s, "color", x, y).x / 16.0;
            q.diffuse += test::aovAt(*s, "diffuse", x, y).x / 16.0;
            q.specular += test::aovAt(*s, "specular", x, y).x / 16.0;
        }
    q.alpha = test::meanAlpha(*s);
    return q;
}

}  // namespace

TEST(Opacity, TransparentModeKeepsTheSpecularAndScalesTheRest) {
    // UsdPreviewSurface opacityMode "transparent" (the fallback): at opacity a the surface
    // reflects its full specular, a times its diffuse, and lets 1 - a of what is behind through:
    // colour = specular + a diffuse + (1 - a) * 1 under a white dome. "presence" scales it all:
    // a (diffuse + specular) + 1 - a.
    const QuadLight opaque = quadUnderDome("");
    ASSERT_GT(opaque.specular, 0.02);
    ASSERT_GT(opaque.diffuse, 0.3);
    for (double a : {0.0, 0.25, 0.6}) {
        const std::string op = "float inputs:opacity = " + std::to_string(a);
        const QuadLight t = quadUnderDome(op);
        EXPECT_NEAR(t.color, opaque.specular + a * opaque.diffuse + (1.0 - a), 0.01) << "transparent " << a;
        EXPECT_NEAR(t.specular, opaque.specular, 0.004) << "transparent " << a;
        EXPECT_NEAR(t.alpha, a, 0.01) << "transparent " << a;  // coverage, as Storm composites it
        const QuadLight p = quadUnderDome(op + "\n        token inputs:opacityMode = \"presence\"");
        EXPECT_NEAR(p.color, a * (opaque.diffuse + opaque.specular) + (1.0 - a), 0.01) << "presence " << a;
        EXPECT_NEAR(p.alpha, a, 0.01) << "presence " << a;
    }
}

TEST(Opacity, StackedTransparentCardsStayQuietAndCoverage) {
    // Eight clear (opacity 0, transparent mode) cards in front of a white dome: each reflects a
    // little and passes the rest. Picking "pass" for half the paths with weight 2 gave a pixel
    // standard deviation of 0.68 at 16 spp; in proportion to what each branch carries it stays
    // small. Coverage (alpha) of clear cards is 0.
    std::string cards;
    for (int i = 0; i < 8; ++i) {
        const std::string z = std::to_string(-i);
        cards += test::quadMesh("C" + std::to_string(i),
                                "(-5, -5, " + z + "), (5, -5, " + z + "), (5, 5, " + z + "), (-5, 5, " + z + ")",
                                "rel material:binding = </Clear>");
    }
    const std::string usda = kDomeAndCamera + R"(def Material "Clear" {
    token outputs:surface.connect = </Clear/S.outputs:surface>
    def Shader "S" {
        uniform token info:id = "UsdPreviewSurface"
        float inputs:opacity = 0
        float inputs:roughness = 0.3
        token outputs:surface
    }
}
)" + cards;
    auto s = test::renderUsda(usda, 8, 8, 16, {}, {{"sampler", "independent"}});
    double sum = 0, sq = 0;
    for (int i = 0; i < 64; ++i) {
        const double r = s->color()[4 * i];
        sum += r, sq += r * r;
    }
    const double mean = sum / 64, sd = std::sqrt(std::max(0.0, sq / 64 - mean * mean));
    EXPECT_GT(mean, 1.0);  // the dome plus the cards' reflections
    EXPECT_LT(sd, 0.25) << "mean " << mean;
    EXPECT_NEAR(test::meanAlpha(*s), 0.0, 1e-6);
}
