// SPDX-License-Identifier: Apache-2.0
// The C ABI driven the way a viewport drives it: settings, camera, resolution, AOVs,
// progressive passes, and incremental edits whose render stats show what was rebuilt.
// Delegates come from the real plugin (PRINCIPLED_PLUGIN_PATH) and, for comparison, from the
// statically linked table (prdCreateDelegateFromApi).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <string>

#include "plugins/abi/principled_c.h"
#include "plugins/embree/embreePlugin.h"

using ::testing::HasSubstr;

namespace {

// A grey Lambertian quad (z = 0, facing +Z) filling the left half of an orthographic view,
// lit head-on by a distant light.
const char* kScene = R"(#usda 1.0
(
    upAxis = "Y"
)
def Xform "World"
{
    def Mesh "Plane" (prepend apiSchemas = ["MaterialBindingAPI"])
    {
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(-10, -10, 0), (0, -10, 0), (0, 10, 0), (-10, 10, 0)]
        rel material:binding = </World/Mat>
    }
    def Material "Mat"
    {
        token outputs:surface.connect = </World/Mat/S.outputs:surface>
        def Shader "S"
        {
            uniform token info:id = "UsdPreviewSurface"
            color3f inputs:diffuseColor = (0.5, 0.5, 0.5)
            float inputs:ior = 1
            float inputs:roughness = 1
            token outputs:surface
        }
    }
    def DistantLight "Sun"
    {
        float inputs:intensity = 2
        float inputs:angle = 0
    }
    def Camera "Cam"
    {
        token projection = "orthographic"
        float horizontalAperture = 200
        float verticalAperture = 200
        double3 xformOp:translate = (0, 0, 10)
        uniform token[] xformOpOrder = ["xformOp:translate"]
    }
    def Camera "Other"
    {
        double3 xformOp:translate = (0, 0, 30)
        uniform token[] xformOpOrder = ["xformOp:translate"]
    }
}
)";

/// The registry reads the variable once per process: every test sets the same value.
void usePluginPath() {
    setenv("PRINCIPLED_PLUGIN_PATH", PRINCIPLED_EMBREE_PLUGIN_DIR ":" PRD_TEST_PLUGIN_DIR, 1);
}

class AbiTest : public ::testing::Test {
  protected:
    static void SetUpTestSuite() { usePluginPath(); }
    void SetUp() override {
        ASSERT_EQ(prdCreateDelegate("PrincipledEmbreeRenderer", &d), PRD_OK)
            << prdLastError(nullptr);
        ASSERT_EQ(prdSetResolution(d, 16, 16), PRD_OK);
        ASSERT_EQ(prdSetSettingInt(d, "convergedSamplesPerPixel", 4), PRD_OK);
        ASSERT_EQ(prdSetSettingInt(d, "defaultLighting", 0), PRD_OK);
        ASSERT_EQ(prdBindAov(d, "color"), PRD_OK);
        ASSERT_EQ(prdOpenStageString(d, kScene, "abi.usda"), PRD_OK) << prdLastError(d);
    }
    void TearDown() override { prdDestroyDelegate(d); }

    void renderToConvergence() {
        int converged = 0;
        for (int i = 0; i < 64 && !converged; ++i) ASSERT_EQ(prdRenderPass(d, &converged), PRD_OK);
        ASSERT_EQ(converged, 1);
    }
    /// Mean red of the left (plane) and right (empty) halves.
    std::pair<double, double> halves() {
        PrdBufferView v{};
        EXPECT_EQ(prdMapAov(d, "color", &v), PRD_OK) << prdLastError(d);
        const float* px = static_cast<const float*>(v.data);
        double left = 0, right = 0;
        for (int y = 0; y < v.height; ++y)
            for (int x = 0; x < v.width; ++x)
                (x < v.width / 2 ? left : right) += px[4 * (y * v.width + x)];
        double n = v.width * v.height / 2.0;
        return {left / n, right / n};
    }
    std::map<std::string, double> stats() {
        std::map<std::string, double> out;
        int n = 0;
        EXPECT_EQ(prdStatCount(d, &n), PRD_OK);
        for (int i = 0; i < n; ++i) {
            const char* k = nullptr;
            double v = 0;
            EXPECT_EQ(prdStat(d, i, &k, &v), PRD_OK);
            out[k] = v;
        }
        return out;
    }

    PrdDelegate* d = nullptr;
};

}  // namespace

TEST_F(AbiTest, RendersTheAnalyticLambertValue) {
    renderToConvergence();
    auto [left, right] = halves();
    // Delta distant light head-on on a Lambertian: L = albedo * E / pi.
    EXPECT_NEAR(left, 0.5 * 2.0 / M_PI, 1e-3);
    EXPECT_EQ(right, 0.0);
    int converged = 0, done = 0, target = 0;
    EXPECT_EQ(prdProgress(d, &converged, &done, &target), PRD_OK);
    EXPECT_EQ(converged, 1);
    EXPECT_EQ(done, 4);
    EXPECT_EQ(target, 4);
}

