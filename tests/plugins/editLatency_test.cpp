// SPDX-License-Identifier: Apache-2.0
// Incremental commits (issue 7, edit latency): each host edit makes the render delegate redo
// only the tables it affects (read from the commit counters in renderStats()), the progressive
// pass restarts only when something visible changed, and the image after the edit equals a
// fresh render of the edited scene (same seed, same samples).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>

#include "plugins/renderSession.h"
#include "scene_adapter/stageEditor.h"

using namespace principled;
using adapter::EditValue;

namespace {

std::string defaultScene() {
    std::ifstream f(PRINCIPLED_DEFAULT_SCENE_PATH);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    if (at != std::string::npos) text.replace(at, from.size(), to);
    return text;
}

host::SessionOptions options() {
    host::SessionOptions o;
    o.width = 96;
    o.height = 54;
    o.samplesPerPixel = 2;
    o.seed = 3;
    return o;
}

void render(host::RenderSession& s) {
    for (int i = 0; i < 64 && !s.step(); ++i) {
    }
    ASSERT_TRUE(s.converged());
}

std::vector<float> image(const host::RenderSession& s) {
    const float* c = s.color();
    return std::vector<float>(c, c + size_t(s.width()) * s.height() * 4);
}

double maxDifference(const std::vector<float>& a, const std::vector<float>& b) {
    EXPECT_EQ(a.size(), b.size());
    double d = 0.0;
    for (size_t i = 0; i < a.size() && i < b.size(); ++i) d = std::max(d, std::abs(double(a[i]) - b[i]));
    return d;
}

std::map<std::string, double> delta(const std::map<std::string, double>& before,
                                    const std::map<std::string, double>& after) {
    std::map<std::string, double> d;
    for (const auto& [k, v] : after) d[k] = v - before.at(k);
    return d;
}

// Renders the default scene, applies `edit`, renders again; returns the counter deltas of the
// edit and checks the new image against a fresh session of `editedText`.
std::map<std::string, double> editAndCompare(const std::function<void(adapter::StageEditor&)>& edit,
                                             const std::string& editedText) {
    auto s = host::RenderSession::openString(defaultScene(), "default.usda", options());
    render(*s);
    std::vector<float> before = image(*s);
    auto stats0 = s->stats();
    edit(s->editor());
    render(*s);
    auto d = delta(stats0, s->stats());
    EXPECT_GT(d["samples"], 0.0) << "the pass did not restart after the edit";
    EXPECT_GT(maxDifference(before, image(*s)), 0.0) << "the edit did not change the image";
    auto fresh = host::RenderSession::openString(editedText, "edited.usda", options());
    render(*fresh);
    EXPECT_LE(maxDifference(image(*s), image(*fresh)), 1e-6) << "edited image != fresh render";
    return d;
}

}  // namespace

TEST(EditLatency, MaterialEditUpdatesOneRecordOnly) {
    auto d = editAndCompare(
        [](adapter::StageEditor& e) {
            e.setAttribute("/World/Looks/Reference/Surface", "inputs:diffuseColor", EditValue::of({0.1, 0.6, 0.2}));
        },
        replaced(defaultScene(), "color3f inputs:diffuseColor = (0.646, 0.415, 0.0177)",
                 "color3f inputs:diffuseColor = (0.1, 0.6, 0.2)"));
    EXPECT_EQ(d["materialUpdates"], 1);
    for (const char* k : {"materialTableBuilds", "materialBindings", "lightTableBuilds", "meshLightBuilds",
                          "lightDistributionBuilds", "instanceTableBuilds", "topLevelCommits", "blasBuilds",
                          "meshesRebuilt", "transformUpdates"})
        EXPECT_EQ(d[k], 0) << k;
}

TEST(EditLatency, LightEditRebuildsTheLightTableOnly) {
    auto d = editAndCompare(
        [](adapter::StageEditor& e) { e.setAttribute("/World/Sky", "inputs:intensity", EditValue::of({0.9})); },
        replaced(defaultScene(), "float inputs:intensity = 0.6", "float inputs:intensity = 0.9"));
    EXPECT_EQ(d["lightTableBuilds"], 1);
    EXPECT_EQ(d["lightDistributionBuilds"], 1);
    for (const char* k : {"materialTableBuilds", "materialUpdates", "materialBindings", "meshLightBuilds",
                          "instanceTableBuilds", "topLevelCommits", "blasBuilds", "meshesRebuilt"})
        EXPECT_EQ(d[k], 0) << k;
}

TEST(EditLatency, TransformEditCommitsTheTopLevelOnly) {
    auto d = editAndCompare(
        [](adapter::StageEditor& e) {
            e.setAttribute("/World/Reference", "xformOp:translate", EditValue::of({-3.45, 0.9, 0.2}));
        },
        replaced(defaultScene(), "double3 xformOp:translate = (-3.45, 0.5, 0)",
                 "double3 xformOp:translate = (-3.45, 0.9, 0.2)"));
    EXPECT_EQ(d["topLevelCommits"], 1);
    EXPECT_EQ(d["transformUpdates"], 1);
    for (const char* k : {"materialTableBuilds", "materialUpdates", "materialBindings", "lightTableBuilds",
                          "meshLightBuilds", "blasBuilds", "meshesRebuilt"})
        EXPECT_EQ(d[k], 0) << k;
}

