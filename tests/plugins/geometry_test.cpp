// Geometry through the whole slice (USDA -> adapter -> delegate -> pixels): implicit shapes,
// GeomSubset material bindings and PointInstancers, checked on the ID AOVs.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <map>
#include <string>

#include "plugins/renderSession.h"

using namespace principled;

namespace {

// An orthographic camera at z = 10 looking down -Z over [-2, 2] x [-2, 2].
const char* kCamera = R"(
def Camera "Cam"
{
    token projection = "orthographic"
    float horizontalAperture = 40
    float verticalAperture = 40
    double3 xformOp:translate = (0, 0, 10)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
)";

struct Rendered {
    std::unique_ptr<host::RenderSession> session;
    std::map<std::string, host::RenderSession::AovImage> aov;
    int w = 0, h = 0;
    int id(const char* name, int x, int y) const {
        return static_cast<const int32_t*>(aov.at(name).pixels)[y * w + x];
    }
    const float* color(int x, int y) const { return session->color() + 4 * (y * w + x); }
    // The pixel over world point (x, y) of the camera above.
    int px(double x) const { return int((x + 2.0) / 4.0 * w); }
    int py(double y) const { return int((2.0 - y) / 4.0 * h); }
};

Rendered render(const std::string& body, int size = 32, int spp = 2) {
    host::SessionOptions o;
    o.width = o.height = size;
    o.samplesPerPixel = spp;
    o.aovs = {"primId", "instanceId", "materialId", "elementId"};
    Rendered r;
    r.session = host::RenderSession::openString("#usda 1.0\n(\n    upAxis = \"Y\"\n)\n" + body + kCamera,
                                                "geometry.usda", o);
    while (!r.session->step()) {
    }
    for (const auto& a : r.session->aovs()) r.aov[a.name] = a;
    r.w = r.h = size;
    return r;
}

}  // namespace

TEST(Geometry, ImplicitShapesRenderWithFinitePixels) {
    for (const char* shape : {"Cube", "Cylinder", "Cone", "Capsule"}) {
        SCOPED_TRACE(shape);
        Rendered r = render(std::string("def ") + shape + " \"S\" { double radius = 0.8\n double height = 1\n double size = 1.5 }\n");
        int hits = 0;
        for (int y = 0; y < r.h; ++y)
            for (int x = 0; x < r.w; ++x) {
                const float* c = r.color(x, y);
                for (int k = 0; k < 4; ++k) ASSERT_TRUE(std::isfinite(c[k]));
                hits += r.id("primId", x, y) >= 0;
            }
        EXPECT_GT(hits, r.w * r.h / 8);
        EXPECT_EQ(r.id("primId", r.w / 2, r.h / 2), 0);
        EXPECT_EQ(r.id("primId", 0, 0), -1);
    }
}

TEST(Geometry, GeomSubsetsBindMaterialsPerFace) {
    // Two faces: x < 0 (face 0) bound to Red, x > 0 (face 1) to Green by GeomSubsets.
    Rendered r = render(R"(
def Mesh "Quad"
{
    uniform token subdivisionScheme = "none"
    int[] faceVertexCounts = [4, 4]
    int[] faceVertexIndices = [0, 1, 4, 3, 1, 2, 5, 4]
    point3f[] points = [(-1.5, -1.5, 0), (0, -1.5, 0), (1.5, -1.5, 0), (-1.5, 1.5, 0), (0, 1.5, 0), (1.5, 1.5, 0)]
    def GeomSubset "Left"
    {
        uniform token elementType = "face"
        uniform token familyName = "materialBind"
        int[] indices = [0]
        rel material:binding = </Looks/Red>
    }
    def GeomSubset "Right"
    {
        uniform token elementType = "face"
        uniform token familyName = "materialBind"
        int[] indices = [1]
        rel material:binding = </Looks/Green>
    }
}
def Scope "Looks"
{
    def Material "Green"
    {
        token outputs:surface.connect = </Looks/Green/S.outputs:surface>
        def Shader "S"
        {
            uniform token info:id = "UsdPreviewSurface"
            color3f inputs:diffuseColor = (0, 0.8, 0)
            token outputs:surface
        }
    }
    def Material "Red"
    {
        token outputs:surface.connect = </Looks/Red/S.outputs:surface>
        def Shader "S"
        {
            uniform token info:id = "UsdPreviewSurface"
            color3f inputs:diffuseColor = (0.8, 0, 0)
            token outputs:surface
        }
    }
}
)");
    // Materials are indexed in path order: Green 0, Red 1.
    int lx = r.px(-0.75), rx = r.px(0.75), y = r.py(0.0);
    EXPECT_EQ(r.id("elementId", lx, y), 0);
    EXPECT_EQ(r.id("elementId", rx, y), 1);
    EXPECT_EQ(r.id("materialId", lx, y), 1);
    EXPECT_EQ(r.id("materialId", rx, y), 0);
    EXPECT_GT(r.color(lx, y)[0], 4.0f * r.color(lx, y)[1]);
    EXPECT_GT(r.color(rx, y)[1], 4.0f * r.color(rx, y)[0]);
}

