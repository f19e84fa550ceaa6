// SPDX-License-Identifier: Apache-2.0
// UsdSkel linear blend skinning against hand-computed poses.
#include "scene_adapter/skinning.h"

#include <gtest/gtest.h>

#include <chrono>
#include <string>

#include "delegate/hd/tokens.h"
#include "delegate/renderDelegate.h"
#include "scene_adapter/stageEditor.h"
#include "scene_adapter/usdSceneDelegate.h"
#include "scene_adapter/usda/stage.h"

using namespace principled;

namespace {

// A two-joint arm along +x: "arm" at the origin, "arm/hand" at x = 1 (bind and rest alike).
// The SkelRoot sits at y = 10, the mesh's own transform (x = 100) must be ignored. Points:
// p0 (0.5, 0, 0) on the arm only, p1 (1.5, 0, 0) on the hand only, p2 (1.5, 1, 0) half and half.
// The animation turns the hand 90 degrees about z (quaternion (cos 45, 0, 0, sin 45)).
std::string scene(const std::string& extra, const std::string& animation) {
    return R"(#usda 1.0
def SkelRoot "Rig" (
    prepend apiSchemas = ["SkelBindingAPI"]
)
{
    double3 xformOp:translate = (0, 10, 0)
    uniform token[] xformOpOrder = ["xformOp:translate"]
    rel skel:skeleton = </Rig/Skel>
    def Skeleton "Skel" (
        prepend apiSchemas = ["SkelBindingAPI"]
    )
    {
        uniform token[] joints = ["arm", "arm/hand"]
        uniform matrix4d[] bindTransforms = [((1,0,0,0),(0,1,0,0),(0,0,1,0),(0,0,0,1)), ((1,0,0,0),(0,1,0,0),(0,0,1,0),(1,0,0,1))]
        uniform matrix4d[] restTransforms = [((1,0,0,0),(0,1,0,0),(0,0,1,0),(0,0,0,1)), ((1,0,0,0),(0,1,0,0),(0,0,1,0),(1,0,0,1))]
)" + animation + R"(
    }
    def SkelAnimation "Anim"
    {
        uniform token[] joints = ["arm/hand"]
        float3[] translations = [(1, 0, 0)]
        quatf[] rotations = [(0.70710678, 0, 0, 0.70710678)]
        half3[] scales = [(1, 1, 1)]
    }
    def Mesh "Arm" (
        prepend apiSchemas = ["SkelBindingAPI"]
    )
    {
        double3 xformOp:translate = (100, 0, 0)
        uniform token[] xformOpOrder = ["xformOp:translate"]
        int[] faceVertexCounts = [3]
        int[] faceVertexIndices = [0, 1, 2]
        point3f[] points = [(0.5, 0, 0), (1.5, 0, 0), (1.5, 1, 0)]
        normal3f[] normals = [(0, 1, 0), (0, 1, 0), (0, 1, 0)] (interpolation = "vertex")
)" + extra + R"(
    }
}
)";
}

const char* kInfluences = R"(
        int[] primvars:skel:jointIndices = [0, 0, 1, 0, 0, 1] (interpolation = "vertex" elementSize = 2)
        float[] primvars:skel:jointWeights = [1, 0, 1, 0, 0.5, 0.5] (interpolation = "vertex" elementSize = 2)
)";
const char* kAnimated = R"(        rel skel:animationSource = </Rig/Anim>)";

struct Posed {
    std::unique_ptr<usd::Stage> stage;
    embree::EmbreeRenderDelegate renderDelegate;
    hd::RenderIndex index{&renderDelegate};
    std::unique_ptr<adapter::UsdSceneDelegate> scene;
    explicit Posed(const std::string& text) {
        stage = usd::Stage::openString(text, "skel.usda");
        scene = std::make_unique<adapter::UsdSceneDelegate>(*stage);
        scene->populate(&index);
    }
    std::vector<glm::vec3> get(const char* key) const {
        hd::Value v = scene->get(hd::Path("/Rig/Arm"), hd::Token(key));
        const auto* p = hd::getIf<std::vector<glm::vec3>>(v);
        return p ? *p : std::vector<glm::vec3>();
    }
    bool warned(const std::string& what) const {
        for (const auto& w : scene->warnings())
            if (w.find(what) != std::string::npos) return true;
        return false;
    }
};

void expectNear(const glm::vec3& a, const glm::vec3& b) {
    EXPECT_NEAR(a.x, b.x, 1e-5f);
    EXPECT_NEAR(a.y, b.y, 1e-5f);
    EXPECT_NEAR(a.z, b.z, 1e-5f);
}

}  // namespace

