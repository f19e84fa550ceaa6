#include "scene_adapter/materialBinding.h"

#include <gtest/gtest.h>

#include "scene_adapter/usda/stage.h"

using namespace principled;

namespace {

struct Resolved {
    std::unique_ptr<usd::Stage> stage;
    std::vector<std::string> warnings;
    std::unique_ptr<adapter::MaterialBindingResolver> resolver;
    explicit Resolved(const std::string& body) {
        stage = usd::Stage::openString("#usda 1.0\n" + body + R"(
def Scope "Looks" {
    def Material "A" {}
    def Material "B" {}
    def Material "C" {}
    def Material "D" {}
    def Shader "NotAMaterial" {}
}
)", "b.usda");
        resolver = std::make_unique<adapter::MaterialBindingResolver>(
            *stage, [this](const std::string& w, const std::string& m) { warnings.push_back(w + ": " + m); });
    }
    std::string operator()(const std::string& path) const { return resolver->resolve(*stage->prim(path)); }
};

}  // namespace

TEST(MaterialBinding, NearestDirectBindingWinsUnlessAnAncestorsIsStronger) {
    Resolved r(R"(
def Xform "Weak" {
    rel material:binding = </Looks/A>
    def Mesh "Own" { rel material:binding = </Looks/B> }
    def Mesh "Inherits" {}
}
def Xform "Strong" {
    rel material:binding = </Looks/A> ( bindMaterialAs = "strongerThanDescendants" )
    def Xform "Mid" {
        rel material:binding = </Looks/C> ( bindMaterialAs = "strongerThanDescendants" )
        def Mesh "Own" { rel material:binding = </Looks/B> }
    }
}
)");
    EXPECT_EQ(r("/Weak/Own"), "/Looks/B");
    EXPECT_EQ(r("/Weak/Inherits"), "/Looks/A");
    EXPECT_EQ(r("/Strong/Mid/Own"), "/Looks/A");  // the outermost strong binding
}

TEST(MaterialBinding, TheFullPurposeIsResolvedBeforeAllPurposeBindings) {
    Resolved r(R"(
def Xform "Group" {
    rel material:binding:full = </Looks/C>
    def Mesh "Own" { rel material:binding = </Looks/B> }
}
def Mesh "Both" {
    rel material:binding = </Looks/B>
    rel material:binding:full = </Looks/D>
}
def Mesh "PreviewOnly" { rel material:binding:preview = </Looks/D> }
)");
    EXPECT_EQ(r("/Group/Own"), "/Looks/C");  // a full binding anywhere above beats all-purpose ones
    EXPECT_EQ(r("/Both"), "/Looks/D");
    EXPECT_EQ(r("/PreviewOnly"), "");  // other purposes are not ours
}

TEST(MaterialBinding, CollectionBindingsApplyToMembersBelowTheBindingPrim) {
    Resolved r(R"(
def Xform "Set" (
    prepend apiSchemas = ["MaterialBindingAPI", "CollectionAPI:metal", "CollectionAPI:glass"]
)
{
    rel collection:metal:includes = [</Set/Robot>, </Elsewhere>]
    rel collection:metal:excludes = </Set/Robot/Eye>
    rel collection:glass:includes = </Set/Robot/Eye>
    rel material:binding:collection:metal = [</Set.collection:metal>, </Looks/B>]
    rel material:binding:collection:glass = [</Set.collection:glass>, </Looks/C>]
    rel material:binding = </Looks/A>
    def Xform "Robot" {
        def Mesh "Body" {}
        def Mesh "Eye" {}
        def Mesh "Arm" { rel material:binding = </Looks/D> }
    }
    def Mesh "Floor" {}
}
def Mesh "Elsewhere" {}
)");
    EXPECT_EQ(r("/Set/Robot/Body"), "/Looks/B");
    EXPECT_EQ(r("/Set/Robot/Eye"), "/Looks/C");
    EXPECT_EQ(r("/Set/Robot/Arm"), "/Looks/D");   // a nearer direct binding beats the collection's
    EXPECT_EQ(r("/Set/Floor"), "/Looks/A");       // not a member: the direct binding above
    EXPECT_EQ(r("/Elsewhere"), "");                // a member, but the binding is not above it
    EXPECT_TRUE(r.warnings.empty());
}