TEST(Geometry, PointInstancerPlacesInstancesAndHidesInvisibleIds) {
    // Three instances of a sphere along X; instance 1 (at the origin, where the prototype
    // itself sits) is hidden, so nothing may be drawn there: prototypes are drawn only
    // through their instancer.
    Rendered r = render(R"(
def PointInstancer "Inst"
{
    rel prototypes = [</Inst/Protos/Ball>, </Inst/Protos/Box>]
    int[] protoIndices = [0, 0, 0, 1]
    point3f[] positions = [(-1.2, 0, 0), (0, 0, 0), (1.2, 0, 0), (0, 1.2, 0)]
    quath[] orientations = [(1, 0, 0, 0), (1, 0, 0, 0), (1, 0, 0, 0), (0.7071068, 0, 0, 0.7071068)]
    float3[] scales = [(1, 1, 1), (1, 1, 1), (1, 1, 1), (2, 1, 1)]
    int64[] invisibleIds = [1]
    def Scope "Protos"
    {
        def Sphere "Ball" { double radius = 0.4 }
        def Xform "Box"
        {
            double3 xformOp:translate = (0, 0, 0)
            uniform token[] xformOpOrder = ["xformOp:translate"]
            def Cube "Body" { double size = 0.4 }
        }
    }
}
)",
                        64);
    int y = r.py(0.0);
    int ball = r.id("primId", r.px(-1.2), y);
    EXPECT_GE(ball, 0);
    EXPECT_EQ(r.id("primId", r.px(1.2), y), ball);
    EXPECT_EQ(r.id("instanceId", r.px(-1.2), y), 0);
    EXPECT_EQ(r.id("instanceId", r.px(1.2), y), 2);
    EXPECT_EQ(r.id("primId", r.px(0.0), y), -1);  // invisibleIds, and no prototype drawn
    // Instance 3: the box, scaled 2x along X and then turned 90 degrees: 0.4 wide, 0.8 tall.
    EXPECT_EQ(r.id("instanceId", r.px(0.0), r.py(1.2)), 3);
    EXPECT_NE(r.id("primId", r.px(0.0), r.py(1.2)), ball);
    EXPECT_GE(r.id("primId", r.px(0.0), r.py(1.5)), 0);
    EXPECT_EQ(r.id("primId", r.px(0.3), r.py(1.2)), -1);
    auto stats = r.session->stats();
    EXPECT_EQ(stats["blasBuilds"], 2.0);  // one per prototype rprim
    EXPECT_EQ(stats["instances"], 3.0);   // 4 minus the invisible one
}

TEST(Geometry, HundredThousandInstancesShareOneBlas) {
    const int n = 100000;
    std::string positions, ids;
    positions.reserve(size_t(n) * 24);
    for (int i = 0; i < n; ++i) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%s(%.4f, %.4f, 0)", i ? ", " : "", -1.9 + 3.8 * (i % 316) / 315.0,
                      -1.9 + 3.8 * (i / 316) / 316.0);
        positions += buf;
        ids += i ? ", 0" : "0";
    }
    std::string scene = "def PointInstancer \"Inst\"\n{\n    rel prototypes = [</Inst/P/Tri>]\n    int[] protoIndices = [" + ids +
                        "]\n    point3f[] positions = [" + positions + R"(]
    def Scope "P"
    {
        def Mesh "Tri"
        {
            uniform token subdivisionScheme = "none"
            int[] faceVertexCounts = [3]
            int[] faceVertexIndices = [0, 1, 2]
            point3f[] points = [(-0.005, -0.005, 0), (0.005, -0.005, 0), (0, 0.005, 0)]
        }
    }
}
)";
    auto start = std::chrono::steady_clock::now();
    Rendered r = render(scene, 16, 1);
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(r.session->stats()["blasBuilds"], 1.0);
    EXPECT_LT(seconds, 5.0);
    std::printf("100k instances: parse + sync + 16x16x1 render in %.3f s\n", seconds);
}

