#include "scene_adapter/usdSceneDelegate.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "delegate/hd/camera.h"
#include "delegate/hd/tokens.h"
#include "delegate/renderDelegate.h"
#include "scene_adapter/usda/stage.h"

using namespace principled;

namespace {

struct Populated {
    std::unique_ptr<usd::Stage> stage;
    embree::EmbreeRenderDelegate renderDelegate;
    hd::RenderIndex index{&renderDelegate};
    std::unique_ptr<adapter::UsdSceneDelegate> scene;
    explicit Populated(const std::string& text) {
        stage = usd::Stage::openString(text, "t.usda");
        scene = std::make_unique<adapter::UsdSceneDelegate>(*stage);
        scene->populate(&index);
    }
};

const char* kScene = R"(#usda 1.0
def Xform "World"
{
    double3 xformOp:translate = (0, 10, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
    rel material:binding = </World/Looks/Red>
    def Mesh "Tri"
    {
        int[] faceVertexCounts = [3]
        int[] faceVertexIndices = [0, 1, 2]
        point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
        normal3f[] normals = [(0, 0, 1)] (interpolation = "constant")
        color3f[] primvars:displayColor = [(1, 0, 0)]
        texCoord2f[] primvars:st = [(0, 0), (1, 0)] (interpolation = "faceVarying")
        int[] primvars:st:indices = [0, 1, 1]
    }
    def Sphere "Guide"
    {
        uniform token purpose = "guide"
    }
    def Sphere "Hidden"
    {
        token visibility = "invisible"
    }
    def Cube "Box"
    {
    }
    def Camera "Cam"
    {
        float focalLength = 35
        float horizontalAperture = 36
    }
    def Scope "Looks"
    {
        def Material "Red"
        {
            float inputs:rough = 0.25
            token outputs:surface.connect = </World/Looks/Red/S.outputs:surface>
            def Shader "S"
            {
                uniform token info:id = "UsdPreviewSurface"
                color3f inputs:diffuseColor.connect = </World/Looks/Red/Tex.outputs:rgb>
                float inputs:roughness.connect = </World/Looks/Red.inputs:rough>
                token outputs:surface
            }
            def Shader "Tex"
            {
                uniform token info:id = "UsdUVTexture"
                asset inputs:file = @tex.png@
                float3 outputs:rgb
            }
        }
    }
    def DistantLight "Sun"
    {
        float inputs:intensity = 3
    }
}
)";

}  // namespace

TEST(UsdSceneDelegate, PopulatesRenderablePrimsAndSkipsGuides) {
    Populated p(kScene);
    EXPECT_NE(p.index.rprim(hd::Path("/World/Tri")), nullptr);
    EXPECT_EQ(p.index.rprim(hd::Path("/World/Guide")), nullptr);
    EXPECT_NE(p.index.rprim(hd::Path("/World/Hidden")), nullptr);
    EXPECT_FALSE(p.scene->getVisible(hd::Path("/World/Hidden")));
    EXPECT_EQ(p.scene->cameras(), std::vector<hd::Path>{hd::Path("/World/Cam")});
    // Implicit shapes are meshes now (scene_adapter/implicitShapes.h), without a warning.
    EXPECT_NE(p.index.rprim(hd::Path("/World/Box")), nullptr);
    for (const auto& w : p.scene->warnings()) EXPECT_EQ(w.find("Cube"), std::string::npos) << w;
    EXPECT_EQ(p.scene->getMeshTopology(hd::Path("/World/Box")).faceVertexCounts.size(), 6u);
}

TEST(UsdSceneDelegate, TransformsTopologyAndPrimvars) {
    Populated p(kScene);
    hd::Path tri("/World/Tri");
    glm::dmat4 m = p.scene->getTransform(tri);
    EXPECT_DOUBLE_EQ(m[3][1], 10.0);
    hd::MeshTopology t = p.scene->getMeshTopology(tri);
    EXPECT_EQ(t.scheme, hd::Token("catmullClark"));  // the USD fallback
    EXPECT_EQ(t.faceVertexIndices, (std::vector<int>{0, 1, 2}));
    auto constant = p.scene->getPrimvarDescriptors(tri, hd::Interpolation::Constant);
    bool hasColor = false, hasNormals = false;
    for (const auto& d : constant) {
        hasColor |= d.name == hd::Token("displayColor");
        hasNormals |= d.name == hd::tokens::normals();
    }
    EXPECT_TRUE(hasColor);
    EXPECT_TRUE(hasNormals);
    auto fv = p.scene->getPrimvarDescriptors(tri, hd::Interpolation::FaceVarying);
    ASSERT_EQ(fv.size(), 1u);
    EXPECT_TRUE(fv[0].indexed);
    std::vector<int> idx;
    hd::Value st = p.scene->getIndexedPrimvar(tri, hd::Token("st"), &idx);
    EXPECT_EQ(idx, (std::vector<int>{0, 1, 1}));
    EXPECT_EQ(hd::getIf<std::vector<glm::vec2>>(st)->size(), 2u);
}