TEST(EditLatency, CameraMoveCommitsNothingButRestartsThePass) {
    auto d = editAndCompare(
        [](adapter::StageEditor& e) {
            e.setAttribute("/World/Camera", "xformOp:translate", EditValue::of({0.3, 1.7, 9.0}));
        },
        replaced(defaultScene(), "double3 xformOp:translate = (0, 1.6, 9)",
                 "double3 xformOp:translate = (0.3, 1.7, 9)"));
    for (const char* k : {"commits", "materialTableBuilds", "materialUpdates", "lightTableBuilds",
                          "meshLightBuilds", "lightDistributionBuilds", "topLevelCommits", "blasBuilds",
                          "meshesRebuilt"})
        EXPECT_EQ(d[k], 0) << k;
}

TEST(EditLatency, NothingEditedNothingRestarted) {
    auto s = host::RenderSession::openString(defaultScene(), "default.usda", options());
    render(*s);
    auto stats0 = s->stats();
    std::vector<float> before = image(*s);
    s->step();
    auto d = delta(stats0, s->stats());
    EXPECT_EQ(d["samples"], 0);
    EXPECT_EQ(d["commits"], 0);
    EXPECT_EQ(maxDifference(before, image(*s)), 0.0);
}

// An emissive mesh is a light: editing its material's emission or moving it redoes the mesh
// lights and the distribution, and still matches a fresh render.
TEST(EditLatency, EmissiveMeshEditsRedoTheMeshLights) {
    const std::string scene = R"(#usda 1.0
(
    upAxis = "Y"
)
def Xform "World"
{
    def Camera "Cam"
    {
        double3 xformOp:translate = (0, 0, 10)
        uniform token[] xformOpOrder = ["xformOp:translate"]
    }
    def Mesh "Panel"
    {
        uniform token subdivisionScheme = "none"
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 1, 2, 3]
        point3f[] points = [(-1, 2, 1), (1, 2, 1), (1, 2, -1), (-1, 2, -1)]
        double3 xformOp:translate = (0, 0, 0)
        uniform token[] xformOpOrder = ["xformOp:translate"]
        rel material:binding = </World/Looks/Glow>
    }
    def Mesh "Floor"
    {
        uniform token subdivisionScheme = "none"
        int[] faceVertexCounts = [4]
        int[] faceVertexIndices = [0, 3, 2, 1]
        point3f[] points = [(-5, -1, 5), (5, -1, 5), (5, -1, -5), (-5, -1, -5)]
        rel material:binding = </World/Looks/Grey>
    }
    def Scope "Looks"
    {
        def Material "Glow"
        {
            token outputs:surface.connect = </World/Looks/Glow/S.outputs:surface>
            def Shader "S"
            {
                uniform token info:id = "UsdPreviewSurface"
                color3f inputs:emissiveColor = (4, 4, 4)
                token outputs:surface
            }
        }
        def Material "Grey"
        {
            token outputs:surface.connect = </World/Looks/Grey/S.outputs:surface>
            def Shader "S"
            {
                uniform token info:id = "UsdPreviewSurface"
                color3f inputs:diffuseColor = (0.5, 0.5, 0.5)
                token outputs:surface
            }
        }
    }
}
)";
    auto s = host::RenderSession::openString(scene, "glow.usda", options());
    render(*s);
    auto stats0 = s->stats();
    s->editor().setAttribute("/World/Looks/Glow/S", "inputs:emissiveColor", EditValue::of({2, 3, 4}));
    s->editor().setAttribute("/World/Panel", "xformOp:translate", EditValue::of({0.5, 0.5, 0}));
    render(*s);
    auto d = delta(stats0, s->stats());
    EXPECT_EQ(d["meshLightBuilds"], 1);
    EXPECT_EQ(d["lightDistributionBuilds"], 1);
    EXPECT_EQ(d["materialTableBuilds"], 0);
    EXPECT_EQ(d["lightTableBuilds"], 0);
    EXPECT_EQ(s->stats()["lights"], 1);
    std::string edited = replaced(scene, "color3f inputs:emissiveColor = (4, 4, 4)", "color3f inputs:emissiveColor = (2, 3, 4)");
    edited = replaced(edited, "double3 xformOp:translate = (0, 0, 0)", "double3 xformOp:translate = (0.5, 0.5, 0)");
    auto fresh = host::RenderSession::openString(edited, "glow2.usda", options());
    render(*fresh);
    EXPECT_LE(maxDifference(image(*s), image(*fresh)), 1e-6);
}
