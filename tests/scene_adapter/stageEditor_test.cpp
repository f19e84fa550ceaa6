// SPDX-License-Identifier: Apache-2.0
// Host edits (scene_adapter/stageEditor.h): each edit marks exactly the dirty bits it implies
// on exactly the prims it affects (read from the change tracker before sync and from
// RenderIndex::lastSync() after), and the rendered AOVs show the edit.
#include "scene_adapter/stageEditor.h"

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "delegate/hd/renderIndex.h"
#include "delegate/hd/tokens.h"
#include "delegate/renderBuffer.h"
#include "delegate/renderDelegate.h"
#include "plugins/renderSession.h"
#include "scene_adapter/usdSceneDelegate.h"
#include "scene_adapter/usda/stage.h"

using namespace principled;
using adapter::EditError;
using adapter::EditValue;
namespace D = hd::RprimDirty;
namespace S = hd::SprimDirty;

namespace {

// Camera at z=10 looking down -Z (horizontal field of view 60 degrees: +-5.8 units at z=0);
// a distant light along -Z; two quads under /World/Group, a sphere, a point instancer.
const char* kScene = R"(#usda 1.0
(
    upAxis = "Y"
)
def Xform "World"
{
    def Camera "Cam"
    {
        float focalLength = 18.15
        float horizontalAperture = 20.955
        float verticalAperture = 15.2908
        double3 xformOp:translate = (0, 0, 10)
        uniform token[] xformOpOrder = ["xformOp:translate"]
    }
    def DistantLight "Sun"
    {
        float inputs:intensity = 3
        float inputs:angle = 0
    }
    def Xform "Group"
    {
        def Mesh "Left"
        {
            uniform token subdivisionScheme = "none"
            int[] faceVertexCounts = [4]
            int[] faceVertexIndices = [0, 1, 2, 3]
            point3f[] points = [(-3, -1, 0), (-1, -1, 0), (-1, 1, 0), (-3, 1, 0)]
            rel material:binding = </World/Looks/Red>
        }
        def Mesh "Right"
        {
            uniform token subdivisionScheme = "none"
            int[] faceVertexCounts = [4]
            int[] faceVertexIndices = [0, 1, 2, 3]
            point3f[] points = [(1, -1, 0), (3, -1, 0), (3, 1, 0), (1, 1, 0)]
            rel material:binding = </World/Looks/Blue>
            def GeomSubset "Half"
            {
                uniform token elementType = "face"
                uniform token familyName = "materialBind"
                int[] indices = []
            }
        }
    }
    def Sphere "Ball"
    {
        double radius = 0.5
        double3 xformOp:translate = (0, 2.5, 0)
        uniform token[] xformOpOrder = ["xformOp:translate"]
    }
    def PointInstancer "Inst"
    {
        rel prototypes = [</World/Inst/Protos/Box>]
        point3f[] positions = [(-2, -3, 0), (2, -3, 0)]
        int[] protoIndices = [0, 0]
        def Scope "Protos"
        {
            def Cube "Box"
            {
                double size = 0.8
            }
        }
    }
    def Scope "Looks"
    {
        def Material "Red"
        {
            token outputs:surface.connect = </World/Looks/Red/Surface.outputs:surface>
            def Shader "Surface"
            {
                uniform token info:id = "UsdPreviewSurface"
                color3f inputs:diffuseColor = (0.8, 0.05, 0.05)
                token outputs:surface
            }
        }
        def Material "Blue"
        {
            token outputs:surface.connect = </World/Looks/Blue/Surface.outputs:surface>
            def Shader "Surface"
            {
                uniform token info:id = "UsdPreviewSurface"
                color3f inputs:diffuseColor = (0.05, 0.05, 0.8)
                token outputs:surface
            }
        }
    }
}
)";

using Dirty = std::map<std::string, hd::DirtyBits>;

