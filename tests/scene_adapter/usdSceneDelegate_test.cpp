#include "scene_adapter/usdSceneDelegate.h"

#include <gtest/gtest.h>

#include <set>

#include "delegate/primvarUtil.h"

#include <filesystem>

#include "delegate/hd/camera.h"
#include "delegate/hd/tokens.h"
#include "delegate/renderDelegate.h"
#include "delegate/shading/materialProgram.h"
#include "scene_adapter/usda/stage.h"
#include "tests/delegate/shading/testImages.h"

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

TEST(UsdSceneDelegate, TraversalFollowsDefinitionPurposeAndXformability) {
    // A def under an `over` nothing defines is not drawn (UsdPrimDefaultPredicate); a child
    // that authors purpose "render" under a guide is drawn (its own opinion wins), one that
    // authors nothing is not; a Scope's and an untyped prim's xformOps are ignored, with a
    // warning, while an Xform's apply.
    Populated p(R"(#usda 1.0
over "Renamed" { def Sphere "Ball" { } }
def Xform "Guides" ( ) {
    uniform token purpose = "guide"
    def Sphere "Inherits" { }
    def Sphere "Render" { uniform token purpose = "render" }
}
def Scope "Group" {
    double3 xformOp:translate = (5, 0, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
    def Sphere "InScope" { }
}
def "Untyped" {
    double3 xformOp:translate = (0, 5, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
    def Xform "Moved" {
        double3 xformOp:translate = (0, 0, 2)
        uniform token[] xformOpOrder = ["xformOp:translate"]
        def Sphere "Ball" { }
    }
}
)");
    EXPECT_EQ(p.index.rprim(hd::Path("/Renamed/Ball")), nullptr);
    EXPECT_EQ(p.index.rprim(hd::Path("/Guides/Inherits")), nullptr);
    EXPECT_NE(p.index.rprim(hd::Path("/Guides/Render")), nullptr);
    ASSERT_NE(p.index.rprim(hd::Path("/Group/InScope")), nullptr);
    EXPECT_EQ(p.scene->getTransform(hd::Path("/Group/InScope"))[3], glm::dvec4(0, 0, 0, 1));
    EXPECT_EQ(p.scene->getTransform(hd::Path("/Untyped/Moved/Ball"))[3], glm::dvec4(0, 0, 2, 1));
    int notXformable = 0;
    for (const auto& w : p.scene->warnings()) notXformable += w.find("is not Xformable") != std::string::npos;
    EXPECT_EQ(notXformable, 2);
}

TEST(UsdSceneDelegate, AMetreLongLensWithDepthOfFieldIsReported) {
    Populated mm(R"(#usda 1.0
( metersPerUnit = 1 )
def Camera "C" { float focalLength = 50
    float fStop = 2.8
    float focusDistance = 3 }
)");
    std::string all;
    for (const auto& w : mm.scene->warnings()) all += w + "\n";
    EXPECT_NE(all.find("focalLength 50 is a 5 m lens"), std::string::npos) << all;
    Populated tenths(R"(#usda 1.0
( metersPerUnit = 1 )
def Camera "C" { float focalLength = 0.5
    float fStop = 2.8
    float focusDistance = 3 }
)");
    for (const auto& w : tenths.scene->warnings()) EXPECT_EQ(w.find("lens"), std::string::npos) << w;
}

TEST(UsdSceneDelegate, ImplicitShapesOutsideTheirExtentAreReported) {
    Populated p(R"(#usda 1.0
def Cube "Small" { double size = 2
    float3[] extent = [(-0.1, -0.1, -0.1), (0.1, 0.1, 0.1)] }
def Cube "Right" { double size = 2
    float3[] extent = [(-1, -1, -1), (1, 1, 1)] }
def Sphere "Ball" { double radius = 3
    float3[] extent = [(-1, -1, -1), (1, 1, 1)] }
)");
    std::string all;
    for (const auto& w : p.scene->warnings()) all += w + "\n";
    EXPECT_NE(all.find("/Small: the Cube reaches outside its authored extent"), std::string::npos) << all;
    EXPECT_NE(all.find("/Ball: the Sphere reaches outside"), std::string::npos) << all;
    EXPECT_EQ(all.find("/Right"), std::string::npos) << all;
}

TEST(UsdSceneDelegate, SubsetFacesOutsideTheMeshAreReported) {
    Populated p(R"(#usda 1.0
def Mesh "M" {
    int[] faceVertexCounts = [3, 3]
    int[] faceVertexIndices = [0, 1, 2, 0, 2, 3]
    point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
    def GeomSubset "Sub" {
        uniform token elementType = "face"
        uniform token familyName = "materialBind"
        int[] indices = [1, 7, -3]
    }
}
)");
    std::string all;
    for (const auto& w : p.scene->warnings()) all += w + "\n";
    EXPECT_NE(all.find("/M/Sub: GeomSubset indices name 2 face(s) outside the mesh's [0, 2) (the first: 7)"), std::string::npos) << all;
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

TEST(UsdSceneDelegate, ConstantPrimvarsAreInheritedFromAncestors) {
    // UsdGeomPrimvarsAPI::FindInheritablePrimvars: constant primvars of ancestors reach a prim
    // that authors none of that name (nearest wins; its own, or a non-constant one on a nearer
    // ancestor, hides them), indices included.
    Populated p(R"(#usda 1.0
def Xform "World" {
    color3f[] primvars:displayColor = [(1, 0, 0)]
    float[] primvars:tint = [0.25, 0.75]
    int[] primvars:tint:indices = [1]
    float primvars:ramp = 3
    def Xform "Group" {
        float[] primvars:ramp = [1, 2, 3] (interpolation = "vertex")
        def Sphere "Inherits" { }
        def Sphere "Own" { color3f[] primvars:displayColor = [(0, 0, 1)] }
        def Sphere "PerPoint" { color3f[] primvars:displayColor = [(0, 1, 0), (0, 0, 1)] (interpolation = "vertex") }
        def Sphere "Declared" { color3f[] primvars:displayColor }
    }
}
)");
    const hd::Path inherits("/World/Group/Inherits"), own("/World/Group/Own");
    auto names = [&](const hd::Path& id) {
        std::set<std::string> out;
        for (const auto& d : p.scene->getPrimvarDescriptors(id, hd::Interpolation::Constant)) out.insert(d.name.str());
        return out;
    };
    EXPECT_EQ(names(inherits), (std::set<std::string>{"displayColor", "tint"}));  // ramp: blocked by Group's
    EXPECT_EQ(embree::constantDisplayColor(p.scene.get(), inherits), glm::vec3(1, 0, 0));
    EXPECT_EQ(embree::constantDisplayColor(p.scene.get(), own), glm::vec3(0, 0, 1));
    // Per-element colours are no constant colour (their first used to colour the whole prim
    // when they were invalid and ignored).
    EXPECT_FALSE(embree::constantDisplayColor(p.scene.get(), hd::Path("/World/Group/PerPoint")).has_value());
    // Declared without a value: as if not there (it hides nothing).
    EXPECT_EQ(embree::constantDisplayColor(p.scene.get(), hd::Path("/World/Group/Declared")), glm::vec3(1, 0, 0));
    std::vector<int> idx;
    hd::Value tint = p.scene->getIndexedPrimvar(inherits, hd::Token("tint"), &idx);
    ASSERT_NE(hd::getIf<std::vector<float>>(tint), nullptr);
    EXPECT_EQ(idx, (std::vector<int>{1}));
    EXPECT_TRUE(hd::isEmpty(p.scene->getIndexedPrimvar(inherits, hd::Token("ramp"), &idx)));
}

TEST(UsdSceneDelegate, PointInstancerVelocitiesAndHiddenIds) {
    // Positions move on from their sample by velocities (and accelerations) sampled at the same
    // time, dt in seconds (24 time codes per second); velocities sampled elsewhere are ignored
    // (interpolation). inactiveIds (metadata) and invisibleIds hide instances by id, ids beyond
    // 32 bits included.
    const std::string scene = R"(#usda 1.0
( timeCodesPerSecond = 24 )
def PointInstancer "PI" ( prepend inactiveIds = [8589934592] ) {
    rel prototypes = [</PI/Ball>]
    int[] protoIndices = [0, 0, 0]
    int64[] ids = [4294967296, 4294967297, 8589934592]
    int64[] invisibleIds = [4294967297]
    point3f[] positions.timeSamples = { 0: [(0, 0, 0), (1, 0, 0), (2, 0, 0)], 24: [(0, 5, 0), (1, 5, 0), (2, 5, 0)] }
    vector3f[] velocities.timeSamples = { 0: [(0, 2, 0), (0, 2, 0), (0, 2, 0)] }
    vector3f[] accelerations.timeSamples = { 0: [(4, 0, 0), (4, 0, 0), (4, 0, 0)] }
    def Sphere "Ball" { }
}
def PointInstancer "Late" {
    rel prototypes = [</Late/Ball>]
    int[] protoIndices = [0]
    point3f[] positions.timeSamples = { 0: [(0, 0, 0)], 24: [(0, 4, 0)] }
    vector3f[] velocities.timeSamples = { 6: [(0, 100, 0)] }
    def Sphere "Ball" { }
}
)";
    auto stage = usd::Stage::openString(scene, "pi.usda");
    embree::EmbreeRenderDelegate rd;
    hd::RenderIndex index(&rd);
    adapter::AdapterOptions o;
    o.time = 12.0;  // 0.5 s after the sample at 0
    adapter::UsdSceneDelegate sd(*stage, o);
    sd.populate(&index);
    const auto pi = sd.getInstancerArrays(hd::Path("/PI"));
    ASSERT_TRUE(pi->translations.has_value());
    ASSERT_EQ(pi->translations->size(), 3u);
    EXPECT_NEAR((*pi->translations)[0].y, 1.0f, 1e-5f);  // 2 * 0.5, not the interpolated 2.5
    EXPECT_NEAR((*pi->translations)[0].x, 0.5f, 1e-5f);  // 4 * 0.5^2 / 2
    EXPECT_EQ(sd.getInstanceIndices(hd::Path("/PI"), hd::Path("/PI/Ball")), (std::vector<int>{0}));
    const auto late = sd.getInstancerArrays(hd::Path("/Late"));
    ASSERT_TRUE(late->translations.has_value());
    EXPECT_NEAR((*late->translations)[0].y, 2.0f, 1e-5f);  // interpolated
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
    // lengths, which are tenths of a scene unit (on this metre stage 0.5 is 50 mm).
    const char* text = R"(#usda 1.0
(
    metersPerUnit = 1
)
def Camera "Cam"
{
    float focalLength = 0.5
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
    // Synced into the camera sprim: 0.05 m / (2 x 2.8) = 8.93 mm.
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

namespace {

// MaterialX materials (docs/materials.md, "MaterialX"): terminal choice, Standard Surface, and a
// NodeGraph of MaterialX texture nodes. TEX is replaced by an image's path.
const char* kMaterialXLooks = R"(#usda 1.0
def Scope "Looks"
{
    def Material "MxOnly"
    {
        token outputs:mtlx:surface.connect = </Looks/MxOnly/SS.outputs:out>
        def Shader "SS"
        {
            uniform token info:id = "ND_standard_surface_surfaceshader"
            color3f inputs:base_color = (0.8, 0.1, 0.1)
            float inputs:metalness = 1
            float inputs:specular_roughness = 0.3
            token outputs:out
        }
    }
    def Material "Both"
    {
        token outputs:mdl:surface.connect = </Looks/Both/Mdl.outputs:out>
        token outputs:mtlx:surface.connect = </Looks/Both/SS.outputs:out>
        token outputs:surface.connect = </Looks/Both/Preview.outputs:surface>
        def Shader "Preview"
        {
            uniform token info:id = "UsdPreviewSurface"
            color3f inputs:diffuseColor = (1, 0, 0)
            token outputs:surface
        }
        def Shader "SS"
        {
            uniform token info:id = "ND_standard_surface_surfaceshader"
            color3f inputs:base_color = (0, 0, 1)
            token outputs:out
        }
        def Shader "Mdl"
        {
            uniform token info:implementationSource = "sourceAsset"
            token outputs:out
        }
    }
    def Material "MdlOnly"
    {
        token outputs:mdl:surface.connect = </Looks/MdlOnly/Mdl.outputs:out>
        def Shader "Mdl"
        {
            uniform token info:implementationSource = "sourceAsset"
            token outputs:out
        }
    }
    def Material "PreviewAsMtlx"
    {
        token outputs:mtlx:surface.connect = </Looks/PreviewAsMtlx/S.outputs:out>
        def Shader "S"
        {
            uniform token info:id = "ND_UsdPreviewSurface_surfaceshader"
            color3f inputs:diffuseColor = (0.1, 0.7, 0.2)
            float inputs:roughness = 0.4
            float inputs:clearcoat = 0.5
            token outputs:out
        }
    }
    def Material "Graph"
    {
        float inputs:rough = 0.45
        token outputs:mtlx:surface.connect = </Looks/Graph/SS.outputs:out>
        def Shader "SS"
        {
            uniform token info:id = "ND_standard_surface_surfaceshader"
            color3f inputs:base_color.connect = </Looks/Graph/NG.outputs:base_color>
            float inputs:specular_roughness.connect = </Looks/Graph.inputs:rough>
            float inputs:metalness = 0.25
            float inputs:metalness.connect = </Looks/Graph/NG.outputs:metal>
            float inputs:emission = 1
            color3f inputs:emission_color.connect = </Looks/Graph/NG.outputs:glow>
            token outputs:out
        }
        def NodeGraph "NG"
        {
            asset inputs:glowFile = @TEX@ (
                colorSpace = "srgb_texture"
            )
            color3f outputs:base_color.connect = </Looks/Graph/NG/Img.outputs:out>
            color3f outputs:glow.connect = </Looks/Graph/NG/GlowImg.outputs:out>
            float outputs:metal.connect = </Looks/Graph/NG/Mul.outputs:out>
            def Shader "Uv"
            {
                uniform token info:id = "ND_texcoord_vector2"
                float2 outputs:out
            }
            def Shader "Img"
            {
                uniform token info:id = "ND_image_color3"
                asset inputs:file = @TEX@ (
                    colorSpace = "lin_rec709"
                )
                float2 inputs:texcoord.connect = </Looks/Graph/NG/Uv.outputs:out>
                color3f outputs:out
            }
            def Shader "GlowImg"
            {
                uniform token info:id = "ND_image_color3"
                asset inputs:file.connect = </Looks/Graph/NG.inputs:glowFile>
                color3f outputs:out
            }
            def Shader "Mul"
            {
                uniform token info:id = "ND_noise2d_float"
                float inputs:in1 = 0.5
                float outputs:out
            }
        }
    }
}
)";

class StContext : public shading::ShadingContext {
  public:
    glm::vec2 st{0.0f};
    bool primvar(const hd::Token& name, int components, float* out) const override {
        if (name != hd::Token("st") || components != 2) return false;
        out[0] = st.x;
        out[1] = st.y;
        return true;
    }
    bool primvarDerivatives(const hd::Token&, glm::vec2*, glm::vec2*) const override {
        return false;
    }
};

struct MaterialXLooks {
    shading::test::TempDir dir;
    std::string texture = dir.file("rb.png");
    std::unique_ptr<Populated> scene;
    shading::TextureCache cache;
    std::vector<std::string> notes;

    MaterialXLooks() {
        // 2 x 1 texels: red on the left, blue on the right (8-bit codes 204).
        std::vector<float> px = {0.8f, 0.0f, 0.0f, 0.0f, 0.0f, 0.8f};
        EXPECT_TRUE(shading::test::writeImage(texture, 2, 1, 3, px, OIIO::TypeDesc::UINT8));
        std::string text = kMaterialXLooks;
        for (size_t at; (at = text.find("TEX")) != std::string::npos;) text.replace(at, 3, texture);
        scene = std::make_unique<Populated>(text);
    }
    hd::MaterialNetwork network(const char* material) {
        return scene->scene->getMaterialResource(hd::Path(material));
    }
    shading::MaterialProgram compile(const char* material) {
        return shading::MaterialProgram::compile(network(material), cache, &notes);
    }
};

bool anyHas(const std::vector<std::string>& notes, const std::string& text) {
    for (const auto& n : notes)
        if (n.find(text) != std::string::npos) return true;
    return false;
}

}  // namespace

TEST(UsdSceneDelegate, MaterialXSurfaceIsTheTerminalWhenNoUniversalSurface) {
    MaterialXLooks looks;
    hd::MaterialNetwork n = looks.network("/Looks/MxOnly");
    EXPECT_EQ(n.surfaceTerminal, hd::Path("/Looks/MxOnly/SS"));
    ASSERT_EQ(n.nodes.size(), 1u);
    EXPECT_NE(n.nodes[0].where.find("t.usda:"), std::string::npos) << n.nodes[0].where;
    StContext ctx;
    shading::ShadedMaterial m = looks.compile("/Looks/MxOnly").evaluate(ctx);
    EXPECT_NEAR(m.params.baseColor.x, 0.8f, 1e-6f);
    EXPECT_NEAR(m.params.baseColor.y, 0.1f, 1e-6f);
    EXPECT_NEAR(m.params.baseColor.z, 0.1f, 1e-6f);
    EXPECT_FLOAT_EQ(m.params.metallic, 1.0f);
    EXPECT_FLOAT_EQ(m.params.roughness, 0.3f);
    EXPECT_NEAR(m.params.specular, 0.5f, 1e-6f);
    EXPECT_TRUE(looks.notes.empty()) << looks.notes.front();
}

TEST(UsdSceneDelegate, UniversalSurfaceWinsOverMaterialXAndOtherContextsAreIgnored) {
    MaterialXLooks looks;
    hd::MaterialNetwork both = looks.network("/Looks/Both");
    EXPECT_EQ(both.surfaceTerminal, hd::Path("/Looks/Both/Preview"));
    EXPECT_EQ(both.nodes.size(), 1u);  // the mtlx and mdl shaders are not walked
    StContext ctx;
    shading::ShadedMaterial m = looks.compile("/Looks/Both").evaluate(ctx);
    EXPECT_EQ(m.params.baseColor, glm::vec3(1.0f, 0.0f, 0.0f));
    EXPECT_TRUE(looks.network("/Looks/MdlOnly").surfaceTerminal.empty());
}

TEST(UsdSceneDelegate, MaterialXUsdPreviewSurfaceMapsLikeUsdPreviewSurface) {
    MaterialXLooks looks;
    StContext ctx;
    shading::ShadedMaterial m = looks.compile("/Looks/PreviewAsMtlx").evaluate(ctx);
    EXPECT_NEAR(m.params.baseColor.y, 0.7f, 1e-6f);
    EXPECT_FLOAT_EQ(m.params.roughness, 0.4f);
    EXPECT_FLOAT_EQ(m.params.clearcoat, 0.5f);
    EXPECT_NEAR(m.params.specular, 0.5f, 1e-6f);  // UsdPreviewSurface ior fallback 1.5
    EXPECT_TRUE(looks.notes.empty()) << looks.notes.front();
}

TEST(UsdSceneDelegate, MaterialXNodeGraphTexturesAndUnsupportedNodes) {
    MaterialXLooks looks;
    hd::MaterialNetwork n = looks.network("/Looks/Graph");
    const hd::MaterialNode* img = n.node(hd::Path("/Looks/Graph/NG/Img"));
    ASSERT_TRUE(img);
    EXPECT_EQ(hd::getString(img->parameters.at(hd::Token("colorSpace:file"))), "lin_rec709");
    // A file from the graph's interface input brings that input's colour space along.
    const hd::MaterialNode* glow = n.node(hd::Path("/Looks/Graph/NG/GlowImg"));
    ASSERT_TRUE(glow);
    EXPECT_EQ(hd::getString(glow->parameters.at(hd::Token("colorSpace:file"))), "srgb_texture");
    const hd::MaterialNode* ss = n.node(n.surfaceTerminal);
    ASSERT_TRUE(ss);
    EXPECT_FLOAT_EQ(*hd::getFloat(ss->parameters.at(hd::Token("specular_roughness"))), 0.45f);
    auto& c = ss->inputConnections.at(hd::Token("base_color"));
    ASSERT_EQ(c.size(), 1u);
    EXPECT_EQ(c[0].upstreamNode, hd::Path("/Looks/Graph/NG/Img"));  // through the graph output
    EXPECT_EQ(c[0].upstreamOutput, hd::Token("out"));

    shading::MaterialProgram p = looks.compile("/Looks/Graph");
    ASSERT_EQ(p.primvarsRead().size(), 1u);
    EXPECT_EQ(p.primvarsRead()[0], hd::Token("st"));
    StContext ctx;
    ctx.st = {0.25f, 0.5f};  // left texel, read linear (lin_rec709): code 204 -> 0.8
    shading::ShadedMaterial left = p.evaluate(ctx);
    EXPECT_NEAR(left.params.baseColor.x, 0.8f, 1e-6f);
    EXPECT_NEAR(left.params.baseColor.z, 0.0f, 1e-6f);
    ctx.st = {0.75f, 0.5f};
    EXPECT_NEAR(p.evaluate(ctx).params.baseColor.z, 0.8f, 1e-6f);
    EXPECT_FLOAT_EQ(left.params.roughness, 0.45f);  // from the material's interface input
    // emission_color: the same texels decoded from sRGB (0.8 -> 0.6038), times emission 1.
    EXPECT_NEAR(left.emission.x, 0.6038f, 1e-3f);
    EXPECT_NEAR(left.emission.z, 0.0f, 1e-6f);
    // The noise node is not supported: metalness keeps its authored 0.25, with a note that
    // names the node and where it was authored.
    EXPECT_FLOAT_EQ(left.params.metallic, 0.25f);
    EXPECT_TRUE(anyHas(looks.notes,
                       ": /Looks/Graph/NG/Mul: node 'ND_noise2d_float' not supported"));
    ASSERT_FALSE(looks.notes.empty());
    EXPECT_TRUE(anyHas(looks.notes, "t.usda:")) << looks.notes.front();
}

TEST(UsdSceneDelegate, CollectionBindingsReachMeshesAndSubsets) {
    Populated p(R"(#usda 1.0
def Xform "World" (
    prepend apiSchemas = ["MaterialBindingAPI", "CollectionAPI:red"]
)
{
    rel collection:red:includes = [</World/Tri/Part>, </World/Other>]
    rel material:binding:collection:red = [</World.collection:red>, </World/Looks/Red>]
    rel material:binding = </World/Looks/Blue>
    def Mesh "Tri"
    {
        int[] faceVertexCounts = [3, 3]
        int[] faceVertexIndices = [0, 1, 2, 0, 2, 3]
        point3f[] points = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)]
        def GeomSubset "Part"
        {
            uniform token elementType = "face"
            uniform token familyName = "materialBind"
            int[] indices = [1]
        }
    }
    def Mesh "Other"
    {
        int[] faceVertexCounts = [3]
        int[] faceVertexIndices = [0, 1, 2]
        point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
    }
    def Scope "Looks"
    {
        def Material "Red" {}
        def Material "Blue" {}
    }
}
)");
    EXPECT_EQ(p.scene->getMaterialId(hd::Path("/World/Tri")), hd::Path("/World/Looks/Blue"));
    EXPECT_EQ(p.scene->getMaterialId(hd::Path("/World/Other")), hd::Path("/World/Looks/Red"));
    auto subsets = p.scene->getMaterialSubsets(hd::Path("/World/Tri"));
    ASSERT_EQ(subsets.size(), 1u);
    EXPECT_EQ(subsets[0].first, hd::Path("/World/Looks/Red"));
    EXPECT_EQ(subsets[0].second, std::vector<int>{1});
    EXPECT_TRUE(p.scene->warnings().empty());
}

TEST(UsdSceneDelegate, LightAndShadowLinksNameTheirPrimsAsCategories) {
    Populated p(R"(#usda 1.0
def Xform "World"
{
    def SphereLight "Key"
    {
        uniform bool collection:lightLink:includeRoot = 0
        rel collection:lightLink:includes = </World/Hero>
    }
    def SphereLight "Fill" { rel collection:lightLink:excludes = </World/Hero/Face> }
    def SphereLight "Rim" { rel collection:shadowLink:excludes = </World/Hero> }
    def DomeLight_1 "Sky" { rel collection:lightLink:excludes = </World/Prop> }
    def Xform "Hero" { def Sphere "Face" {} def Sphere "Body" {} }
    def Sphere "Prop" {}
}
)");
    using V = std::vector<hd::Token>;
    const hd::Token key("/World/Key.collection:lightLink"), fill("/World/Fill.collection:lightLink"),
        rim("/World/Rim.collection:shadowLink"), sky("/World/Sky.collection:lightLink");
    EXPECT_EQ(p.scene->getCategories(hd::Path("/World/Hero/Face")), (V{key, sky}));
    EXPECT_EQ(p.scene->getCategories(hd::Path("/World/Hero/Body")), (V{fill, key, sky}));
    EXPECT_EQ(p.scene->getCategories(hd::Path("/World/Prop")), (V{fill, rim}));
    EXPECT_EQ(hd::getString(p.scene->getLightParamValue(hd::Path("/World/Key"), hd::Token("lightLink"))), key.str());
    EXPECT_TRUE(hd::isEmpty(p.scene->getLightParamValue(hd::Path("/World/Rim"), hd::Token("lightLink"))));
    EXPECT_EQ(hd::getString(p.scene->getLightParamValue(hd::Path("/World/Rim"), hd::Token("shadowLink"))), rim.str());
    EXPECT_TRUE(hd::isEmpty(p.scene->getLightParamValue(hd::Path("/World/Key"), hd::Token("shadowLink"))));
    EXPECT_TRUE(p.scene->warnings().empty());
}

TEST(UsdSceneDelegate, PlanesAreTwoSidedQuadsByDefault) {
    Populated p(R"(#usda 1.0
def Plane "Ground" { double width = 4  double length = 6  uniform token axis = "Y" }
def Plane "Card" { uniform bool doubleSided = 0 }
)");
    const hd::Value value = p.scene->get(hd::Path("/Ground"), hd::Token("points"));
    const auto* points = hd::getIf<std::vector<glm::vec3>>(value);
    ASSERT_TRUE(points);
    ASSERT_EQ(points->size(), 4u);
    for (const glm::vec3& v : *points) {
        EXPECT_EQ(v.y, 0.0f);
        EXPECT_EQ(std::abs(v.x), 2.0f);
        EXPECT_EQ(std::abs(v.z), 3.0f);
    }
    EXPECT_TRUE(p.scene->getDoubleSided(hd::Path("/Ground")));
    EXPECT_FALSE(p.scene->getDoubleSided(hd::Path("/Card")));
    EXPECT_TRUE(p.scene->warnings().empty());
}

TEST(UsdSceneDelegate, DomeLight1TurnsItsPoleToTheSceneUpAxis) {
    // UsdLuxDomeLight_1 poleAxis: "scene" on a Z-up stage, or "Z", turns the dome +90 degrees
    // about X (its +Y pole to +Z), the dome only; DomeLight and poleAxis "Y" stay as authored.
    auto pole = [](const std::string& upAxis, const std::string& prim) {
        Populated p("#usda 1.0\n(\n    upAxis = \"" + upAxis + "\"\n)\n" + prim);
        const glm::dmat4 m = p.scene->getTransform(hd::Path("/Sky"));
        return glm::dvec3(m * glm::dvec4(0, 1, 0, 0));
    };
    EXPECT_EQ(pole("Z", "def DomeLight_1 \"Sky\" {}"), glm::dvec3(0, 0, 1));
    EXPECT_EQ(pole("Y", "def DomeLight_1 \"Sky\" { uniform token poleAxis = \"Z\" }"), glm::dvec3(0, 0, 1));
    EXPECT_EQ(pole("Z", "def DomeLight_1 \"Sky\" { uniform token poleAxis = \"Y\" }"), glm::dvec3(0, 1, 0));
    EXPECT_EQ(pole("Y", "def DomeLight_1 \"Sky\" {}"), glm::dvec3(0, 1, 0));
    EXPECT_EQ(pole("Z", "def DomeLight \"Sky\" {}"), glm::dvec3(0, 1, 0));
    // Composed with the dome's own transform (the offset applies first, in the dome's frame).
    const std::string turned = R"(def DomeLight_1 "Sky" { uniform token poleAxis = "Z"
    float xformOp:rotateZ = 90
    uniform token[] xformOpOrder = ["xformOp:rotateZ"] })";
    const glm::dvec3 d = pole("Y", turned);
    EXPECT_NEAR(d.x, 0.0, 1e-12);
    EXPECT_NEAR(d.y, 0.0, 1e-12);
    EXPECT_NEAR(d.z, 1.0, 1e-12);
}