TEST(Skinning, TheRestPoseIsTheBindPoseInTheSkeletonsSpace) {
    Posed s(scene(kInfluences, ""));
    const auto p = s.get("points");
    ASSERT_EQ(p.size(), 3u);
    expectNear(p[0], {0.5f, 0, 0});
    expectNear(p[1], {1.5f, 0, 0});
    expectNear(p[2], {1.5f, 1, 0});
    // The skeleton's world transform (the SkelRoot's y = 10), not the mesh's own x = 100.
    const glm::dmat4 w = s.scene->getTransform(hd::Path("/Rig/Arm"));
    EXPECT_DOUBLE_EQ(w[3][0], 0.0);
    EXPECT_DOUBLE_EQ(w[3][1], 10.0);
}

TEST(Skinning, TheAnimationTurnsTheHandAndBlendsTheSharedPoint) {
    Posed s(scene(kInfluences, kAnimated));
    const auto p = s.get("points");
    ASSERT_EQ(p.size(), 3u);
    // Hand turned 90 degrees about z around (1, 0, 0): (1.5, 0) -> (1, 0.5), (1.5, 1) -> (0, 0.5).
    expectNear(p[0], {0.5f, 0, 0});
    expectNear(p[1], {1.0f, 0.5f, 0});
    // Half arm (unmoved (1.5, 1)) and half hand ((0, 0.5)): the blended matrix's image.
    expectNear(p[2], {0.75f, 0.75f, 0});
    // Normals: the arm's stays +y; the hand's turns to -x; the blend's is normalised.
    const auto n = s.get("normals");
    ASSERT_EQ(n.size(), 3u);
    expectNear(n[0], {0, 1, 0});
    expectNear(n[1], {-1, 0, 0});
    EXPECT_NEAR(glm::length(n[2]), 1.0f, 1e-5f);
    // The influences are not shading primvars.
    for (const auto& d : s.scene->getPrimvarDescriptors(hd::Path("/Rig/Arm"), hd::Interpolation::Vertex))
        EXPECT_EQ(d.name.str().rfind("skel:", 0), std::string::npos) << d.name.str();
}

TEST(Skinning, TheMeshsOwnJointOrderAndTheGeomBindTransformApply) {
    // skel:joints reverses the order, so index 1 is "arm" and 0 is "arm/hand"; the geometry
    // was bound 1 unit lower in y (geomBindTransform lifts it back).
    const std::string extra = R"(
        uniform token[] skel:joints = ["arm/hand", "arm"]
        int[] primvars:skel:jointIndices = [1, 1, 0, 1, 1, 0] (interpolation = "vertex" elementSize = 2)
        float[] primvars:skel:jointWeights = [1, 0, 1, 0, 0.5, 0.5] (interpolation = "vertex" elementSize = 2)
        matrix4d primvars:skel:geomBindTransform = ((1,0,0,0),(0,1,0,0),(0,0,1,0),(0,1,0,1))
)";
    Posed s(scene(extra, kAnimated));
    const auto p = s.get("points");
    ASSERT_EQ(p.size(), 3u);
    expectNear(p[0], {0.5f, 1, 0});    // arm only: lifted by the geomBindTransform
    expectNear(p[1], {0.0f, 0.5f, 0});  // (1.5, 1) under the turned hand
}

TEST(Skinning, MalformedBindingsWarnAndDrawTheBindPose) {
    const std::string badIndex = R"(
        int[] primvars:skel:jointIndices = [0, 0, 7, 0, 0, 1] (interpolation = "vertex" elementSize = 2)
        float[] primvars:skel:jointWeights = [1, 0, 1, 0, 0.5, 0.5] (interpolation = "vertex" elementSize = 2)
)";
    Posed s(scene(badIndex, kAnimated));
    EXPECT_TRUE(s.warned("out of range"));
    const auto p = s.get("points");
    ASSERT_EQ(p.size(), 3u);
    expectNear(p[1], {1.5f, 0, 0});  // as authored
    const std::string shortWeights = R"(
        int[] primvars:skel:jointIndices = [0, 0, 1, 0, 0, 1] (interpolation = "vertex" elementSize = 2)
        float[] primvars:skel:jointWeights = [1, 0, 1] (interpolation = "vertex" elementSize = 2)
)";
    Posed t(scene(shortWeights, kAnimated));
    EXPECT_TRUE(t.warned("expected 6"));
}

