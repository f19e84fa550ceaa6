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

TEST(CollectionMembership, IncludedCollectionsMergeInIncludeOrder) {
    // UsdCollectionAPI: the includes in order, an included collection's rules overwriting what
    // came before, then the excludes.
    Opened o(R"(#usda 1.0
def Xform "W" { def Mesh "M" {} }
def Scope "C" {
    rel collection:x:includes = </W>
    rel collection:x:excludes = </W/M>
    rel collection:y:includes = </W/M>
    rel collection:a:includes = [</W/M>, </C.collection:x>]
    rel collection:b:includes = [</C.collection:x>, </C.collection:y>]
}
)");
    EXPECT_FALSE(o.collection("/C.collection:a").includes("/W/M"));  // x's exclude came later
    EXPECT_TRUE(o.collection("/C.collection:b").includes("/W/M"));   // y's include came later
}

TEST(CollectionMembership, HostileNestingIsCutNotExponentialNorDeep) {
    // A diamond 100 levels deep (2^100 paths through it) and a chain 5000 collections long.
    std::string diamond = "#usda 1.0\ndef Xform \"W\" { def Mesh \"M\" {} }\ndef Scope \"C\" {\n";
    const int levels = 100;
    for (int i = 0; i < levels; ++i)
        for (const char* side : {"a", "b"})
            diamond += "    rel collection:l" + std::to_string(i) + side + ":includes = [</C.collection:l" +
                       std::to_string(i + 1) + "a>, </C.collection:l" + std::to_string(i + 1) + "b>]\n";
    diamond += "    rel collection:l100a:includes = </W/M>\n    rel collection:l100b:includes = </W/M>\n}\n";
    Opened d(diamond);
    // Nested deeper than kMaxNesting: the innermost collections are left out, with a warning.
    EXPECT_FALSE(d.collection("/C.collection:l0a").includes("/W/M"));
    EXPECT_TRUE(d.collection("/C.collection:l50a").includes("/W/M"));
    EXPECT_FALSE(d.warnings.empty());
    std::string chain = "#usda 1.0\ndef Xform \"W\" { def Mesh \"M\" {} }\ndef Scope \"C\" {\n";
    for (int i = 0; i < 5000; ++i)
        chain += "    rel collection:c" + std::to_string(i) + ":includes = </C.collection:c" + std::to_string(i + 1) + ">\n";
    chain += "    rel collection:c5000:includes = </W/M>\n}\n";
    Opened c(chain);
    EXPECT_FALSE(c.collection("/C.collection:c0").includes("/W/M"));
    EXPECT_TRUE(c.collection("/C.collection:c4990").includes("/W/M"));
}