TEST_F(AbiTest, SettingsAreDescribedTypedAndChecked) {
    int n = 0;
    ASSERT_EQ(prdSettingCount(d, &n), PRD_OK);
    std::map<std::string, PrdSettingDescriptor> byKey;
    for (int i = 0; i < n; ++i) {
        PrdSettingDescriptor s{};
        ASSERT_EQ(prdSettingDescriptor(d, i, &s), PRD_OK);
        byKey[s.key] = s;
    }
    ASSERT_TRUE(byKey.count("convergedSamplesPerPixel"));
    EXPECT_EQ(byKey["convergedSamplesPerPixel"].type, PRD_TYPE_INT);
    EXPECT_STREQ(byKey["convergedSamplesPerPixel"].defaultText, "64");
    EXPECT_EQ(byKey["shadingModel"].type, PRD_TYPE_STRING);
    EXPECT_EQ(byKey["clampIndirect"].type, PRD_TYPE_FLOAT);

    const char* text = nullptr;
    ASSERT_EQ(prdGetSetting(d, "convergedSamplesPerPixel", &text), PRD_OK);
    EXPECT_STREQ(text, "4");
    ASSERT_EQ(prdSetSettingString(d, "shadingModel", "ue4"), PRD_OK);
    ASSERT_EQ(prdGetSetting(d, "shadingModel", &text), PRD_OK);
    EXPECT_STREQ(text, "ue4");
    EXPECT_EQ(prdSetSettingInt(d, "clampIndirect", 3), PRD_OK);  // an int for a float is fine
    ASSERT_EQ(prdGetSetting(d, "clampIndirect", &text), PRD_OK);
    EXPECT_STREQ(text, "3");

    EXPECT_EQ(prdSetSettingString(d, "shadingModel", "phong"), PRD_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(prdLastError(d),
                 "prdSetSettingString: render setting 'shadingModel': must be 'disney' or 'ue4', "
                 "not 'phong'");
    EXPECT_EQ(prdSetSettingInt(d, "convergedSamplesPerPixel", 0), PRD_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(prdSetSettingFloat(d, "seed", 1.5), PRD_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(
        prdLastError(d),
        "prdSetSettingFloat: render setting 'seed' is an int; set it with prdSetSettingInt");
    EXPECT_EQ(prdSetSettingInt(d, "sampels", 1), PRD_ERROR_NOT_FOUND);
    EXPECT_THAT(
        prdLastError(d),
        HasSubstr("unknown render setting 'sampels'; settings: convergedSamplesPerPixel, seed"));
    EXPECT_EQ(prdSetSettingInt(d, "seed", 7), PRD_OK);
    EXPECT_STREQ(prdLastError(d), "");  // cleared by a successful call
}

TEST_F(AbiTest, CameraAndResolution) {
    const char* cam = nullptr;
    ASSERT_EQ(prdGetCamera(d, &cam), PRD_OK);
    EXPECT_STREQ(cam, "/World/Cam");
    EXPECT_EQ(prdSetCamera(d, "/World/Nope"), PRD_ERROR_NOT_FOUND);
    EXPECT_STREQ(prdLastError(d),
                 "prdSetCamera: camera '/World/Nope' not found in the stage; cameras: "
                 "/World/Cam, /World/Other");
    ASSERT_EQ(prdSetCamera(d, "/World/Other"), PRD_OK);
    ASSERT_EQ(prdGetCamera(d, &cam), PRD_OK);
    EXPECT_STREQ(cam, "/World/Other");

    EXPECT_EQ(prdSetResolution(d, 0, 10), PRD_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(prdLastError(d),
                 "prdSetResolution: resolution 0x10 must be between 1x1 and 32768x32768");
    ASSERT_EQ(prdSetResolution(d, 20, 10), PRD_OK);
    int converged = 0;
    ASSERT_EQ(prdRenderPass(d, &converged), PRD_OK);
    PrdBufferView v{};
    ASSERT_EQ(prdMapAov(d, "color", &v), PRD_OK);
    EXPECT_EQ(v.width, 20);
    EXPECT_EQ(v.height, 10);
}

TEST_F(AbiTest, AovsAreListedAndDescribed) {
    int n = 0;
    ASSERT_EQ(prdAovCount(d, &n), PRD_OK);
    std::map<std::string, PrdAovInfo> byName;
    for (int i = 0; i < n; ++i) {
        PrdAovInfo a{};
        ASSERT_EQ(prdAovInfo(d, i, &a), PRD_OK);
        byName[a.name] = a;
    }
    ASSERT_TRUE(byName.count("color"));
    ASSERT_TRUE(byName.count("primId"));
    EXPECT_EQ(byName["primId"].format, PRD_FORMAT_INT32);
    EXPECT_EQ(byName["primId"].multiSampled, 0);
    ASSERT_EQ(prdBindAov(d, "primId"), PRD_OK);
    ASSERT_EQ(prdBindAov(d, "cameraDepth"), PRD_OK);
    renderToConvergence();
    PrdBufferView v{};
    ASSERT_EQ(prdMapAov(d, "primId", &v), PRD_OK);
    EXPECT_EQ(v.format, PRD_FORMAT_INT32);
    EXPECT_EQ(v.channels, 1);
    const int32_t* ids = static_cast<const int32_t*>(v.data);
    PrdBufferView z{};
    ASSERT_EQ(prdMapAov(d, "cameraDepth", &z), PRD_OK);
    EXPECT_EQ(z.format, PRD_FORMAT_FLOAT32);
    const float* depth = static_cast<const float*>(z.data);
    // IDs and depth are first-hit values: exact on every pixel, the edge included.
    for (int y = 0; y < v.height; ++y)
        for (int x = 0; x < v.width; ++x) {
            int i = y * v.width + x;
            if (x < v.width / 2) {
                EXPECT_EQ(ids[i], ids[0]) << x << "," << y;
                EXPECT_NEAR(depth[i], 10.0f, 1e-4f) << x << "," << y;
            } else {
                EXPECT_EQ(ids[i], -1) << x << "," << y;
            }
        }
    EXPECT_GE(ids[0], 0);
    ASSERT_EQ(prdUnbindAov(d, "primId"), PRD_OK);
    EXPECT_EQ(prdMapAov(d, "primId", &v), PRD_ERROR_NOT_BOUND);
    EXPECT_EQ(prdUnbindAov(d, "primId"), PRD_ERROR_NOT_BOUND);
    EXPECT_EQ(prdAovInfo(d, n, &byName["x"]), PRD_ERROR_NOT_FOUND);
}

TEST_F(AbiTest, MaterialEditRerendersWithoutAnyBvhBuild) {
    renderToConvergence();
    double before = halves().first;
    double builds = stats()["blasBuilds"];
    double rebuilt = stats()["meshesRebuilt"];
    const double red[3] = {1.0, 0.0, 0.0};
    ASSERT_EQ(prdSetAttributeNumbers(d, "/World/Mat/S", "inputs:diffuseColor", red, 3), PRD_OK)
        << prdLastError(d);
    int converged = 1;
    ASSERT_EQ(prdRenderPass(d, &converged), PRD_OK);
    EXPECT_EQ(converged, 0);  // the edit restarted accumulation
    renderToConvergence();
    EXPECT_NEAR(halves().first, 2.0 * before, 1e-3);  // red albedo 1 instead of 0.5
    EXPECT_EQ(stats()["blasBuilds"], builds);
    EXPECT_EQ(stats()["meshesRebuilt"], rebuilt);
}

TEST_F(AbiTest, LightEditScalesTheImageExactly) {
    renderToConvergence();
    double before = halves().first;
    const double intensity = 6.0;
    ASSERT_EQ(prdSetAttributeNumbers(d, "/World/Sun", "inputs:intensity", &intensity, 1), PRD_OK);
    renderToConvergence();
    EXPECT_NEAR(halves().first, 3.0 * before, 1e-4);
}

TEST_F(AbiTest, TransformEditMovesTheMeshWithoutRebuildingIt) {
    renderToConvergence();
    auto [left, right] = halves();
    ASSERT_GT(left, 0.1);
    double rebuilt = stats()["meshesRebuilt"];
    // Move the quad 10 units right: it now fills the right half.
    const double m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 10, 0, 0, 1};
    ASSERT_EQ(prdSetLocalTransform(d, "/World/Plane", m), PRD_OK) << prdLastError(d);
    renderToConvergence();
    auto [left2, right2] = halves();
    EXPECT_EQ(left2, 0.0);
    EXPECT_NEAR(right2, left, 1e-3);
    EXPECT_EQ(stats()["meshesRebuilt"], rebuilt);
    EXPECT_GT(stats()["transformUpdates"], 0.0);
}

TEST_F(AbiTest, XformOpEditMovesTheCamera) {
    renderToConvergence();
    double left = halves().first;
    double rebuilt = stats()["meshesRebuilt"];
    // The camera slides 5 units right: the quad's right edge (x = 0) moves to a quarter width.
    const double t[3] = {5, 0, 10};
    ASSERT_EQ(prdSetAttributeNumbers(d, "/World/Cam", "xformOp:translate", t, 3), PRD_OK)
        << prdLastError(d);
    renderToConvergence();
    EXPECT_NEAR(halves().first, 0.5 * left, 1e-3);
    EXPECT_EQ(stats()["meshesRebuilt"], rebuilt);
    // Back where it was: the same image as before the edit.
    const double back[3] = {0, 0, 10};
    ASSERT_EQ(prdSetAttributeNumbers(d, "/World/Cam", "xformOp:translate", back, 3), PRD_OK);
    renderToConvergence();
    EXPECT_NEAR(halves().first, left, 1e-6);
}

TEST_F(AbiTest, FramingCropsAndRestoresTheImage) {
    // The plane fills the left half. A data window over the right half renders only that half
    // (the plane is gone); NULL returns to the stage's framing (the whole image).
    renderToConvergence();
    const double left = halves().first;
    ASSERT_GT(left, 0.1);
    const double rightHalf[4] = {0.5, 0.0, 1.0, 1.0};
    ASSERT_EQ(prdSetFraming(d, "expandAperture", 1.0, rightHalf), PRD_OK) << prdLastError(d);
    renderToConvergence();
    EXPECT_EQ(halves().first, 0.0);
    ASSERT_EQ(prdSetFraming(d, nullptr, 0.0, nullptr), PRD_OK) << prdLastError(d);
    renderToConvergence();
    EXPECT_NEAR(halves().first, left, 1e-6);
    // Kept across stages, like the resolution.
    ASSERT_EQ(prdSetFraming(d, "cropAperture", 1.0, rightHalf), PRD_OK);
    ASSERT_EQ(prdOpenStageString(d, kScene, "again.usda"), PRD_OK) << prdLastError(d);
    renderToConvergence();
    EXPECT_EQ(halves().first, 0.0);
    // Bad values: statuses naming them, and the framing in force stays.
    EXPECT_EQ(prdSetFraming(d, "squash", 1.0, nullptr), PRD_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(prdLastError(d)).find("'squash'"), std::string::npos) << prdLastError(d);
    EXPECT_EQ(prdSetFraming(d, "expandAperture", 0.0, nullptr), PRD_ERROR_INVALID_ARGUMENT);
    const double outside[4] = {-0.5, 0.0, 0.5, 1.0}, empty[4] = {0.5, 0.0, 0.5, 1.0};
    EXPECT_EQ(prdSetFraming(d, "expandAperture", 1.0, outside), PRD_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(prdSetFraming(d, "expandAperture", 1.0, empty), PRD_ERROR_INVALID_ARGUMENT);
    renderToConvergence();
    EXPECT_EQ(halves().first, 0.0);
}

TEST_F(AbiTest, ReloadTexturesReportsWhetherAnythingWasRead) {
    // The scene has no texture: nothing to re-read, even when asked to drop everything (the
    // image is not restarted for nothing).
    int reloaded = -1;
    ASSERT_EQ(prdReloadTextures(d, 1, &reloaded), PRD_OK) << prdLastError(d);
    EXPECT_EQ(reloaded, 0);
    ASSERT_EQ(prdReloadTextures(d, 0, &reloaded), PRD_OK) << prdLastError(d);
    EXPECT_EQ(reloaded, 0);
    EXPECT_EQ(prdReloadTextures(d, 1, nullptr), PRD_OK);
    PrdDelegate* fresh = nullptr;
    ASSERT_EQ(prdCreateDelegate("PrincipledEmbreeRenderer", &fresh), PRD_OK);
    EXPECT_EQ(prdReloadTextures(fresh, 1, &reloaded), PRD_ERROR_NO_STAGE);
    prdDestroyDelegate(fresh);
}

TEST_F(AbiTest, PointsEditRebuildsThatMesh) {
    renderToConvergence();
    double rebuilt = stats()["meshesRebuilt"];
    const double pts[12] = {0, -10, 0, 10, -10, 0, 10, 10, 0, 0, 10, 0};  // the right half
    ASSERT_EQ(prdSetAttributeNumbers(d, "/World/Plane", "points", pts, 12), PRD_OK)
        << prdLastError(d);
    renderToConvergence();
    auto [left, right] = halves();
    EXPECT_EQ(left, 0.0);
    EXPECT_GT(right, 0.1);
    EXPECT_GT(stats()["meshesRebuilt"], rebuilt);
}

TEST_F(AbiTest, EditErrorsAreStatusesWithMessages) {
    const double one = 1.0, two[2] = {1, 2};
    EXPECT_EQ(prdSetAttributeNumbers(d, "/World/Nope", "inputs:x", &one, 1), PRD_ERROR_NOT_FOUND);
    EXPECT_STREQ(prdLastError(d), "prdSetAttributeNumbers: setAttribute: no prim at '/World/Nope'");
    EXPECT_EQ(prdSetAttributeNumbers(d, "/World/Plane", "xformOp:translate", &one, 1),
              PRD_ERROR_UNSUPPORTED);
    EXPECT_STREQ(prdLastError(d),
                 "prdSetAttributeNumbers: 'xformOp:translate' is not in the xformOpOrder of "
                 "'/World/Plane' (author xformOpOrder first, or replace the whole transform)");
    EXPECT_EQ(prdSetAttributeNumbers(d, "/World/Cam", "xformOp:translate", &one, 1),
              PRD_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(prdLastError(d),
                 "prdSetAttributeNumbers: /World/Cam.xformOp:translate: expected double3, got 1 "
                 "number");
    EXPECT_EQ(prdSetAttributeString(d, "/World/Plane", "faceVertexCounts", "x"),
              PRD_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(prdSetAttributeNumbers(d, "/World/Mat/S", "inputs:diffuseColor", two, 2),
              PRD_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(prdLastError(d),
                 "prdSetAttributeNumbers: /World/Mat/S.inputs:diffuseColor: expected color3f, got "
                 "2 numbers");
    EXPECT_EQ(prdSetAttributeString(d, "/World/Mat/S", "inputs:roughness", "rough"),
              PRD_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(prdSetAttributeNumbers(d, "/World/Plane", "points", nullptr, 3),
              PRD_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(prdLastError(d), "prdSetAttributeNumbers: values is NULL");
}

TEST_F(AbiTest, AddBindAndRemovePrims) {
    renderToConvergence();
    double left = halves().first;
    // A second quad in the right half, with a red material built through the ABI.
    ASSERT_EQ(prdAddPrim(d, "/World/Red", "Material"), PRD_OK) << prdLastError(d);
    ASSERT_EQ(prdAddPrim(d, "/World/Red/S", "Shader"), PRD_OK) << prdLastError(d);
    ASSERT_EQ(prdSetAttributeString(d, "/World/Red/S", "info:id", "UsdPreviewSurface"), PRD_OK)
        << prdLastError(d);
    const double red[3] = {1, 0, 0}, ior = 1;
    ASSERT_EQ(prdSetAttributeNumbers(d, "/World/Red/S", "inputs:diffuseColor", red, 3), PRD_OK);
    ASSERT_EQ(prdSetAttributeNumbers(d, "/World/Red/S", "inputs:ior", &ior, 1), PRD_OK);
    ASSERT_EQ(prdConnectAttribute(d, "/World/Red", "outputs:surface", "/World/Red/S.outputs:surface"),
              PRD_OK) << prdLastError(d);
    ASSERT_EQ(prdAddPrim(d, "/World/Quad", "Mesh"), PRD_OK) << prdLastError(d);
    const double pts[12] = {0, -10, 0, 10, -10, 0, 10, 10, 0, 0, 10, 0};
    const double counts[1] = {4}, indices[4] = {0, 1, 2, 3};
    ASSERT_EQ(prdSetAttributeNumbers(d, "/World/Quad", "points", pts, 12), PRD_OK) << prdLastError(d);
    ASSERT_EQ(prdSetAttributeNumbers(d, "/World/Quad", "faceVertexCounts", counts, 1), PRD_OK);
    ASSERT_EQ(prdSetAttributeNumbers(d, "/World/Quad", "faceVertexIndices", indices, 4), PRD_OK);
    ASSERT_EQ(prdBindMaterial(d, "/World/Quad", "/World/Red"), PRD_OK) << prdLastError(d);
    renderToConvergence();
    auto [l1, r1] = halves();
    EXPECT_NEAR(l1, left, 1e-6);
    EXPECT_NEAR(r1, 2.0 * left, 1e-3);  // red albedo 1 where the grey one is 0.5
    // Rebinding the plane to the red material doubles the left half's red.
    ASSERT_EQ(prdBindMaterial(d, "/World/Plane", "/World/Red"), PRD_OK);
    renderToConvergence();
    EXPECT_NEAR(halves().first, 2.0 * left, 1e-3);
    // Removing the material: both fall back to the default material (no crash, still lit).
    ASSERT_EQ(prdRemovePrim(d, "/World/Red"), PRD_OK) << prdLastError(d);
    renderToConvergence();
    EXPECT_GT(halves().first, 0.0);
    ASSERT_EQ(prdRemovePrim(d, "/World/Quad"), PRD_OK);
    renderToConvergence();
    EXPECT_EQ(halves().second, 0.0);
    // Errors name the prim and leave the scene alone.
    EXPECT_EQ(prdAddPrim(d, "/World/Plane", "Mesh"), PRD_ERROR_INVALID_ARGUMENT);
    EXPECT_THAT(prdLastError(d), HasSubstr("/World/Plane"));
    EXPECT_EQ(prdAddPrim(d, "/World/T", "Teapot"), PRD_ERROR_UNSUPPORTED);
    EXPECT_EQ(prdRemovePrim(d, "/World/Quad"), PRD_ERROR_NOT_FOUND);
    EXPECT_EQ(prdBindMaterial(d, "/World/Plane", "/World/Sun"), PRD_ERROR_INVALID_ARGUMENT);
    EXPECT_THAT(prdLastError(d), HasSubstr("expected a Material"));
    const char* targets[1] = {"/World/Nope"};
    EXPECT_EQ(prdSetRelationship(d, "/World/Plane", "material:binding", targets, 1),
              PRD_ERROR_INVALID_ARGUMENT);
    const double uv[4] = {0, 0, 1, 1};
    EXPECT_EQ(prdSetAttributeTyped(d, "/World/Plane", "primvars:uv", "texCoord2f[]", uv, 4), PRD_OK)
        << prdLastError(d);
    EXPECT_EQ(prdSetAttributeTyped(d, "/World/Plane", "points", "float[]", uv, 4),
              PRD_ERROR_INVALID_ARGUMENT);
}

TEST_F(AbiTest, CameraParameterEditChangesTheFraming) {
    renderToConvergence();
    double left = halves().first;
    // 400 tenths: the view is 40 units square, so the quad covers a quarter of the left half.
    const double aperture = 400;
    ASSERT_EQ(prdSetAttributeNumbers(d, "/World/Cam", "horizontalAperture", &aperture, 1), PRD_OK)
        << prdLastError(d);
    ASSERT_EQ(prdSetAttributeNumbers(d, "/World/Cam", "verticalAperture", &aperture, 1), PRD_OK);
    renderToConvergence();
    EXPECT_NEAR(halves().first, 0.25 * left, 1e-3);
}

TEST_F(AbiTest, OpeningAStageWithoutTheRequestedCameraFailsAndLeavesNoStage) {
    ASSERT_EQ(prdSetCamera(d, "/World/Other"), PRD_OK);
    const char* other = R"(#usda 1.0
def Camera "OnlyCam"
{
}
)";
    EXPECT_EQ(prdOpenStageString(d, other, "other.usda"), PRD_ERROR_NOT_FOUND);
    EXPECT_STREQ(prdLastError(d),
                 "prdOpenStageString: camera '/World/Other' not found in the stage; "
                 "cameras: /OnlyCam");
    EXPECT_EQ(prdRenderPass(d, nullptr), PRD_ERROR_NO_STAGE);
    ASSERT_EQ(prdSetCamera(d, nullptr), PRD_OK);
    ASSERT_EQ(prdOpenStageString(d, other, "other.usda"), PRD_OK);
    const char* cam = nullptr;
    ASSERT_EQ(prdGetCamera(d, &cam), PRD_OK);
    EXPECT_STREQ(cam, "/OnlyCam");
}

TEST(AbiRegistry, RenderersAreListedByPriorityAndPluginFailuresAreStatuses) {
    usePluginPath();
    ASSERT_EQ(prdRendererCount(), 3);
    PrdRendererInfo info{};
    ASSERT_EQ(prdRendererInfo(0, &info), PRD_OK);
    EXPECT_STREQ(info.typeName, "PrincipledEmbreeRenderer");
    EXPECT_STREQ(info.pluginName, "hdPrincipled");
    ASSERT_EQ(prdRendererInfo(1, &info), PRD_OK);
    EXPECT_STREQ(info.typeName, "FakeRenderer");
    ASSERT_EQ(prdRendererInfo(2, &info), PRD_OK);
    EXPECT_STREQ(info.typeName, "FutureRenderer");
    EXPECT_EQ(info.loaded, 0);
    EXPECT_EQ(prdRendererInfo(3, &info), PRD_ERROR_NOT_FOUND);
    EXPECT_STREQ(prdLastError(nullptr), "prdRendererInfo: index 3 out of range (3 renderers)");
    EXPECT_STREQ(prdRegistryDiagnostics(), "");

    PrdDelegate* d = nullptr;
    EXPECT_EQ(prdCreateDelegate("Fake", &d), PRD_ERROR_UNSUPPORTED);
    EXPECT_STREQ(prdLastError(nullptr), "prdCreateDelegate: fake plugin: create always fails");
    EXPECT_EQ(d, nullptr);
    EXPECT_EQ(prdCreateDelegate("FutureRenderer", &d), PRD_ERROR_PLUGIN);
    EXPECT_THAT(prdLastError(nullptr), HasSubstr("has ABI version 999; this host needs 1"));
    EXPECT_EQ(d, nullptr);
}

TEST(AbiDirect, StaticallyLinkedTableRendersTheSameImageAsThePlugin) {
    usePluginPath();
    auto render = [](PrdDelegate* d) {
        EXPECT_EQ(prdSetResolution(d, 8, 8), PRD_OK);
        EXPECT_EQ(prdSetSettingInt(d, "convergedSamplesPerPixel", 2), PRD_OK);
        EXPECT_EQ(prdBindAov(d, "color"), PRD_OK);
        EXPECT_EQ(prdOpenStageString(d, kScene, "abi.usda"), PRD_OK);
        int converged = 0;
        while (!converged) EXPECT_EQ(prdRenderPass(d, &converged), PRD_OK);
        PrdBufferView v{};
        EXPECT_EQ(prdMapAov(d, "color", &v), PRD_OK);
        const float* p = static_cast<const float*>(v.data);
        return std::vector<float>(p, p + 8 * 8 * 4);
    };
    PrdDelegate* direct = nullptr;
    PrdDelegate* loaded = nullptr;
    ASSERT_EQ(prdCreateDelegateFromApi(prdEmbreeRendererApi(), nullptr, &direct), PRD_OK);
    ASSERT_EQ(prdCreateDelegate(nullptr, &loaded), PRD_OK);  // highest priority: Embree
    EXPECT_EQ(render(direct), render(loaded));
    prdDestroyDelegate(direct);
    prdDestroyDelegate(loaded);

    EXPECT_EQ(prdCreateDelegateFromApi(prdEmbreeRendererApi(), "Cycles", &direct),
              PRD_ERROR_NOT_FOUND);
    EXPECT_STREQ(
        prdLastError(nullptr),
        "prdCreateDelegate: this plugin provides 'PrincipledEmbreeRenderer', not 'Cycles'");
    EXPECT_EQ(direct, nullptr);
}

namespace {

/// kScene rebuilt from host data through the scene builder.
PrdSceneBuilder* buildHostScene() {
    PrdSceneBuilder* b = nullptr;
    EXPECT_EQ(prdSceneBuilderCreate(&b), PRD_OK);
    const float points[] = {-10, -10, 0, 0, -10, 0, 0, 10, 0, -10, 10, 0};
    const int counts[] = {4}, indices[] = {0, 1, 2, 3};
    EXPECT_EQ(prdSceneAddMesh(b, "/World/Plane", points, 4, counts, 1, indices, 4), PRD_OK)
        << prdLastError(nullptr);
    EXPECT_EQ(prdSceneAddMaterial(b, "/World/Mat"), PRD_OK);
    const double grey[3] = {0.5, 0.5, 0.5}, one = 1.0, two = 2.0, zero = 0.0;
    EXPECT_EQ(prdSceneSetMaterialInput(b, "/World/Mat", "diffuseColor", grey, 3), PRD_OK);
    EXPECT_EQ(prdSceneSetMaterialInput(b, "/World/Mat", "ior", &one, 1), PRD_OK);
    EXPECT_EQ(prdSceneSetMaterialInput(b, "/World/Mat", "roughness", &one, 1), PRD_OK);
    EXPECT_EQ(prdSceneBindMaterial(b, "/World/Plane", "/World/Mat"), PRD_OK);
    EXPECT_EQ(prdSceneAddPrim(b, "/World/Sun", "DistantLight"), PRD_OK);
    EXPECT_EQ(prdSceneSetAttribute(b, "/World/Sun", "float", "inputs:intensity", &two, 1, nullptr),
              PRD_OK);
    EXPECT_EQ(prdSceneSetAttribute(b, "/World/Sun", "float", "inputs:angle", &zero, 1, nullptr),
              PRD_OK);
    EXPECT_EQ(prdSceneAddPrim(b, "/World/Cam", "Camera"), PRD_OK);
    EXPECT_EQ(prdSceneSetAttributeString(b, "/World/Cam", "token", "projection", "orthographic"),
              PRD_OK);
    const double aperture = 200;
    EXPECT_EQ(
        prdSceneSetAttribute(b, "/World/Cam", "float", "horizontalAperture", &aperture, 1, nullptr),
        PRD_OK);
    EXPECT_EQ(
        prdSceneSetAttribute(b, "/World/Cam", "float", "verticalAperture", &aperture, 1, nullptr),
        PRD_OK);
    const double m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 10, 1};
    EXPECT_EQ(prdSceneSetTransform(b, "/World/Cam", m), PRD_OK);
    return b;
}

}  // namespace

TEST_F(AbiTest, HostBuiltSceneRendersLikeTheSameUsdaText) {
    renderToConvergence();
    auto [left, right] = halves();
    PrdSceneBuilder* b = buildHostScene();
    ASSERT_EQ(prdOpenStageFromBuilder(d, b), PRD_OK) << prdLastError(d);
    renderToConvergence();
    auto [left2, right2] = halves();
    EXPECT_NEAR(left2, left, 1e-6);
    EXPECT_EQ(right2, right);
    const char* text = nullptr;
    ASSERT_EQ(prdSceneToUsda(b, &text), PRD_OK);
    EXPECT_THAT(text,
                HasSubstr("def Mesh \"Plane\" (prepend apiSchemas = [\"MaterialBindingAPI\"])"));
    EXPECT_THAT(text, HasSubstr("matrix4d xformOp:transform = ((1, 0, 0, 0), (0, 1, 0, 0), (0, 0, "
                                "1, 0), (0, 0, 10, 1))"));
    // Edits work on host-built scenes too.
    const double red[3] = {1, 0, 0};
    ASSERT_EQ(prdSetAttributeNumbers(d, "/World/Mat/Surface", "inputs:diffuseColor", red, 3),
              PRD_OK);
    renderToConvergence();
    EXPECT_NEAR(halves().first, 2 * left, 1e-3);
    prdSceneBuilderDestroy(b);
}

TEST(SceneBuilder, ErrorsAreStatusesWithMessages) {
    PrdSceneBuilder* b = nullptr;
    ASSERT_EQ(prdSceneBuilderCreate(&b), PRD_OK);
    const float pts[] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const int three[] = {3}, bad[] = {0, 1, 5}, ok[] = {0, 1, 2};
    EXPECT_EQ(prdSceneAddMesh(b, "World/M", pts, 3, three, 1, ok, 3), PRD_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(prdLastError(nullptr),
                 "prdSceneAddMesh: prim path 'World/M' must be absolute, like /World/Mesh");
    EXPECT_EQ(prdSceneAddMesh(b, "/World/M", pts, 3, three, 1, bad, 3), PRD_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(prdLastError(nullptr), "prdSceneAddMesh: index 5 at 2 is out of range (3 points)");
    EXPECT_EQ(prdSceneAddMesh(b, "/World/M", pts, 3, three, 1, ok, 2), PRD_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(prdLastError(nullptr),
                 "prdSceneAddMesh: face vertex counts add up to 3 but 2 indices were given");
    ASSERT_EQ(prdSceneAddMesh(b, "/World/M", pts, 3, three, 1, ok, 3), PRD_OK);
    EXPECT_EQ(prdSceneAddPrim(b, "/World/M", "Xform"), PRD_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(prdLastError(nullptr), "prdSceneAddPrim: prim '/World/M' already exists");
    const double n2[2] = {0, 1};
    EXPECT_EQ(
        prdSceneSetAttribute(b, "/World/M", "normal3f[]", "primvars:normals", n2, 2, "vertex"),
        PRD_ERROR_INVALID_ARGUMENT);
    EXPECT_STREQ(prdLastError(nullptr),
                 "prdSceneSetAttribute: 'primvars:normals' of type normal3f[] needs a multiple of "
                 "3 numbers, got 2");
    EXPECT_EQ(prdSceneSetAttribute(b, "/World/Nope", "float", "x", n2, 1, nullptr),
              PRD_ERROR_NOT_FOUND);
    EXPECT_EQ(prdSceneSetMaterialInput(b, "/World/M", "diffuseColor", n2, 1), PRD_ERROR_NOT_FOUND);
    EXPECT_EQ(prdSceneBindMaterial(nullptr, "/a", "/b"), PRD_ERROR_NULL_HANDLE);
    EXPECT_STREQ(prdLastError(nullptr), "prdSceneBindMaterial: builder is NULL");
    const double normals[9] = {0, 0, 1, 0, 0, 1, 0, 0, 1};
    ASSERT_EQ(
        prdSceneSetAttribute(b, "/World/M", "normal3f[]", "primvars:normals", normals, 9, "vertex"),
        PRD_OK);
    const char* text = nullptr;
    ASSERT_EQ(prdSceneToUsda(b, &text), PRD_OK);
    EXPECT_THAT(text, HasSubstr("normal3f[] primvars:normals = [(0, 0, 1), (0, 0, 1), (0, 0, 1)] "
                                "(interpolation = \"vertex\")"));
    EXPECT_THAT(text, HasSubstr("def Xform \"World\"\n{\n    def Mesh \"M\"\n    {\n"));
    prdSceneBuilderDestroy(b);
}

TEST_F(AbiTest, InstancerTransformEditMovesItsInstancesWithoutRebuilding) {
    // The plane of kScene drawn by a PointInstancer (one instance at the origin).
    std::string scene = kScene;
    const std::string from = "    def Mesh \"Plane\"";
    size_t at = scene.find(from);
    ASSERT_NE(at, std::string::npos);
    size_t end = scene.find("    def Material", at);
    std::string plane = scene.substr(at, end - at);
    std::string instancer = "    def PointInstancer \"Inst\"\n    {\n"
                            "        rel prototypes = [</World/Inst/Plane>]\n"
                            "        int[] protoIndices = [0]\n"
                            "        point3f[] positions = [(0, 0, 0)]\n" +
                            plane + "    }\n";
    scene.replace(at, end - at, instancer);
    ASSERT_EQ(prdOpenStageString(d, scene.c_str(), "instancer.usda"), PRD_OK) << prdLastError(d);
    renderToConvergence();
    auto [left, right] = halves();
    EXPECT_NEAR(left, 0.5 * 2.0 / M_PI, 1e-3);
    EXPECT_EQ(right, 0.0);
    double blas = stats()["blasBuilds"];
    const double m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 10, 0, 0, 1};
    ASSERT_EQ(prdSetLocalTransform(d, "/World/Inst", m), PRD_OK) << prdLastError(d);
    renderToConvergence();
    auto [left2, right2] = halves();
    EXPECT_EQ(left2, 0.0);
    EXPECT_NEAR(right2, left, 1e-3);  // moved once: not instancer * world of the prototype
    EXPECT_EQ(stats()["blasBuilds"], blas);
}