TEST(Skinning, EditingTheAnimationPosesTheMeshAgain) {
    Posed s(scene(kInfluences, kAnimated));
    s.index.sync();
    adapter::StageEditor editor(*s.stage, *s.scene, s.index);
    editor.setAttribute("/Rig/Anim", "rotations", adapter::EditValue::of({1, 0, 0, 0}));  // unturned
    EXPECT_NE(s.index.changeTracker().dirtyBits(hd::ChangeTracker::Kind::Rprim, hd::Path("/Rig/Arm")) &
                  hd::RprimDirty::Points,
              0u);
    auto p = s.get("points");
    ASSERT_EQ(p.size(), 3u);
    expectNear(p[1], {1.5f, 0, 0});
    // Moving the SkelRoot moves the skeleton's space, so the mesh follows.
    const double m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 20, 0, 1};
    editor.setTransform("/Rig", m);
    EXPECT_DOUBLE_EQ(s.scene->getTransform(hd::Path("/Rig/Arm"))[3][1], 20.0);
    EXPECT_DOUBLE_EQ(s.scene->getTransform(hd::Path("/Rig/Arm"))[3][0], 0.0);
}

TEST(Skinning, AnInactiveAnimationOrSkeletonIsNotUsed) {
    std::string text = scene(kInfluences, kAnimated);
    const std::string anim = "def SkelAnimation \"Anim\"\n";
    text.replace(text.find(anim), anim.size(), "def SkelAnimation \"Anim\" (\n        active = false\n    )\n");
    Posed s(text);
    auto p = s.get("points");
    ASSERT_EQ(p.size(), 3u);
    expectNear(p[1], {1.5f, 0, 0});  // the rest pose
    EXPECT_TRUE(s.warned("not an active SkelAnimation"));
    // An inactive skeleton: the mesh is drawn as authored, in its own transform (x = 100).
    std::string off = scene(kInfluences, kAnimated);
    const std::string skel = "def Skeleton \"Skel\" (\n";
    off.replace(off.find(skel), skel.size(), skel + "        active = false\n");
    Posed t(off);
    EXPECT_TRUE(t.warned("inactive"));
    EXPECT_EQ(t.scene->getTransform(hd::Path("/Rig/Arm"))[3][0], 100.0);
}

TEST(Skinning, EditsRePoseOnlyWhatTheyTouch) {
    std::string text = scene(kInfluences, kAnimated) + "def Xform \"Other\" {}\n";
    Posed s(text);
    s.index.sync();
    adapter::StageEditor editor(*s.stage, *s.scene, s.index);
    auto armBits = [&] {
        return s.index.changeTracker().dirtyBits(hd::ChangeTracker::Kind::Rprim, hd::Path("/Rig/Arm"));
    };
    // An unrelated prim moves: the skinned mesh is not touched.
    const double m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 5, 0, 0, 1};
    editor.setTransform("/Other", m);
    EXPECT_EQ(armBits(), 0u);
    // The mesh's own transform is ignored: only its transform bit, and the skeleton's space stays.
    editor.setTransform("/Rig/Arm", m);
    EXPECT_EQ(s.scene->getTransform(hd::Path("/Rig/Arm"))[3][0], 0.0);
    s.index.sync();
    // Removing the skeleton draws the mesh as authored, in its own (edited) transform.
    editor.removePrim("/Rig/Skel");
    EXPECT_NE(armBits() & hd::RprimDirty::Points, 0u);
    const auto p = s.get("points");
    ASSERT_EQ(p.size(), 3u);
    expectNear(p[1], {1.5f, 0, 0});
    EXPECT_EQ(s.scene->getTransform(hd::Path("/Rig/Arm"))[3][0], 5.0);
}

TEST(Skinning, FixingABrokenSkeletonPosesTheMesh) {
    std::string text = scene(kInfluences, kAnimated);
    const std::string bind = "uniform matrix4d[] bindTransforms = [((1,0,0,0),(0,1,0,0),(0,0,1,0),(0,0,0,1)), ";
    text.replace(text.find(bind), bind.size(), "uniform matrix4d[] bindTransforms = [");  // one matrix for two joints
    Posed s(text);
    EXPECT_TRUE(s.warned("bindTransforms has 1 matrices for 2 joints"));
    expectNear(s.get("points")[1], {1.5f, 0, 0});
    s.index.sync();
    adapter::StageEditor editor(*s.stage, *s.scene, s.index);
    editor.setAttribute("/Rig/Skel", "bindTransforms",
                        adapter::EditValue::of({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,  //
                                                1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1}));
    expectNear(s.get("points")[1], {1.0f, 0.5f, 0});  // the turned hand
}