struct Fixture {
    std::unique_ptr<host::RenderSession> s;
    Fixture() {
        host::SessionOptions o;
        o.width = 48;
        o.height = 36;
        o.samplesPerPixel = 2;
        o.aovs = {"primId"};
        s = host::RenderSession::openString(kScene, "edits.usda", o);
        render();
    }
    adapter::StageEditor& edit() { return s->editor(); }
    hd::RenderIndex& index() { return *s->index(); }
    Dirty dirty(hd::ChangeTracker::Kind kind) {
        Dirty out;
        for (const hd::Path& id : index().changeTracker().dirtyIds(kind))
            out[id.str()] = index().changeTracker().dirtyBits(kind, id);
        return out;
    }
    Dirty rprims() { return dirty(hd::ChangeTracker::Kind::Rprim); }
    Dirty sprims() { return dirty(hd::ChangeTracker::Kind::Sprim); }
    void render() {
        while (!s->step()) {
        }
    }
    double stat(const char* k) { return s->stats()[k]; }
    int primIdOf(const char* path) {
        hd::Rprim* r = index().rprim(hd::Path(path));
        return r ? r->primId() : -1;
    }
    /// Pixels per primId in the primId AOV.
    std::map<int, int> coverage() {
        auto* ids = static_cast<const int*>(s->buffer("primId")->map());
        std::map<int, int> out;
        for (int i = 0; i < s->width() * s->height(); ++i) out[ids[i]]++;
        return out;
    }
    /// Mean colour over the pixels of one prim.
    glm::vec3 colorOf(const char* path) {
        int id = primIdOf(path);
        auto* ids = static_cast<const int*>(s->buffer("primId")->map());
        const float* c = s->color();
        glm::vec3 sum(0.0f);
        int n = 0;
        for (int i = 0; i < s->width() * s->height(); ++i)
            if (ids[i] == id) sum += glm::vec3(c[4 * i], c[4 * i + 1], c[4 * i + 2]), ++n;
        return n ? sum / float(n) : glm::vec3(-1.0f);
    }
    /// Centroid column of one prim's pixels.
    double column(const char* path) {
        int id = primIdOf(path);
        auto* ids = static_cast<const int*>(s->buffer("primId")->map());
        double sum = 0;
        int n = 0;
        for (int i = 0; i < s->width() * s->height(); ++i)
            if (ids[i] == id) sum += i % s->width(), ++n;
        return n ? sum / n : -1.0;
    }
    std::vector<std::pair<std::string, hd::DirtyBits>> syncedRprims() {
        std::vector<std::pair<std::string, hd::DirtyBits>> out;
        for (const auto& [id, bits] : index().lastSync().rprims) out.emplace_back(id.str(), bits);
        return out;
    }
};

const hd::Path kLeft("/World/Group/Left"), kRight("/World/Group/Right");

TEST(StageEditor, PointsEditMarksPointsOnlyOnThatMesh) {
    Fixture f;
    int before = f.coverage()[f.primIdOf("/World/Group/Left")];
    double blas = f.stat("blasBuilds");
    f.edit().setAttribute("/World/Group/Left", "points",
                          EditValue::of({-3, -1, 0, -2, -1, 0, -2, 0, 0, -3, 0, 0}));
    EXPECT_EQ(f.rprims(), (Dirty{{"/World/Group/Left", D::Points}}));
    EXPECT_TRUE(f.sprims().empty());
    f.index().sync();
    EXPECT_EQ(
        f.syncedRprims(),
        (std::vector<std::pair<std::string, hd::DirtyBits>>{{"/World/Group/Left", D::Points}}));
    EXPECT_TRUE(f.index().lastSync().sprims.empty());
    f.render();
    EXPECT_EQ(f.stat("blasBuilds"), blas + 1);
    int after = f.coverage()[f.primIdOf("/World/Group/Left")];
    EXPECT_GT(before, 0);
    EXPECT_NEAR(double(after) / before, 0.25, 0.12);  // a quarter of the area
}

