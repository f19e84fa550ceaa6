// SPDX-License-Identifier: Apache-2.0
// usd::StageEdit: session-layer edits of a composed stage.
#include "scene_adapter/usda/stageEdit.h"

#include <gtest/gtest.h>

using namespace principled::usd;

namespace {

const char* kText = R"(#usda 1.0
def Xform "A"
{
    double radius.timeSamples = { 1: 1, 2: 2 }
    def Sphere "B"
    {
    }
}
)";

TEST(StageEdit, AnEditIsTheStrongestOpinionAtEveryTime) {
    auto stage = Stage::openString(kText, "t.usda");
    StageEdit edit(*stage);
    const Attribute* a = edit.setAttribute("/A", "radius", "double", false,
                                           Value::number("double", 5, StageEdit::location()));
    ASSERT_NE(a, nullptr);
    EXPECT_EQ(a, stage->prim("/A")->attribute("radius"));  // the same attribute, edited
    EXPECT_EQ(*a->get(1.0).getDouble(), 5.0);
    EXPECT_EQ(*a->get(kDefaultTime).getDouble(), 5.0);
    EXPECT_EQ(a->location().str(), "<host edit>");
}

TEST(StageEdit, NewAttributesAndRelationshipsAreFoundByName) {
    auto stage = Stage::openString(kText, "t.usda");
    StageEdit edit(*stage);
    edit.setAttribute("/A", "aaa", "float", false, Value::number("float", 1, {}));
    edit.setAttribute("/A", "zzz", "float", false, Value::number("float", 2, {}));
    edit.setRelationship("/A", "material:binding", {"/M"});
    const Prim* a = stage->prim("/A");
    ASSERT_NE(a->attribute("aaa"), nullptr);
    ASSERT_NE(a->attribute("zzz"), nullptr);
    EXPECT_NE(a->attribute("radius"), nullptr);  // lookup stays sorted
    ASSERT_NE(a->relationship("material:binding"), nullptr);
    EXPECT_EQ(a->relationship("material:binding")->targets(), std::vector<std::string>{"/M"});
    EXPECT_EQ(edit.setAttribute("/Nope", "x", "float", false, Value()), nullptr);
}

TEST(StageEdit, DefineAndRemovePrims) {
    auto stage = Stage::openString(kText, "t.usda");
    StageEdit edit(*stage);
    const Prim* c = edit.definePrim("/A/C", "Mesh");
    ASSERT_NE(c, nullptr);
    EXPECT_TRUE(c->isDefined());
    EXPECT_EQ(c->parent(), stage->prim("/A"));
    EXPECT_EQ(stage->prim("/A")->children().back(), c);
    EXPECT_EQ(edit.definePrim("/A/C", "Mesh"), nullptr);  // taken
    EXPECT_EQ(edit.definePrim("/X/Y", "Mesh"), nullptr);  // no parent
    const Prim* b = stage->prim("/A/B");
    EXPECT_TRUE(edit.removePrim("/A"));
    EXPECT_EQ(stage->prim("/A"), nullptr);
    EXPECT_EQ(stage->prim("/A/B"), nullptr);
    EXPECT_TRUE(stage->pseudoRoot()->children().empty());
    EXPECT_EQ(b->path(), "/A/B");  // still allocated: readers' pointers stay valid
    EXPECT_FALSE(edit.removePrim("/A"));
    EXPECT_FALSE(edit.removePrim("/"));
}

}  // namespace