TEST(Skinning, LongJointPathsStayLinear) {
    // 25 joints whose paths are 8000 segments deep: finding parents by hashing every prefix
    // took seconds; the segment trie takes milliseconds.
    std::string deep;
    for (int i = 0; i < 8000; ++i) deep += i ? "/a" : "a";
    std::string joints, binds;
    for (int j = 0; j < 25; ++j) {
        joints += std::string(j ? ", " : "") + "\"" + deep + "/j" + std::to_string(j) + "\"";
        binds += std::string(j ? ", " : "") + "((1,0,0,0),(0,1,0,0),(0,0,1,0),(0,0,0,1))";
    }
    std::string text = scene(kInfluences, "");
    text.replace(text.find("[\"arm\", \"arm/hand\"]"), std::string("[\"arm\", \"arm/hand\"]").size(), "[" + joints + "]");
    const size_t b = text.find("uniform matrix4d[] bindTransforms");
    text.replace(b, text.find('\n', b) - b, "uniform matrix4d[] bindTransforms = [" + binds + "]");
    const size_t r = text.find("uniform matrix4d[] restTransforms");
    text.erase(r, text.find('\n', r) - r);
    const auto start = std::chrono::steady_clock::now();
    Posed s(text);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    expectNear(s.get("points")[1], {1.5f, 0, 0});  // identity pose
    EXPECT_LT(seconds, 2.0);  // generous: the quadratic walk took minutes at this depth
}

TEST(Skinning, BlendShapesOffsetThePointsBeforeSkinning) {
    // "up" lifts point 0 by (0, 0, 2) (sparse), "side" moves every point by (0, 1, 0); the
    // animation weighs them 0.5 and 0 ("side" then does nothing).
    std::string text = scene(std::string(kInfluences) + R"(
        uniform token[] skel:blendShapes = ["up", "side"]
        rel skel:blendShapeTargets = [</Rig/Arm/Up>, </Rig/Arm/Side>]
        def BlendShape "Up"
        {
            uniform vector3f[] offsets = [(0, 0, 2)]
            uniform int[] pointIndices = [0]
        }
        def BlendShape "Side"
        {
            uniform vector3f[] offsets = [(0, 1, 0), (0, 1, 0), (0, 1, 0)]
        }
)", kAnimated);
    const std::string weights = "        half3[] scales = [(1, 1, 1)]\n";
    text.replace(text.find(weights), weights.size(),
                 weights + "        uniform token[] blendShapes = [\"up\", \"side\"]\n        float[] blendShapeWeights = [0.5, 0]\n");
    Posed s(text);
    const auto p = s.get("points");
    ASSERT_EQ(p.size(), 3u);
    expectNear(p[0], {0.5f, 0, 1});     // lifted, on the unmoved arm
    expectNear(p[1], {1.0f, 0.5f, 0});  // untouched by the shapes, turned with the hand
    // The same shapes on a mesh without joint influences: offsets only, its own transform.
    const size_t i = text.find("int[] primvars:skel:jointIndices");
    text.erase(i, text.find("float[] primvars:skel:jointWeights") - i);
    const size_t w = text.find("float[] primvars:skel:jointWeights");
    text.erase(w, text.find('\n', w) - w);
    Posed t(text);
    const auto q = t.get("points");
    ASSERT_EQ(q.size(), 3u);
    expectNear(q[0], {0.5f, 0, 1});
    expectNear(q[1], {1.5f, 0, 0});
    EXPECT_EQ(t.scene->getTransform(hd::Path("/Rig/Arm"))[3][0], 100.0);
    // Moving the rig or the mesh keeps such a mesh in its own space.
    t.index.sync();
    adapter::StageEditor editor(*t.stage, *t.scene, t.index);
    const double x50[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 50, 0, 0, 1};
    editor.setTransform("/Rig/Arm", x50);
    EXPECT_EQ(t.scene->getTransform(hd::Path("/Rig/Arm"))[3][0], 50.0);
    EXPECT_EQ(t.scene->getTransform(hd::Path("/Rig/Arm"))[3][1], 10.0);  // under the SkelRoot's y = 10
}

TEST(Skinning, MovesKeepEachMeshInItsOwnSpace) {
    // A skinned mesh follows its skeleton; after the move a resync (purpose edit) must not bring
    // back the skeleton's old place from a cached pose.
    Posed s(scene(kInfluences, kAnimated));
    s.index.sync();
    adapter::StageEditor editor(*s.stage, *s.scene, s.index);
    const double x7[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 7, 0, 0, 1};
    editor.setTransform("/Rig/Skel", x7);
    EXPECT_EQ(s.scene->getTransform(hd::Path("/Rig/Arm"))[3][0], 7.0);
    editor.setAttribute("/Rig/Arm", "purpose", adapter::EditValue::text("render"));
    EXPECT_EQ(s.scene->getTransform(hd::Path("/Rig/Arm"))[3][0], 7.0);
}