TEST(StageEditor, MaterialInputMarksOnlyThatMaterialAndRebuildsNoRprim) {
    Fixture f;
    glm::vec3 c0 = f.colorOf("/World/Group/Right");
    EXPECT_GT(c0.z, c0.y);
    double blas = f.stat("blasBuilds");
    f.edit().setAttribute("/World/Looks/Blue/Surface", "inputs:diffuseColor",
                          EditValue::of({0.05, 0.8, 0.05}));
    EXPECT_TRUE(f.rprims().empty());
    EXPECT_EQ(f.sprims(), (Dirty{{"/World/Looks/Blue", S::MaterialParams}}));
    f.index().sync();
    EXPECT_TRUE(f.index().lastSync().rprims.empty());
    ASSERT_EQ(f.index().lastSync().sprims.size(), 1u);
    f.render();
    EXPECT_EQ(f.stat("blasBuilds"), blas);
    glm::vec3 c1 = f.colorOf("/World/Group/Right");
    EXPECT_GT(c1.y, 2.0f * c1.z);
}

TEST(StageEditor, XformTransformMarksTransformOnDescendantsOnly) {
    Fixture f;
    double col0 = f.column("/World/Group/Left");
    double blas = f.stat("blasBuilds");
    const double m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1.5, 0, 0, 1};
    f.edit().setTransform("/World/Group", m);
    EXPECT_EQ(f.rprims(),
              (Dirty{{"/World/Group/Left", D::Transform}, {"/World/Group/Right", D::Transform}}));
    EXPECT_TRUE(f.sprims().empty());
    f.render();
    EXPECT_EQ(f.stat("blasBuilds"), blas);  // instances move; no BVH is rebuilt
    EXPECT_NEAR(f.column("/World/Group/Left") - col0, 1.5 / 11.6 * 48, 1.5);
}

TEST(StageEditor, CameraAndLightEditsMarkTheirSprim) {
    Fixture f;
    f.edit().setAttribute("/World/Sun", "inputs:intensity", EditValue::of({6}));
    f.edit().setAttribute("/World/Cam", "focalLength", EditValue::of({30}));
    EXPECT_EQ(f.sprims(), (Dirty{{"/World/Cam", S::Params}, {"/World/Sun", S::Params}}));
    EXPECT_TRUE(f.rprims().empty());
    const double m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 12, 1};
    f.edit().setTransform("/World/Cam", m);
    EXPECT_EQ(f.sprims()["/World/Cam"], S::Params | S::Transform);
}

TEST(StageEditor, BindingMarksMaterialIdOnThatRprimAndChangesItsColour) {
    Fixture f;
    f.edit().bindMaterial("/World/Group/Right", "/World/Looks/Red");
    EXPECT_EQ(f.rprims(), (Dirty{{"/World/Group/Right", D::MaterialId}}));
    EXPECT_TRUE(f.sprims().empty());
    f.render();
    glm::vec3 c = f.colorOf("/World/Group/Right");
    EXPECT_GT(c.x, 4.0f * c.z);
    // Binding an ancestor reaches only rprims whose resolved material changes (Left: none).
    f.edit().bindMaterial("/World/Group", "/World/Looks/Blue");
    EXPECT_TRUE(f.rprims().empty());
}

TEST(StageEditor, GeomSubsetBindingMarksItsMesh) {
    Fixture f;
    f.edit().setAttribute("/World/Group/Right/Half", "indices", EditValue::of({0}));
    EXPECT_EQ(f.rprims(), (Dirty{{"/World/Group/Right", D::MaterialId}}));
    f.edit().bindMaterial("/World/Group/Right/Half", "/World/Looks/Red");
    EXPECT_EQ(f.rprims(), (Dirty{{"/World/Group/Right", D::MaterialId}}));
    f.render();
    glm::vec3 c = f.colorOf("/World/Group/Right");
    EXPECT_GT(c.x, 4.0f * c.z);
}

