#include "scene_adapter/collectionMembership.h"

#include <gtest/gtest.h>

#include "scene_adapter/usda/stage.h"

using namespace principled;
using adapter::CollectionMembership;

namespace {

struct Opened {
    std::unique_ptr<usd::Stage> stage;
    std::vector<std::string> warnings;
    explicit Opened(const std::string& text) : stage(usd::Stage::openString(text, "c.usda")) {}
    CollectionMembership collection(const std::string& path) {
        return CollectionMembership(*stage, path, [&](const std::string& where, const std::string& m) {
            warnings.push_back(where + ": " + m);
        });
    }
};

const char* kScene = R"(#usda 1.0
def Xform "World" (
    prepend apiSchemas = ["CollectionAPI:shiny", "CollectionAPI:exact", "CollectionAPI:outer", "CollectionAPI:all", "CollectionAPI:loop"]
)
{
    rel collection:shiny:includes = [</World/Robot>, </World/Lamp>]
    rel collection:shiny:excludes = </World/Robot/Eye>
    rel collection:exact:includes = </World/Robot>
    uniform token collection:exact:expansionRule = "explicitOnly"
    rel collection:outer:includes = [</World.collection:exact>, </World/Tree>]
    rel collection:outer:excludes = </World/Tree/Leaf>
    uniform bool collection:all:includeRoot = 1
    rel collection:all:excludes = </World/Lamp>
    rel collection:loop:includes = </World.collection:loop>
    def Xform "Robot" { def Mesh "Body" {} def Mesh "Eye" { def Mesh "Pupil" {} } }
    def Mesh "Lamp" {}
    def Xform "Tree" { def Mesh "Leaf" {} def Mesh "Trunk" {} }
}
)";

}  // namespace

TEST(CollectionMembership, IncludesExpandToDescendantsAndTheNearestRuleDecides) {
    Opened o(kScene);
    CollectionMembership c = o.collection("/World.collection:shiny");
    EXPECT_TRUE(c.includes("/World/Robot"));
    EXPECT_TRUE(c.includes("/World/Robot/Body"));
    EXPECT_FALSE(c.includes("/World/Robot/Eye"));
    EXPECT_FALSE(c.includes("/World/Robot/Eye/Pupil"));  // below an exclude
    EXPECT_TRUE(c.includes("/World/Lamp"));
    EXPECT_FALSE(c.includes("/World/Tree/Leaf"));
    EXPECT_FALSE(c.includes("/World"));  // an ancestor of a member is not a member
    EXPECT_TRUE(o.warnings.empty());
}

TEST(CollectionMembership, ExplicitOnlyHoldsTheListedPrimsOnly) {
    Opened o(kScene);
    CollectionMembership c = o.collection("/World.collection:exact");
    EXPECT_TRUE(c.includes("/World/Robot"));
    EXPECT_FALSE(c.includes("/World/Robot/Body"));
}

TEST(CollectionMembership, IncludedCollectionsMergeAndOwnExcludesWin) {
    Opened o(kScene);
    CollectionMembership c = o.collection("/World.collection:outer");
    EXPECT_TRUE(c.includes("/World/Robot"));
    EXPECT_FALSE(c.includes("/World/Robot/Body"));  // the included collection's explicitOnly
    EXPECT_TRUE(c.includes("/World/Tree/Trunk"));
    EXPECT_FALSE(c.includes("/World/Tree/Leaf"));
}

TEST(CollectionMembership, IncludeRootHoldsEverythingButThePseudoRoot) {
    Opened o(kScene);
    CollectionMembership c = o.collection("/World.collection:all");
    EXPECT_TRUE(c.includes("/World"));
    EXPECT_TRUE(c.includes("/World/Tree/Leaf"));
    EXPECT_FALSE(c.includes("/World/Lamp"));
    EXPECT_FALSE(c.includes("/"));
}

TEST(CollectionMembership, BadCollectionsAreReportedAndHoldNothing) {
    Opened o(kScene);
    CollectionMembership loop = o.collection("/World.collection:loop");
    EXPECT_FALSE(loop.includes("/World/Lamp"));
    ASSERT_EQ(o.warnings.size(), 1u);
    EXPECT_NE(o.warnings[0].find("includes itself"), std::string::npos) << o.warnings[0];
    CollectionMembership missing = o.collection("/Nowhere.collection:x");
    EXPECT_FALSE(missing.includes("/World/Lamp"));
    CollectionMembership notOne = o.collection("/World/Lamp");
    EXPECT_FALSE(notOne.includes("/World/Lamp"));
    EXPECT_EQ(o.warnings.size(), 3u);
}

TEST(CollectionMembership, SplitsCollectionPaths) {
    std::string prim, name;
    EXPECT_TRUE(CollectionMembership::splitCollectionPath("/A/B.collection:shiny", &prim, &name));
    EXPECT_EQ(prim, "/A/B");
    EXPECT_EQ(name, "shiny");
    EXPECT_FALSE(CollectionMembership::splitCollectionPath("/A/B.collection:", &prim, &name));
    EXPECT_FALSE(CollectionMembership::splitCollectionPath("/A/B.points", &prim, &name));
    EXPECT_FALSE(CollectionMembership::splitCollectionPath("A.collection:x", &prim, &name));
}