namespace {
// The arm with one blend shape "up" (point 0 lifted by 2) plus `inbetweens` (attribute lines of
// the BlendShape), animated at blend weight `weight`.
std::string upShapeScene(const std::string& inbetweens, double weight) {
    std::string text = scene(R"(
        uniform token[] skel:blendShapes = ["up"]
        rel skel:blendShapeTargets = </Rig/Arm/Up>
        def BlendShape "Up"
        {
            uniform vector3f[] offsets = [(0, 0, 2)]
            uniform int[] pointIndices = [0]
)" + inbetweens + R"(
        }
)", kAnimated);
    const std::string scales = "        half3[] scales = [(1, 1, 1)]\n";
    text.replace(text.find(scales), scales.size(),
                 scales + "        uniform token[] blendShapes = [\"up\"]\n        float[] blendShapeWeights = [" +
                     std::to_string(weight) + "]\n");
    return text;
}
}  // namespace

TEST(Skinning, InbetweenShapesBlendPiecewiseByWeight) {
    // "up" lifts point 0: 0.5 at its inbetween (weight 0.5), 2 at weight 1 — a bent path. A
    // weight between two sub-shapes blends those two; beyond them all the nearest two are
    // extrapolated (UsdSkelBlendShapeQuery). An inbetween at weight 1 is skipped with a warning.
    // The inbetween also carries normal offsets, the primary shape none.
    auto points = [](double weight, std::vector<std::string>* warnings = nullptr, std::vector<glm::vec3>* normals = nullptr) {
        const std::string text = upShapeScene(R"(
            uniform vector3f[] inbetweens:half = [(0, 0, 0.5)] (weight = 0.5)
            uniform vector3f[] inbetweens:half:normalOffsets = [(1, 0, 0)]
            uniform vector3f[] inbetweens:bad = [(0, 0, 100)] (weight = 1))", weight);
        Posed s(text);
        if (warnings) *warnings = s.scene->warnings();
        if (normals) *normals = s.get("normals");
        const auto p = s.get("points");
        return p.empty() ? -1e9f : p[0].z;
    };
    EXPECT_NEAR(points(0.25), 0.25f, 1e-5f);             // halfway to the inbetween
    EXPECT_NEAR(points(0.5), 0.5f, 1e-5f);               // the inbetween itself
    EXPECT_NEAR(points(0.75), 0.5f * 0.5f + 0.5f * 2.0f, 1e-5f);
    EXPECT_NEAR(points(1.0), 2.0f, 1e-5f);
    EXPECT_NEAR(points(1.5), -1.0f * 0.5f + 2.0f * 2.0f, 1e-5f);  // extrapolated from 0.5 and 1
    EXPECT_NEAR(points(-0.5), -0.5f, 1e-5f);             // extrapolated from 0 and 0.5
    std::vector<std::string> warnings;
    std::vector<glm::vec3> normals;
    points(0.5, &warnings, &normals);
    bool skipped = false;
    for (const auto& w : warnings) skipped = skipped || w.find("inbetweens:bad") != std::string::npos;
    EXPECT_TRUE(skipped);
    ASSERT_EQ(normals.size(), 3u);
    expectNear(normals[0], glm::normalize(glm::vec3(1, 1, 0)));  // (0, 1, 0) + 1 x (1, 0, 0)
    expectNear(normals[1], {0, 1, 0});
}

TEST(Skinning, InbetweensAtOneWeightKeepThePoseFinite) {
    // Two inbetweens at 1.5 bracket nothing: one is skipped with a warning, and weights at and
    // beyond them extrapolate from the remaining pair (1 -> 1.5) instead of dividing by zero.
    const std::string text = upShapeScene(R"(
            uniform vector3f[] inbetweens:a = [(0, 0, 3)] (weight = 1.5)
            uniform vector3f[] inbetweens:b = [(0, 0, 9)] (weight = 1.5))", 2.0);
    Posed s(text);
    const auto p = s.get("points");
    ASSERT_EQ(p.size(), 3u);
    EXPECT_NEAR(p[0].z, 4.0f, 1e-5f);  // 1 -> 1.5 is 2 -> 3; at 2: 4
    EXPECT_TRUE(s.warned("two inbetweens at weight"));
}