TEST(StageEditor, TopologyEditMarksTopologyOnly) {
    Fixture f;
    f.edit().setAttribute("/World/Group/Left", "faceVertexCounts", EditValue::of({3}));
    f.edit().setAttribute("/World/Group/Left", "faceVertexIndices", EditValue::of({0, 1, 2}));
    EXPECT_EQ(f.rprims(), (Dirty{{"/World/Group/Left", D::Topology}}));
    int before = f.coverage()[f.primIdOf("/World/Group/Left")];
    f.render();
    EXPECT_NEAR(double(f.coverage()[f.primIdOf("/World/Group/Left")]) / before, 0.5, 0.15);
    // Fewer points than the topology needs: the mesh warns and skips bad faces, no crash.
    f.edit().setAttribute("/World/Group/Left", "points", EditValue::of({0, 0, 0}));
    EXPECT_EQ(f.rprims(), (Dirty{{"/World/Group/Left", D::Points}}));
    f.render();
    EXPECT_EQ(f.coverage().count(f.primIdOf("/World/Group/Left")), 0u);
}

TEST(StageEditor, VisibilityAndPurpose) {
    Fixture f;
    f.edit().setAttribute("/World/Group", "visibility", EditValue::text("invisible"));
    EXPECT_EQ(f.rprims(),
              (Dirty{{"/World/Group/Left", D::Visibility}, {"/World/Group/Right", D::Visibility}}));
    f.render();
    EXPECT_EQ(f.coverage().count(f.primIdOf("/World/Group/Left")), 0u);
    EXPECT_EQ(f.coverage().count(f.primIdOf("/World/Group/Right")), 0u);
    // purpose = guide takes the prim out of the index; default brings it back.
    size_t n = f.index().rprimCount();
    f.edit().setAttribute("/World/Ball", "purpose", EditValue::text("guide"));
    EXPECT_EQ(f.index().rprimCount(), n - 1);
    f.edit().setAttribute("/World/Ball", "purpose", EditValue::text("default"));
    EXPECT_EQ(f.index().rprimCount(), n);
}

TEST(StageEditor, RemovePrimDropsItsPrimIdAndDirtiesNothingElse) {
    Fixture f;
    int ball = f.primIdOf("/World/Ball");
    ASSERT_GT(f.coverage()[ball], 0);
    f.edit().removePrim("/World/Ball");
    EXPECT_EQ(f.index().rprim(hd::Path("/World/Ball")), nullptr);
    EXPECT_TRUE(f.rprims().empty());
    EXPECT_TRUE(f.sprims().empty());
    f.render();
    EXPECT_EQ(f.coverage().count(ball), 0u);
    EXPECT_THROW(f.edit().setAttribute("/World/Ball", "radius", EditValue::of({1})), EditError);
}

TEST(StageEditor, RemovingAMaterialFallsBackToTheDefaultMaterial) {
    Fixture f;
    f.edit().removePrim("/World/Looks/Blue");
    EXPECT_EQ(f.index().sprim(hd::tokens::material(), hd::Path("/World/Looks/Blue")), nullptr);
    EXPECT_EQ(f.rprims(), (Dirty{{"/World/Group/Right", D::MaterialId}}));
    f.render();
    glm::vec3 c = f.colorOf("/World/Group/Right");
    EXPECT_NEAR(c.x, c.z, 0.1f * (c.x + c.z) + 1e-3f);  // grey, no longer blue
}

TEST(StageEditor, RemovingAPrototypeKeepsTheInstancerSafe) {
    Fixture f;
    ASSERT_NE(f.index().rprim(hd::Path("/World/Inst/Protos/Box")), nullptr);
    f.edit().removePrim("/World/Inst/Protos/Box");
    EXPECT_EQ(f.index().rprim(hd::Path("/World/Inst/Protos/Box")), nullptr);
    f.render();  // no crash; the instancer warns that its prototype is gone
    bool warned = false;
    for (const auto& w : f.s->takeWarnings()) warned |= w.find("Protos/Box") != std::string::npos;
    EXPECT_TRUE(warned);
}

TEST(StageEditor, InstancerArraysMarkItsPrototypes) {
    Fixture f;
    f.edit().setAttribute("/World/Inst", "positions", EditValue::of({-2, -3, 0}));
    f.edit().setAttribute("/World/Inst", "protoIndices", EditValue::of({0}));
    EXPECT_EQ(f.rprims(), (Dirty{{"/World/Inst/Protos/Box", D::Instancer | D::InstanceIndex}}));
    f.render();
    EXPECT_EQ(f.stat("instances"), 1.0);
}