TEST(Geometry, InstanceablePrimsShareOnePrototypeBlas) {
    Rendered r = render(R"(
class Xform "_Ball"
{
    def Sphere "Ball" { double radius = 0.4 }
}
def Xform "A" (instanceable = true
    prepend references = </_Ball>)
{
    double3 xformOp:translate = (-1.2, 0, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
def Xform "B" (instanceable = true
    prepend references = </_Ball>)
{
    double3 xformOp:translate = (1.2, 0, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
def Xform "C" (instanceable = true
    prepend references = </_Ball>)
{
    token visibility = "invisible"
    double3 xformOp:translate = (0, 1.2, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
)",
                        64);
    int y = r.py(0.0);
    int a = r.id("primId", r.px(-1.2), y);
    EXPECT_GE(a, 0);
    EXPECT_EQ(r.id("primId", r.px(1.2), y), a);  // B's hits report the prototype rprim (A's)
    EXPECT_EQ(r.id("instanceId", r.px(-1.2), y), 0);
    EXPECT_EQ(r.id("instanceId", r.px(1.2), y), 1);
    EXPECT_EQ(r.id("primId", r.px(0.0), r.py(1.2)), -1);  // invisible instance
    EXPECT_EQ(r.id("primId", r.px(0.0), y), -1);          // nothing at the prototype's origin
    EXPECT_EQ(r.session->stats()["blasBuilds"], 1.0);
}

TEST(Geometry, UsdWgPrimitivesRender) {
    std::string dir = std::string(PRINCIPLED_SOURCE_DIR) +
                      "/../shared/usd-wg/test_assets/schemaTests/usdGeom/primitives";
    for (const char* name : {"cube", "cylinder", "cone", "capsule", "sphere", "all_primitives"}) {
        SCOPED_TRACE(name);
        host::SessionOptions o;
        o.width = o.height = 32;
        o.samplesPerPixel = 2;
        auto s = host::RenderSession::openFile(dir + "/" + name + ".usda", o);
        while (!s->step()) {
        }
        int hits = 0;
        for (int i = 0; i < 32 * 32; ++i) {
            for (int k = 0; k < 4; ++k) ASSERT_TRUE(std::isfinite(s->color()[4 * i + k]));
            hits += s->color()[4 * i + 3] > 0.0f;
        }
        EXPECT_GT(hits, 20);
    }
}

TEST(Geometry, InstanceablePrimsWithLightsAreExpanded) {
    // A prototype holding a light is not shared (its lights must stay lights): two BLAS.
    Rendered r = render(R"(
class Xform "_Lamp"
{
    def Sphere "Ball" { double radius = 0.4 }
    def DistantLight "Sun" { float inputs:intensity = 1 }
}
def Xform "A" (instanceable = true
    prepend references = </_Lamp>)
{
    double3 xformOp:translate = (-1.2, 0, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
def Xform "B" (instanceable = true
    prepend references = </_Lamp>)
{
    double3 xformOp:translate = (1.2, 0, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
)");
    auto stats = r.session->stats();
    EXPECT_EQ(stats["blasBuilds"], 2.0);
    EXPECT_EQ(stats["lights"], 2.0);
    EXPECT_EQ(stats["instances"], 0.0);
}

TEST(Geometry, BadInstancerAndShapeInputWarnsAndRendersTheRest) {
    Rendered r = render(R"(
def PointInstancer "Inst"
{
    rel prototypes = [</Inst/P/Ball>, </Nope>]
    int[] protoIndices = [0, 5, -1, 0, 1]
    point3f[] positions = [(0, 0, 0), (1, 0, 0), (2, 0, 0)]
    quath[] orientations = [(1, 0, 0, 0)]
    float3[] scales = [(1, 1, 1), (1, 1, 1), (1, 1, 1), (1, 1, 1), (1, 1, 1)]
    def Scope "P" { def Sphere "Ball" { double radius = 0.3 } }
}
def PointInstancer "Empty" { }
def Cone "K" { double radius = inf }
def Capsule "Cap" { uniform token axis = "Q" }
)");
    std::string all;
    for (const auto& w : r.session->takeWarnings()) all += w + "\n";
    for (const char* expected : {"'/Nope' does not exist", "has no prototypes", "Cone not rendered",
                                 "axis 'Q'", "orientations has 1 values", "scales has 5 values",
                                 "protoIndices is longer than positions"})
        EXPECT_NE(all.find(expected), std::string::npos) << expected << "\n" << all;
    EXPECT_EQ(r.session->stats()["instances"], 1.0);
    EXPECT_EQ(r.id("primId", r.px(0.0), r.py(0.0)), r.id("primId", r.px(-0.1), r.py(0.0)));
    EXPECT_GE(r.id("primId", r.px(0.0), r.py(0.0)), 0);
}

TEST(Geometry, InstancesWithASingularTransformAreLeftOutWithAWarning) {
    // A zero scale (fuzzing found it): Embree asserted on the invalid rays (PointInstancer) or
    // on degenerate instance bounds (instanceable prims under a zero transform).
    Rendered r = render(R"(
def PointInstancer "Inst"
{
    rel prototypes = [</Inst/P/Ball>]
    int[] protoIndices = [0, 0, 0]
    point3f[] positions = [(0, 0, 0), (1, 0, 0), (2, 0, 0)]
    float3[] scales = [(1, 1, 1), (1, 1, 0), (0, 0, 0)]
    def Scope "P" { def Sphere "Ball" { double radius = 0.3 } }
}
def Xform "Flat" (instanceable = true)
{
    double3 xformOp:scale = (0, 0, 0)
    uniform token[] xformOpOrder = ["xformOp:scale"]
    def Sphere "S" { double radius = 0.3 }
}
def Xform "Flat2" (instanceable = true)
{
    double3 xformOp:scale = (0, 0, 0)
    uniform token[] xformOpOrder = ["xformOp:scale"]
    def Sphere "S" { double radius = 0.3 }
}
)");
    std::string all;
    for (const auto& w : r.session->takeWarnings()) all += w + "\n";
    EXPECT_NE(all.find("2 instance(s) of /Inst/P/Ball have a transform that is singular"), std::string::npos) << all;
    EXPECT_EQ(r.session->stats()["instances"], 1.0);
    EXPECT_GE(r.id("primId", r.px(0.0), r.py(0.0)), 0);
}

TEST(Geometry, EmissiveInstancerPrototypesAreNotPlacedAsLights) {
    // The prototype's own record is instancer-relative: it must not become a mesh light at
    // the wrong place; each placed instance is a light of its own (the sun + one instance; that
    // it sits where the instance is drawn is checked by Integrator.InstancedEmittersAreLights).
    Rendered r = render(R"(
def PointInstancer "Inst"
{
    rel prototypes = [</Inst/P/Panel>]
    int[] protoIndices = [0]
    point3f[] positions = [(1, 0, 0)]
    def Scope "P"
    {
        def Mesh "Panel" (prepend apiSchemas = ["MaterialBindingAPI"])
        {
            uniform token subdivisionScheme = "none"
            int[] faceVertexCounts = [4]
            int[] faceVertexIndices = [0, 1, 2, 3]
            point3f[] points = [(-0.5, -0.5, 0), (0.5, -0.5, 0), (0.5, 0.5, 0), (-0.5, 0.5, 0)]
            rel material:binding = </Glow>
        }
    }
}
def Material "Glow"
{
    token outputs:surface.connect = </Glow/S.outputs:surface>
    def Shader "S"
    {
        uniform token info:id = "UsdPreviewSurface"
        color3f inputs:emissiveColor = (2, 2, 2)
        token outputs:surface
    }
}
def DistantLight "Sun" { float inputs:intensity = 1 }
)");
    EXPECT_EQ(r.session->stats()["lights"], 2.0);
    EXPECT_GT(r.color(r.px(1.0), r.py(0.0))[0], 1.5f);  // the instance, emitting
    EXPECT_EQ(r.id("primId", r.px(0.0), r.py(0.0)), -1);  // nothing at the prototype's origin
}
