#include "scene_adapter/purpose.h"

#include <gtest/gtest.h>

#include "scene_adapter/lightTypes.h"
#include "scene_adapter/usda/stage.h"

using namespace principled;

namespace {

const char* kScene = R"(#usda 1.0
def Xform "Guides"
{
    uniform token purpose = "guide"
    def Mesh "Cage" {}
    def Mesh "Shown" { uniform token purpose = "render" }
    def SphereLight "Lamp" {}
    def GeometryLight "Legacy" {}
    def Camera "Cam" {}
    def Material "Look" {}
}
def Xform "Proxy" { uniform token purpose = "proxy" def Mesh "Low" {} }
def Mesh "Plain" {}
)";

}  // namespace

TEST(Purpose, OwnValueElseNearestAncestor) {
    auto stage = usd::Stage::openString(kScene, "p.usda");
    ASSERT_TRUE(stage);
    auto drawn = [&](const char* path) { return adapter::renderPurpose(*stage->prim(path), 0.0); };
    EXPECT_FALSE(drawn("/Guides/Cage"));
    EXPECT_TRUE(drawn("/Guides/Shown"));
    EXPECT_FALSE(drawn("/Proxy/Low"));
    EXPECT_TRUE(drawn("/Plain"));
}

TEST(Purpose, OnlyTheLightsTheAdapterDrawsAreExempt) {
    auto stage = usd::Stage::openString(kScene, "p.usda");
    ASSERT_TRUE(stage);
    auto drawn = [&](const char* path) { return adapter::renderPurpose(*stage->prim(path), 0.0); };
    EXPECT_TRUE(drawn("/Guides/Lamp"));
    EXPECT_TRUE(drawn("/Guides/Cam"));
    EXPECT_TRUE(drawn("/Guides/Look"));
    // A type named "...Light" that is not one of the UsdLux lights drawn follows its purpose.
    EXPECT_FALSE(drawn("/Guides/Legacy"));
    EXPECT_TRUE(adapter::lightTypeOf("GeometryLight").empty());
    EXPECT_FALSE(adapter::lightTypeOf("DomeLight_1").empty());
}