TEST(StageEditor, AddMeshMaterialLightAndCamera) {
    Fixture f;
    auto& e = f.edit();
    e.addPrim("/World/Looks/Green", "Material");
    e.addPrim("/World/Looks/Green/Surface", "Shader");
    e.setAttribute("/World/Looks/Green/Surface", "info:id", EditValue::text("UsdPreviewSurface"));
    e.setAttribute("/World/Looks/Green/Surface", "inputs:diffuseColor",
                   EditValue::of({0.05, 0.8, 0.05}));
    e.connect("/World/Looks/Green", "outputs:surface",
              "/World/Looks/Green/Surface.outputs:surface");
    e.addPrim("/World/New", "Mesh");
    e.setAttribute("/World/New", "points",
                   EditValue::of({-1, -2, 1, 1, -2, 1, 1, -1, 1, -1, -1, 1}));
    e.setAttribute("/World/New", "faceVertexCounts", EditValue::of({4}));
    e.setAttribute("/World/New", "faceVertexIndices", EditValue::of({0, 1, 2, 3}));
    e.setAttribute("/World/New", "subdivisionScheme", EditValue::text("none"));
    e.bindMaterial("/World/New", "/World/Looks/Green");
    e.addPrim("/World/Lamp", "SphereLight");
    e.setAttribute("/World/Lamp", "inputs:intensity", EditValue::of({2}));
    e.addPrim("/World/Cam2", "Camera");
    EXPECT_NE(f.index().rprim(hd::Path("/World/New")), nullptr);
    EXPECT_NE(f.index().sprim(hd::tokens::sphereLight(), hd::Path("/World/Lamp")), nullptr);
    EXPECT_EQ(f.s->cameras().size(), 2u);
    // Only the new prims are dirty; nothing that existed is re-synced.
    for (const auto& [id, bits] : f.rprims()) EXPECT_EQ(id, "/World/New");
    for (const auto& [id, bits] : f.sprims())
        EXPECT_TRUE(id == "/World/Looks/Green" || id == "/World/Lamp" || id == "/World/Cam2") << id;
    f.render();
    EXPECT_GT(f.coverage()[f.primIdOf("/World/New")], 0);
    glm::vec3 c = f.colorOf("/World/New");
    EXPECT_GT(c.y, 4.0f * c.z);
    // An implicit shape: its size regenerates the mesh (points and normals, not topology).
    e.addPrim("/World/Box", "Cube");
    f.render();
    e.setAttribute("/World/Box", "size", EditValue::of({0.5}));
    EXPECT_EQ(f.rprims(), (Dirty{{"/World/Box", D::Points | D::Normals}}));
}

