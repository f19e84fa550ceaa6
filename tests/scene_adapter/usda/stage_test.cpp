// SPDX-License-Identifier: Apache-2.0
// The consumer API on a single layer: prims, attributes, relationships, metadata, stage fields,
// time, traversal, errors.
#include "scene_adapter/usda/stage.h"

#include <gtest/gtest.h>

#include <cmath>

#include "testUtil.h"

namespace principled::usd {
namespace {

const char* kScene = R"(#usda 1.0
(
    defaultPrim = "World"
    upAxis = "Z"
    metersPerUnit = 1
    startTimeCode = 1
    endTimeCode = 24
    timeCodesPerSecond = 30
    customLayerData = { string copyright = "me" }
)
def Xform "World" ( kind = "assembly" ) {
    double3 xformOp:translate.timeSamples = { 1: (0, 0, 0), 11: (10, 0, 0) }
    double3 xformOp:translate = (5, 5, 5)
    uniform token[] xformOpOrder = ["xformOp:translate"]
    def Mesh "mesh" ( prepend apiSchemas = ["MaterialBindingAPI", "CollectionAPI:lightLink"] ) {
        int[] faceVertexCounts = [3]
        int[] faceVertexIndices = [0, 1, 2]
        point3f[] points = [(0, 0, 0), (1, 0, 0), (0, 1, 0)]
        texCoord2f[] primvars:st = [(0, 0), (1, 0), (0, 1)] ( interpolation = "faceVarying" )
        int visibleFrom.timeSamples = { 0: 1, 10: 5 }
        custom bool flag = false
        int[] blocked = None
        rel material:binding = </World/Looks/Mat>
    }
    def Scope "Looks" {
        def Material "Mat" {
            token outputs:surface.connect = </World/Looks/Mat/PBR.outputs:surface>
            def Shader "PBR" {
                uniform token info:id = "UsdPreviewSurface"
                color3f inputs:diffuseColor = (0.8, 0.1, 0.1)
                token outputs:surface
            }
        }
    }
}
)";

TEST(Stage, SingleLayerApi) {
    auto stage = Stage::openString(kScene, "scene.usda");
    EXPECT_EQ(stage->defaultPrim(), "World");
    EXPECT_EQ(stage->upAxis(), "Z");
    EXPECT_EQ(stage->metersPerUnit(), 1.0);
    EXPECT_EQ(stage->startTimeCode(), 1.0);
    EXPECT_EQ(stage->endTimeCode(), 24.0);
    EXPECT_EQ(stage->timeCodesPerSecond(), 30.0);
    EXPECT_TRUE(stage->hasTimeCodes());
    EXPECT_EQ(stage->defaultTime(), 1.0);
    EXPECT_EQ(*stage->layerMetadata("customLayerData")->find("copyright")->getString(), "me");
    EXPECT_EQ(stage->layerFiles(), (std::vector<std::string>{"scene.usda"}));
    EXPECT_TRUE(stage->warnings().empty());

    const Prim* root = stage->pseudoRoot();
    ASSERT_EQ(root->children().size(), 1u);
    const Prim* world = stage->prim("/World");
    EXPECT_EQ(world, root->children()[0]);
    EXPECT_EQ(world->parent(), root);
    EXPECT_EQ(world->name(), "World");
    EXPECT_EQ(world->typeName(), "Xform");
    EXPECT_EQ(*world->metadata("kind")->getString(), "assembly");
    EXPECT_EQ(world->location().str(), "scene.usda:11:1");
    EXPECT_TRUE(world->isDefined());
    EXPECT_TRUE(world->isActive());
    EXPECT_FALSE(world->isAbstract());

    const Prim* mesh = stage->prim("/World/mesh");
    ASSERT_NE(mesh, nullptr);
    EXPECT_EQ(mesh->appliedSchemas(),
              (std::vector<std::string>{"MaterialBindingAPI", "CollectionAPI:lightLink"}));
    EXPECT_TRUE(mesh->hasAPI("MaterialBindingAPI"));
    EXPECT_TRUE(mesh->hasAPI("CollectionAPI"));
    EXPECT_TRUE(mesh->hasAPI("CollectionAPI:lightLink"));
    EXPECT_FALSE(mesh->hasAPI("CollectionAPI:shadowLink"));
    EXPECT_FALSE(mesh->hasAPI("Material"));
    const Attribute* pts = mesh->attribute("points");
    ASSERT_NE(pts, nullptr);
    EXPECT_EQ(pts->typeName(), "point3f");
    EXPECT_TRUE(pts->isArray());
    EXPECT_TRUE(pts->hasValue());
    EXPECT_EQ(pts->get().size(), 3u);
    EXPECT_EQ(pts->location().str(), "scene.usda:18:9");
    const Attribute* st = mesh->attribute("primvars:st");
    EXPECT_EQ(*st->metadata("interpolation")->getString(), "faceVarying");
    EXPECT_EQ(st->get().components(), 2);
    EXPECT_TRUE(mesh->attribute("flag")->isCustom());
    EXPECT_EQ(mesh->attribute("flag")->get().getBool(), false);
    EXPECT_TRUE(world->attribute("xformOpOrder")->isUniform());
    EXPECT_FALSE(mesh->attribute("blocked")->hasValue());  // None is a block, not a value
    EXPECT_TRUE(mesh->attribute("blocked")->get().isNone());
    EXPECT_NE(mesh->attribute("blocked")->defaultValue(), nullptr);
    EXPECT_EQ(mesh->attribute("nope"), nullptr);
    EXPECT_EQ(mesh->relationship("material:binding")->targets(),
              (std::vector<std::string>{"/World/Looks/Mat"}));
    // attributes() is sorted by name
    std::vector<std::string> names;
    for (const Attribute* a : mesh->attributes()) names.push_back(a->name());
    EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
    EXPECT_EQ(names.size(), 7u);

    const Attribute* surface = stage->prim("/World/Looks/Mat")->attribute("outputs:surface");
    EXPECT_FALSE(surface->hasValue());
    EXPECT_EQ(surface->defaultValue(), nullptr);
    EXPECT_EQ(surface->connections(),
              (std::vector<std::string>{"/World/Looks/Mat/PBR.outputs:surface"}));
    auto color =
        stage->prim("/World/Looks/Mat/PBR")->attribute("inputs:diffuseColor")->get().getTuple();
    EXPECT_EQ(color->size(), 3u);
    EXPECT_NEAR((*color)[0], 0.8, 1e-12);

    std::vector<std::string> traversal;
    for (const Prim* p : stage->traverse()) traversal.push_back(p->path());
    EXPECT_EQ(traversal, (std::vector<std::string>{"/World", "/World/mesh", "/World/Looks",
                                                   "/World/Looks/Mat", "/World/Looks/Mat/PBR"}));
}

TEST(Stage, TimeRule) {
    auto stage = Stage::openString(kScene, "scene.usda");
    const Attribute* t = stage->prim("/World")->attribute("xformOp:translate");
    EXPECT_EQ(t->timeSamples().size(), 2u);
    EXPECT_TRUE(t->isTimeVarying());
    EXPECT_FALSE(stage->prim("/World/mesh")->attribute("points")->isTimeVarying());
    EXPECT_EQ((*t->get(6.0).getTuple())[0], 5.0);                   // interpolated
    EXPECT_EQ((*t->get(-3.0).getTuple())[0], 0.0);                  // held before
    EXPECT_EQ((*t->get(100.0).getTuple())[0], 10.0);                // held after
    EXPECT_EQ((*t->get(kDefaultTime).getTuple())[0], 5.0);          // the default value
    EXPECT_EQ((*t->get(stage->defaultTime()).getTuple())[0], 0.0);  // startTimeCode = 1
    const Attribute* held = stage->prim("/World/mesh")->attribute("visibleFrom");
    EXPECT_EQ(*held->get(9.9).getInt(), 1);           // ints are held, never interpolated
    EXPECT_EQ(*held->get(kDefaultTime).getInt(), 1);  // no default: the earliest sample

    auto noTime = Stage::openString("#usda 1.0\n", "empty.usda");
    EXPECT_TRUE(std::isnan(noTime->defaultTime()));
    EXPECT_FALSE(noTime->hasTimeCodes());
    EXPECT_EQ(noTime->upAxis(), "Y");
    EXPECT_EQ(noTime->metersPerUnit(), 0.01);
    EXPECT_EQ(noTime->timeCodesPerSecond(), 24.0);
    EXPECT_TRUE(noTime->pseudoRoot()->children().empty());
    auto legacy = Stage::openString(
        "#usda 1.0\n( startFrame = 3 endFrame = 9 framesPerSecond = 30 )\n", "legacy.usda");
    EXPECT_EQ(legacy->defaultTime(), 3.0);
    EXPECT_EQ(legacy->endTimeCode(), 9.0);
    EXPECT_EQ(legacy->timeCodesPerSecond(), 30.0);  // falls back to framesPerSecond
}

TEST(Stage, OpenErrors) {
    try {
        Stage::open("/nonexistent/dir/x.usda");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()), "/nonexistent/dir/x.usda: cannot open layer file");
    }
    EXPECT_EQ(test::parseErrorOf([] { Stage::openString("#usda 1.0\ndef \"A\" {", "bad.usda"); }),
              "bad.usda:2:10: expected '}', found end of file");
}

}  // namespace
}  // namespace principled::usd
