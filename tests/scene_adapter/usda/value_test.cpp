// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/value.h"

#include <gtest/gtest.h>

#include <cmath>

namespace principled::usd {
namespace {

TEST(Value, EmptyAndNone) {
    Value empty;
    EXPECT_TRUE(empty.isEmpty());
    EXPECT_TRUE(empty.isNone());
    EXPECT_EQ(empty.size(), 0u);
    EXPECT_FALSE(empty.getDouble());
    Value none = Value::none("float", true, {"f.usda", 3, 4});
    EXPECT_FALSE(none.isEmpty());
    EXPECT_TRUE(none.isNone());
    EXPECT_TRUE(none.isArray());
    EXPECT_EQ(none.typeName(), "float");
    EXPECT_EQ(none.location().str(), "f.usda:3:4");
    EXPECT_EQ(none.toString(), "None");
}

TEST(Value, NumberGetters) {
    Value b = Value::number("bool", 1, {});
    EXPECT_EQ(b.getBool(), true);
    EXPECT_EQ(b.getInt(), 1);
    Value i = Value::number("int", 3, {});
    EXPECT_FALSE(i.getBool());  // only 0/1 convert
    EXPECT_EQ(i.getInt(), 3);
    EXPECT_EQ(i.getDouble(), 3.0);
    Value zero = Value::number("int", 0, {});
    EXPECT_EQ(zero.getBool(), false);
    Value f = Value::number("float", 2.5, {});
    EXPECT_FALSE(f.getInt());
    EXPECT_EQ(f.getDouble(), 2.5);
    EXPECT_EQ(Value::number("double", 4.0, {}).getInt(), 4);  // exact-integer floats
    EXPECT_FALSE(Value::number("double", 1e300, {}).getInt());
    EXPECT_FALSE(f.getString());
    EXPECT_FALSE(f.getTuple());
    EXPECT_EQ(f.numbers(), nullptr);
    EXPECT_EQ(f.size(), 1u);
}

TEST(Value, TuplesArraysStrings) {
    Value t = Value::tuple("float3", {1, 2, 3}, {});
    EXPECT_EQ(*t.getTuple(), (std::vector<double>{1, 2, 3}));
    EXPECT_EQ(t.components(), 3);
    EXPECT_EQ(t.toString(), "(1, 2, 3)");
    Value a = Value::numberArray("point3f", 3, {1, 2, 3, 4, 5, 6}, {});
    EXPECT_TRUE(a.isArray());
    EXPECT_EQ(a.size(), 2u);
    EXPECT_EQ(a.numbers()->size(), 6u);
    Value copy = a;  // shares storage
    EXPECT_EQ(copy.numbers(), a.numbers());
    Value s = Value::string("token", "x", {});
    EXPECT_EQ(s.getString(), "x");
    EXPECT_EQ(s.toString(), "\"x\"");
    Value ss = Value::stringArray("string", {"a", "b"}, {});
    EXPECT_EQ(ss.size(), 2u);
    EXPECT_EQ(ss.strings()->at(1), "b");
    Value asset = Value::asset({"a.png", "/abs/a.png"}, {});
    EXPECT_EQ(asset.getAsset()->resolved, "/abs/a.png");
    EXPECT_EQ(asset.typeName(), "asset");
    Value assets = Value::assetArray({{"a", "/a"}, {"b", ""}}, {});
    EXPECT_EQ(assets.strings()->at(1), "b");
    EXPECT_EQ(assets.assets()->at(0).resolved, "/a");
    Value p = Value::path("/A/B", {});
    EXPECT_EQ(p.getPath(), "/A/B");
    EXPECT_FALSE(p.getString());
}

TEST(Value, Equality) {
    EXPECT_EQ(Value::number("float", 1, {"a", 1, 1}), Value::number("float", 1, {"b", 2, 2}));
    EXPECT_NE(Value::number("float", 1, {}), Value::number("double", 1, {}));
    EXPECT_NE(Value::number("float", 1, {}), Value::number("float", 2, {}));
    EXPECT_EQ(Value::number("float", std::nan(""), {}), Value::number("float", std::nan(""), {}));
    Value a = Value::numberArray("point3f", 3, {1, 2, 3}, {});
    EXPECT_EQ(a, Value(a));
    EXPECT_EQ(a, Value::numberArray("point3f", 3, {1, 2, 3}, {}));
    EXPECT_NE(a, Value::numberArray("point3f", 3, {1, 2, 4}, {}));
    EXPECT_NE(a, Value::none("point3f", true, {}));
    EXPECT_EQ(Value::string("token", "x", {}), Value::string("token", "x", {}));
    EXPECT_NE(Value::string("token", "x", {}), Value::string("string", "x", {}));
    EXPECT_EQ(Value(), Value());
    Dictionary d{{"k", Value::number("int", 1, {})}};
    EXPECT_EQ(Value::dictionary(d, {}), Value::dictionary(d, {}));
}

TEST(Value, Dictionaries) {
    Dictionary inner{{"n", Value::number("int", 2, {})}};
    Dictionary d{{"s", Value::string("string", "x", {})}, {"inner", Value::dictionary(inner, {})}};
    Value v = Value::dictionary(d, {});
    ASSERT_NE(v.dictionary(), nullptr);
    EXPECT_EQ(v.size(), 2u);
    EXPECT_EQ(v.find("inner")->find("n")->getInt(), 2);
    EXPECT_EQ(v.find("missing"), nullptr);
    EXPECT_EQ(Value::number("int", 1, {}).find("x"), nullptr);
    EXPECT_NE(v.toString().find("s = \"x\""), std::string::npos);
}

}  // namespace
}  // namespace principled::usd