TEST(StageEditor, BadEditsThrowNamingThePrimAndChangeNothing) {
    Fixture f;
    auto expectError = [&](auto&& edit, EditError::Code code, const std::string& needle) {
        try {
            edit();
            ADD_FAILURE() << "no error; expected one mentioning " << needle;
        } catch (const EditError& e) {
            EXPECT_EQ(e.code, code) << e.what();
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
        EXPECT_TRUE(f.rprims().empty());
        EXPECT_TRUE(f.sprims().empty());
    };
    auto& e = f.edit();
    expectError(
        [&] {
            e.setAttribute("/World/Nope", "points", EditValue::of({0, 0, 0}));
        },
        EditError::Code::NotFound, "/World/Nope");
    expectError([&] { e.setAttribute("/World/Group/Left", "points", EditValue::text("x")); },
                EditError::Code::BadValue, "point3f[]");
    expectError(
        [&] {
            e.setAttribute("/World/Group/Left", "points", EditValue::of({1, 2}));
        },
        EditError::Code::BadValue, "/World/Group/Left.points");
    expectError(
        [&] {
            e.setAttribute("/World/Looks/Red/Surface", "inputs:diffuseColor",
                           EditValue::of({1, 0}));
        },
        EditError::Code::BadValue, "color3f");
    expectError(
        [&] { e.setAttribute("/World/Group/Left", "faceVertexCounts", EditValue::of({3.5})); },
        EditError::Code::BadValue, "int[]");
    expectError(
        [&] { e.setAttribute("/World/Group/Left", "visibility", EditValue::text("hidden")); },
        EditError::Code::BadValue, "invisible");
    expectError([&] { e.setAttribute("/World/Group/Left", "madeUp", EditValue::of({1})); },
                EditError::Code::NotFound, "madeUp");
    expectError([&] { e.bindMaterial("/World/Group/Left", "/World/Group/Right"); },
                EditError::Code::BadValue, "expected a Material");
    expectError([&] { e.addPrim("/World/Thing", "Teapot"); }, EditError::Code::Unsupported,
                "Teapot");
    expectError([&] { e.addPrim("/Missing/Child", "Mesh"); }, EditError::Code::NotFound,
                "/Missing");
    expectError([&] { e.addPrim("/World/Group", "Xform"); }, EditError::Code::BadValue,
                "already exists");
    expectError([&] { e.removePrim("/World/Nope"); }, EditError::Code::NotFound, "/World/Nope");
    const double nan[16] = {std::nan(""), 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    expectError([&] { e.setTransform("/World/Group", nan); }, EditError::Code::BadValue, "finite");
    // The values stayed as they were.
    hd::Value pts = f.s->sceneDelegate().get(kLeft, hd::tokens::points());
    ASSERT_TRUE(hd::getIf<std::vector<glm::vec3>>(pts));
    EXPECT_EQ(hd::getIf<std::vector<glm::vec3>>(pts)->size(), 4u);
}

TEST(StageEditor, AnEditWinsOverTimeSamplesAtEveryTime) {
    const char* text = R"(#usda 1.0
(
    startTimeCode = 1
    endTimeCode = 2
)
def Sphere "S"
{
    double radius.timeSamples = { 1: 1, 2: 2 }
}
)";
    host::SessionOptions o;
    o.width = 8;
    o.height = 8;
    o.samplesPerPixel = 1;
    o.time = 2;
    auto s = host::RenderSession::openString(text, "t.usda", o);
    s->editor().setAttribute("/S", "radius", EditValue::of({3}));
    auto r = hd::getFloat(s->sceneDelegate().get(hd::Path("/S"), hd::tokens::radius()));
    ASSERT_TRUE(r);
    EXPECT_EQ(*r, 3.0f);
    EXPECT_EQ(s->stage().prim("/S")->attribute("radius")->typeName(), "double");
}

}  // namespace

namespace {

TEST(StageEditor, EditsReachingInstancesRePopulateTheGroups) {
    const char* text = R"(#usda 1.0
def Xform "Proto" (
    active = false
)
{
    def Mesh "Quad"
    {
        uniform token subdivisionScheme = "none"
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)]
    }
}
def Xform "World"
{
    def Xform "I0" (instanceable = true
        references = </Proto>
        active = true)
    {
        double3 xformOp:translate = (-2, 0, 0)
        uniform token[] xformOpOrder = ["xformOp:translate"]
    }
    def Xform "I1" (instanceable = true
        references = </Proto>
        active = true)
    {
        double3 xformOp:translate = (2, 0, 0)
        uniform token[] xformOpOrder = ["xformOp:translate"]
    }
}
)";
    host::SessionOptions o;
    o.width = 16;
    o.height = 16;
    o.samplesPerPixel = 1;
    auto s = host::RenderSession::openString(text, "inst.usda", o);
    while (!s->step()) {
    }
    double instances = s->stats()["instances"];
    EXPECT_EQ(instances, 2.0);
    // An instance proxy is read-only; the instance itself can move or go.
    EXPECT_THROW(s->editor().setAttribute("/World/I0/Quad", "points", EditValue::of({0, 0, 0})),
                 EditError);
    const double m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 3, 0, 1};
    s->editor().setTransform("/World/I1", m);
    while (!s->step()) {
    }
    EXPECT_EQ(s->stats()["instances"], 2.0);
    s->editor().removePrim("/World/I0");
    while (!s->step()) {
    }
    EXPECT_EQ(s->stats()["instances"], 1.0);
}

}  // namespace

