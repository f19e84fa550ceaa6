// The per-scene report of what the renderer models (delegate/sceneFeatures.h), through a session.
#include <gtest/gtest.h>

#include "delegate/renderDelegate.h"
#include "plugins/renderSession.h"

using namespace principled;

namespace {

std::string scene(float opacity) {
    return R"(#usda 1.0
def Sphere "Ball" (prepend apiSchemas = ["MaterialBindingAPI"])
{
    rel material:binding = </Metal>
}
def Mesh "Floor" (prepend apiSchemas = ["MaterialBindingAPI"])
{
    uniform token subdivisionScheme = "none"
    int[] faceVertexCounts = [4]
    int[] faceVertexIndices = [0, 1, 2, 3]
    point3f[] points = [(-5, -1, -5), (-5, -1, 5), (5, -1, 5), (5, -1, -5)]
    rel material:binding = </Coated>
}
def Material "Metal"
{
    token outputs:surface.connect = </Metal/S.outputs:surface>
    def Shader "S"
    {
        uniform token info:id = "UsdPreviewSurface"
        float inputs:metallic = 1
        float inputs:roughness = 0.3
        float inputs:clearcoat = 0.00001
        token outputs:surface
    }
}
def Material "Coated"
{
    token outputs:surface.connect = </Coated/S.outputs:surface>
    def Shader "S"
    {
        uniform token info:id = "UsdPreviewSurface"
        float inputs:clearcoat = 1
        float inputs:opacity = )" + std::to_string(opacity) + R"(
        token outputs:surface
    }
}
def RectLight "Panel"
{
    float inputs:intensity = 5
    double3 xformOp:translate = (0, 3, 0)
    float xformOp:rotateX = -90
    uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:rotateX"]
}
def DistantLight "Sun"
{
    float inputs:intensity = 2
}
def Camera "Cam"
{
    double3 xformOp:translate = (0, 0, 8)
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
)";
}

}  // namespace

TEST(SceneFeatures, ReportsLobesLightsGeometryAndSkips) {
    host::SessionOptions o;
    o.width = o.height = 8;
    o.samplesPerPixel = 1;
    auto s = host::RenderSession::openString(scene(1.0f), "features.usda", o);
    auto st = s->stats();
    // Metal: specular only (no diffuse at metallic 1; its 1e-5 clearcoat is pruned); the
    // coated dielectric: diffuse, specular, clearcoat.
    EXPECT_EQ(st["scene.lobe.specular"], 2);
    EXPECT_EQ(st["scene.lobe.diffuse"], 1);
    EXPECT_EQ(st["scene.lobe.clearcoat"], 1);
    EXPECT_EQ(st["scene.lobe.transmission"], 0);
    EXPECT_EQ(st["scene.lobe.pruned"], 1);
    EXPECT_EQ(st["scene.material.untextured"], 2);
    EXPECT_EQ(st["scene.material.textured"], 0);
    EXPECT_EQ(st["scene.light.rect"], 1);
    EXPECT_EQ(st["scene.light.distant"], 1);
    EXPECT_EQ(st["scene.light.mesh"], 0);
    EXPECT_EQ(st["scene.geometry.sphere"], 1);
    EXPECT_EQ(st["scene.geometry.mesh"], 1);
    EXPECT_EQ(st["scene.geometry.triangles"], 2);
    EXPECT_EQ(st["scene.skip.plainShadowRays"], 1);
    EXPECT_EQ(st["scene.neeAllLights"], 1);
    std::string line = s->delegate()->sceneSummary();
    EXPECT_NE(line.find("clearcoat 1"), std::string::npos) << line;
    EXPECT_NE(line.find("plain occlusion"), std::string::npos) << line;

    // A partly present material turns the plain occlusion query off.
    auto t = host::RenderSession::openString(scene(0.5f), "features.usda", o);
    EXPECT_EQ(t->stats()["scene.skip.plainShadowRays"], 0);
    EXPECT_EQ(t->stats()["scene.material.partlyPresent"], 1);
}