TEST(MaterialBinding, OnOnePrimTheCollectionBindingBeatsTheDirectOneAndNameOrderDecides) {
    Resolved r(R"(
def Mesh "M" (
    prepend apiSchemas = ["MaterialBindingAPI", "CollectionAPI:self"]
)
{
    rel collection:self:includes = </M>
    rel material:binding = </Looks/A>
    rel material:binding:collection:b10 = [</M.collection:self>, </Looks/C>]
    rel material:binding:collection:B9 = [</M.collection:self>, </Looks/B>]
}
def Xform "Strong" {
    rel collection:c:includes = </Strong/Leaf>
    rel material:binding:collection:c = [</Strong.collection:c>, </Looks/C>] ( bindMaterialAs = "strongerThanDescendants" )
    def Mesh "Leaf" { rel material:binding = </Looks/A> }
}
)");
    EXPECT_EQ(r("/M"), "/Looks/B");  // B9 before b10 in dictionary order
    EXPECT_EQ(r("/Strong/Leaf"), "/Looks/C");
}

TEST(MaterialBinding, BindingsToWhatIsNotAMaterialAreReportedAndSkipped) {
    Resolved r(R"(
def Xform "G" {
    rel material:binding = </Looks/A>
    def Mesh "Bad" { rel material:binding = </Looks/NotAMaterial> }
}
)");
    EXPECT_EQ(r("/G/Bad"), "/Looks/A");
    ASSERT_EQ(r.warnings.size(), 1u);
    EXPECT_NE(r.warnings[0].find("not a Material"), std::string::npos);
    EXPECT_NE(r.warnings[0].find("/G/Bad"), std::string::npos);
}

TEST(MaterialBinding, InheritedKeysMatchWhereDescendantsResolveAlike) {
    Resolved r(R"(
def Xform "One" { rel material:binding = </Looks/A>
    def Xform "Inst" {} }
def Xform "Two" { rel material:binding = </Looks/A>
    def Xform "Deeper" { def Xform "Inst" {} } }
def Xform "Three" { rel material:binding = </Looks/A> ( bindMaterialAs = "strongerThanDescendants" )
    def Xform "Inst" {} }
def Xform "Four" { rel collection:c:includes = </Four/Inst>
    rel material:binding:collection:c = [</Four.collection:c>, </Looks/B>]
    def Xform "Inst" {} }
)");
    auto key = [&](const std::string& p) { return r.resolver->inheritedKey(*r.stage->prim(p)); };
    EXPECT_EQ(key("/One/Inst"), key("/Two/Deeper/Inst"));
    EXPECT_NE(key("/One/Inst"), key("/Three/Inst"));
    EXPECT_NE(key("/Four/Inst"), key("/One/Inst"));
}

TEST(MaterialBinding, CollectionBindingTargetsMayComeInEitherOrderAndDirectOnesNameOne) {
    Resolved r(R"(
def Xform "G" {
    rel collection:c:includes = </G/A>
    rel material:binding:collection:c = [</Looks/B>, </G.collection:c>]
    def Mesh "A" {}
}
def Mesh "Two" { rel material:binding = [</Looks/A>, </Looks/B>] }
)");
    EXPECT_EQ(r("/G/A"), "/Looks/B");
    EXPECT_EQ(r("/Two"), "");  // a direct binding with two targets is not a binding
    ASSERT_EQ(r.warnings.size(), 1u);
    EXPECT_NE(r.warnings[0].find("2 targets"), std::string::npos);
}

TEST(MaterialBinding, InheritedKeysFollowWhatIsPassedDownNotHowItIsWritten) {
    // An instance repeating its parent's binding passes down the same material as one that
    // inherits it: they share a prototype.
    Resolved r(R"(
def Xform "P" { rel material:binding = </Looks/A>
    def Xform "Repeats" { rel material:binding = </Looks/A> }
    def Xform "Inherits" {} }
)");
    auto key = [&](const std::string& p) { return r.resolver->inheritedKey(*r.stage->prim(p)); };
    EXPECT_EQ(key("/P/Repeats"), key("/P/Inherits"));
}