TEST(UsdSceneDelegate, UnsupportedPrimTypesAreReportedOncePerType) {
    // 2500 warnings for 2000 NURBS patches and 500 physics prims buried every other warning.
    std::string text = "#usda 1.0\ndef Xform \"W\" {\n";
    for (int i = 0; i < 50; ++i) text += "    def NurbsPatch \"P" + std::to_string(i) + "\" {}\n";
    text += "    def PhysicsScene \"Physics\" {}\n    def PhysicsCollisionGroup \"G\" {}\n"
            "    def SpatialAudio \"Sound\" {}\n    def RenderPass \"Pass\" {}\n"
            "    def Volume \"Smoke\" { def OpenVDBAsset \"density\" {} }\n}\n";
    Populated p(text);
    std::string all;
    size_t nurbs = 0;
    for (const auto& w : p.scene->warnings()) {
        all += w + "\n";
        nurbs += w.find("'NurbsPatch'") != std::string::npos;
    }
    EXPECT_EQ(nurbs, 1u) << all;
    EXPECT_NE(all.find("t.usda:3:5: /W/P0"), std::string::npos) << all;  // the first one's location
    EXPECT_NE(all.find("'Volume'"), std::string::npos) << all;
    for (const char* quiet : {"Physics", "SpatialAudio", "RenderPass", "OpenVDBAsset"})
        EXPECT_EQ(all.find(quiet), std::string::npos) << quiet << "\n" << all;
}