TEST(UsdSceneDelegate, InheritedBindingAndNetworkThroughInterfaceInputs) {
    Populated p(kScene);
    EXPECT_EQ(p.scene->getMaterialId(hd::Path("/World/Tri")), hd::Path("/World/Looks/Red"));
    hd::MaterialNetwork n = p.scene->getMaterialResource(hd::Path("/World/Looks/Red"));
    EXPECT_EQ(n.surfaceTerminal, hd::Path("/World/Looks/Red/S"));
    ASSERT_EQ(n.nodes.size(), 2u);
    EXPECT_EQ(n.nodes.back().path, n.surfaceTerminal);  // upstream first
    const hd::MaterialNode* s = n.node(n.surfaceTerminal);
    ASSERT_TRUE(s);
    EXPECT_EQ(*hd::getFloat(s->parameters.at(hd::Token("roughness"))), 0.25f);  // via interface
    auto& c = s->inputConnections.at(hd::Token("diffuseColor"));
    ASSERT_EQ(c.size(), 1u);
    EXPECT_EQ(c[0].upstreamNode, hd::Path("/World/Looks/Red/Tex"));
    EXPECT_EQ(c[0].upstreamOutput, hd::Token("rgb"));
}

TEST(UsdSceneDelegate, CameraLengthsAreTenthsOfASceneUnit) {
    Populated p(kScene);
    hd::Path cam("/World/Cam");
    EXPECT_FLOAT_EQ(*hd::getFloat(p.scene->getCameraParamValue(cam, hd::Token("focalLength"))), 3.5f);
    EXPECT_FLOAT_EQ(*hd::getFloat(p.scene->getCameraParamValue(cam, hd::Token("horizontalAperture"))), 3.6f);
    EXPECT_FLOAT_EQ(*hd::getFloat(p.scene->getLightParamValue(hd::Path("/World/Sun"), hd::Token("intensity"))), 3.0f);
}

TEST(UsdSceneDelegate, DepthOfFieldInputsAndTheStageUnitReachTheCamera) {
    // fStop is a ratio and focusDistance is in scene units: neither is scaled like the lens
    // lengths. The stage's metersPerUnit (fallback 0.01) converts the focal length's millimetres.
    const char* text = R"(#usda 1.0
(
    metersPerUnit = 1
)
def Camera "Cam"
{
    float focalLength = 50
    float fStop = 2.8
    float focusDistance = 4.5
}
)";
    Populated p(text);
    hd::Path cam("/Cam");
    EXPECT_FLOAT_EQ(*hd::getFloat(p.scene->getCameraParamValue(cam, hd::Token("fStop"))), 2.8f);
    EXPECT_FLOAT_EQ(*hd::getFloat(p.scene->getCameraParamValue(cam, hd::Token("focusDistance"))), 4.5f);
    EXPECT_FLOAT_EQ(*hd::getFloat(p.scene->getCameraParamValue(cam, hd::Token("metersPerUnit"))), 1.0f);
    EXPECT_FLOAT_EQ(*hd::getFloat(Populated(kScene).scene->getCameraParamValue(
                        hd::Path("/World/Cam"), hd::Token("metersPerUnit"))),
                    0.01f);  // not authored: the UsdGeom fallback
    // Synced into the camera sprim: 50 mm / (2 x 2.8) on a metre stage = 8.93 mm.
    p.index.sync();
    auto* c = dynamic_cast<hd::Camera*>(p.index.sprim(hd::tokens::camera(), cam));
    ASSERT_TRUE(c);
    EXPECT_NEAR(c->lensRadius(), 0.050f / 5.6f, 1e-6f);
}

TEST(UsdSceneDelegate, EveryCorpusFileLoadsWithoutCrashing) {
    // Populating every usd-wg file exercises odd but valid input; none may throw past the
    // stage (composition errors are warnings) or crash.
    std::string root = std::string(PRINCIPLED_SOURCE_DIR) + "/../shared/usd-wg";
    int files = 0;
    for (const auto& e : std::filesystem::recursive_directory_iterator(root)) {
        if (e.path().extension() != ".usda") continue;
        ++files;
        std::unique_ptr<usd::Stage> stage;
        try {
            stage = usd::Stage::open(e.path().string());
        } catch (const usd::Error& err) {
            ADD_FAILURE() << err.what();
            continue;
        }
        embree::EmbreeRenderDelegate rd;
        hd::RenderIndex index(&rd);
        adapter::UsdSceneDelegate sd(*stage);
        sd.populate(&index);
        index.sync();
    }
    EXPECT_GT(files, 50);
}