namespace {

TEST(StageEditor, AddAPointInstancerWithItsPrototype) {
    Fixture f;
    auto& e = f.edit();
    double before = f.stat("instances");
    e.addPrim("/World/Inst2", "PointInstancer");
    e.addPrim("/World/Inst2/Proto", "Sphere");
    e.setAttribute("/World/Inst2/Proto", "radius", EditValue::of({0.3}));
    e.setAttribute("/World/Inst2", "positions", EditValue::of({-4, 2.5, 0, 4, 2.5, 0, 0, -1, 1}));
    e.setAttribute("/World/Inst2", "protoIndices", EditValue::of({0, 0, 0}));
    e.setRelationship("/World/Inst2", "prototypes", {"/World/Inst2/Proto"});
    ASSERT_NE(f.index().rprim(hd::Path("/World/Inst2/Proto")), nullptr);
    f.render();
    EXPECT_EQ(f.stat("instances"), before + 3);
    EXPECT_GT(f.coverage()[f.primIdOf("/World/Inst2/Proto")], 0);
    // One instance hidden: InstanceIndex on the prototype only.
    e.setAttribute("/World/Inst2", "invisibleIds", EditValue::of({2}));
    EXPECT_EQ(f.rprims(), (Dirty{{"/World/Inst2/Proto", D::InstanceIndex}}));
    f.render();
    EXPECT_EQ(f.stat("instances"), before + 2);
}

}  // namespace

TEST(StageEditor, CollectionBindingEditsReSplitTheMeshesTheyReach) {
    Fixture f;
    f.edit().setAttribute("/World/Group/Right/Half", "indices", EditValue::of({0}));
    // A collection on the mesh holding its subset, bound to red: on the mesh's own prim a
    // collection binding beats the direct one (blue), so the subset's faces turn red.
    f.edit().setRelationship("/World/Group/Right", "collection:warm:includes", {"/World/Group/Right/Half"});
    f.edit().setRelationship("/World/Group/Right", "material:binding:collection:warm",
                             {"/World/Group/Right.collection:warm", "/World/Looks/Red"});
    EXPECT_EQ(f.rprims(), (Dirty{{"/World/Group/Right", D::MaterialId}}));
    f.render();
    glm::vec3 c = f.colorOf("/World/Group/Right");
    EXPECT_GT(c.x, 4.0f * c.z);
    // Excluding it again restores the mesh's blue.
    f.edit().setRelationship("/World/Group/Right", "collection:warm:excludes", {"/World/Group/Right/Half"});
    EXPECT_EQ(f.rprims(), (Dirty{{"/World/Group/Right", D::MaterialId}}));
    f.render();
    c = f.colorOf("/World/Group/Right");
    EXPECT_GT(c.z, 4.0f * c.x);
    // The same collection bound on the group, above the mesh's direct binding, is weaker.
    f.edit().setRelationship("/World/Group/Right", "collection:warm:excludes", {});
    f.edit().setRelationship("/World/Group/Right", "material:binding:collection:warm", {});
    f.edit().setRelationship("/World/Group", "material:binding:collection:warm",
                             {"/World/Group/Right.collection:warm", "/World/Looks/Red"});
    f.render();
    c = f.colorOf("/World/Group/Right");
    EXPECT_GT(c.z, 4.0f * c.x);
    // A binding that is not a collection and a Material is refused.
    EXPECT_THROW(f.edit().setRelationship("/World/Group", "material:binding:collection:bad", {"/World/Looks/Red"}),
                 EditError);
}

TEST(StageEditor, LightLinkEditsRelightThePrimsTheyReach) {
    Fixture f;
    const glm::vec3 before = f.colorOf("/World/Group/Right");
    f.edit().setRelationship("/World/Sun", "collection:lightLink:excludes", {"/World/Group/Right"});
    EXPECT_EQ(f.rprims().count("/World/Group/Right"), 1u);
    f.render();
    const glm::vec3 unlit = f.colorOf("/World/Group/Right");
    EXPECT_LT(unlit.z, 0.1f * before.z);  // only light bounced off the other prims is left
    EXPECT_GT(f.colorOf("/World/Group/Left").x, 0.5f * before.z);  // the other quad still lit
    f.edit().setRelationship("/World/Sun", "collection:lightLink:excludes", {});
    f.render();
    EXPECT_NEAR(f.colorOf("/World/Group/Right").z, before.z, 0.02f * before.z);
}

TEST(StageEditor, SubsetsFollowCollectionEditsAfterTheirOwnEdits) {
    // A subset edit records what the subset resolves to, so a later collection edit that brings
    // it back to an earlier material is still seen.
    Fixture f;
    f.edit().setAttribute("/World/Group/Right/Half", "indices", EditValue::of({0}));
    f.edit().bindMaterial("/World/Group/Right/Half", "/World/Looks/Red");
    f.render();
    EXPECT_GT(f.colorOf("/World/Group/Right").x, 4.0f * f.colorOf("/World/Group/Right").z);
    // On the subset itself a collection binding beats its direct one; its collection is empty yet.
    f.edit().setRelationship("/World/Group/Right/Half", "material:binding:collection:x",
                             {"/World/Group.collection:x", "/World/Looks/Blue"});
    f.render();
    f.edit().setRelationship("/World/Group", "collection:x:includes", {"/World/Group/Right/Half"});
    EXPECT_EQ(f.rprims().count("/World/Group/Right"), 1u);
    f.render();
    const glm::vec3 c = f.colorOf("/World/Group/Right");
    EXPECT_GT(c.z, 4.0f * c.x);
}

TEST(StageEditor, RemovingWhatACollectionBindingNeedsReResolves) {
    {
        // The prim holding the collection goes: the mesh falls back to its direct binding.
        Fixture f;
        f.edit().setRelationship("/World/Ball", "collection:c:includes", {"/World/Group/Left"});
        f.edit().setRelationship("/World/Group/Left", "material:binding:collection:c",
                                 {"/World/Ball.collection:c", "/World/Looks/Blue"});
        f.render();
        EXPECT_GT(f.colorOf("/World/Group/Left").z, 4.0f * f.colorOf("/World/Group/Left").x);
        f.edit().removePrim("/World/Ball");
        f.render();
        EXPECT_GT(f.colorOf("/World/Group/Left").x, 4.0f * f.colorOf("/World/Group/Left").z);
    }
    {
        // The Material a subset reaches through a collection goes: the subset takes the mesh's.
        Fixture f;
        f.edit().setAttribute("/World/Group/Right/Half", "indices", EditValue::of({0}));
        f.edit().setRelationship("/World/Group/Right", "collection:warm:includes", {"/World/Group/Right/Half"});
        f.edit().setRelationship("/World/Group/Right", "material:binding:collection:warm",
                                 {"/World/Group/Right.collection:warm", "/World/Looks/Red"});
        f.render();
        EXPECT_GT(f.colorOf("/World/Group/Right").x, 4.0f * f.colorOf("/World/Group/Right").z);
        f.edit().removePrim("/World/Looks/Red");
        f.render();
        EXPECT_GT(f.colorOf("/World/Group/Right").z, 4.0f * f.colorOf("/World/Group/Right").x);
    }
}

TEST(StageEditor, RemovingTheHolderOfANestedLightLinkCollectionUnlinks) {
    // The sun lights what /World/Ball's collection c holds (the right quad); removing the Ball
    // removes c, so the sun lights nothing (as a stage authored that way from the start).
    Fixture f;
    f.edit().setRelationship("/World/Ball", "collection:c:includes", {"/World/Group/Right"});
    f.edit().setAttribute("/World/Sun", "collection:lightLink:includeRoot", EditValue::of({0}), "bool");
    f.edit().setRelationship("/World/Sun", "collection:lightLink:includes", {"/World/Ball.collection:c"});
    f.render();
    const float linked = f.colorOf("/World/Group/Right").z;
    EXPECT_GT(linked, 0.1f);
    f.edit().removePrim("/World/Ball");
    f.render();
    EXPECT_LT(f.colorOf("/World/Group/Right").z, 0.05f * linked);
}
