// SPDX-License-Identifier: Apache-2.0
// Valid USDA that OpenUSD's text parser (pxr/usd/sdf/textFileFormatParser.h) accepts and that
// we once refused or read wrongly (QA report on the USDA grammar); one test per finding.
#include <gtest/gtest.h>

#include <cmath>

#include "scene_adapter/usda/lexer.h"
#include "scene_adapter/usda/parser.h"
#include "scene_adapter/usda/stage.h"
#include "scene_adapter/usda/utf8.h"
#include "testUtil.h"

namespace principled::usd {
namespace {

std::unique_ptr<Layer> parse(std::string_view text) {
    return parseLayer(text, "t.usda", "/tmp");
}

std::string errorOf(std::string_view text) {
    return test::parseErrorOf([&] { parse(text); });
}

TEST(OpenUsdGrammar, Utf8SequenceLength) {
    EXPECT_EQ(utf8SequenceLength("\xC3\xA9", 0), 2u);          // é
    EXPECT_EQ(utf8SequenceLength("\xE5\x90\x8D", 0), 3u);      // 名
    EXPECT_EQ(utf8SequenceLength("\xF0\x9F\x98\x80", 0), 4u);  // U+1F600
    EXPECT_EQ(utf8SequenceLength("a", 0), 0u);
    EXPECT_EQ(utf8SequenceLength("\xA9", 0), 0u);              // lone continuation byte
    EXPECT_EQ(utf8SequenceLength("\xC0\xAF", 0), 0u);          // overlong '/'
    EXPECT_EQ(utf8SequenceLength("\xE0\x80\xAF", 0), 0u);      // overlong '/'
    EXPECT_EQ(utf8SequenceLength("\xED\xA0\x80", 0), 0u);      // surrogate D800
    EXPECT_EQ(utf8SequenceLength("\xF4\x90\x80\x80", 0), 0u);  // above U+10FFFF
    EXPECT_EQ(utf8SequenceLength("\xE5\x90", 0), 0u);          // cut short
    EXPECT_EQ(utf8SequenceLength("\xFF", 0), 0u);
}

TEST(OpenUsdGrammar, Utf8Identifiers) {
    auto layer = parse(R"(#usda 1.0
def Xform "W" (
    customData = { int clé = 1 }
    variants = { string vé = "x" }
)
{
    float café = 1
    texCoord2f[] primvars:ñ:名 = [(0, 1)]
    rel matériau = </W>
}
)");
    const PrimSpec* w = layer->prim("/W");
    ASSERT_NE(w, nullptr);
    ASSERT_NE(w->attribute("café"), nullptr);
    EXPECT_EQ(*w->attribute("café")->defaultValue->getDouble(), 1.0);
    EXPECT_NE(w->attribute("primvars:ñ:名"), nullptr);
    EXPECT_NE(w->relationship("matériau"), nullptr);
    EXPECT_EQ(*w->metadata.at("customData").find("clé")->getInt(), 1);
    EXPECT_EQ(w->variantSelections.at("vé"), "x");
}

TEST(OpenUsdGrammar, MalformedUtf8InAnIdentifierIsALocatedError) {
    EXPECT_EQ(errorOf("#usda 1.0\ndef \"W\" {\n    float caf\xC3 = 1\n}\n"),
              "t.usda:3:14: expected a well-formed UTF-8 character in an identifier, found "
              "'\\xc3'");
    EXPECT_EQ(errorOf("#usda 1.0\ndef \"W\" {\n    float \xFF = 1\n}\n"),
              "t.usda:3:11: expected a well-formed UTF-8 character in an identifier, found "
              "'\\xff'");
}

TEST(OpenUsdGrammar, EmptySymmetryFunction) {
    // Sdf writes `symmetryFunction = ` for an empty token: the identifier is optional and must
    // be on the line of the '='.
    auto layer = parse(R"(#usda 1.0
def Xform "W" (
    symmetryFunction =
    kind = "component"
)
{
    float a = 1 (
        symmetryFunction =
        displayUnit = mm
    )
    float b = 2 (symmetryFunction = mirrorX; permission = private)
    float c = 3 (symmetryFunction =)
}
)");
    const PrimSpec* w = layer->prim("/W");
    EXPECT_EQ(*w->metadata.at("symmetryFunction").getString(), "");
    EXPECT_EQ(*w->metadata.at("kind").getString(), "component");
    EXPECT_EQ(*w->attribute("a")->metadata.at("symmetryFunction").getString(), "");
    EXPECT_EQ(*w->attribute("a")->metadata.at("displayUnit").getString(), "mm");
    EXPECT_EQ(*w->attribute("b")->metadata.at("symmetryFunction").getString(), "mirrorX");
    EXPECT_EQ(*w->attribute("b")->metadata.at("permission").getString(), "private");
    EXPECT_EQ(*w->attribute("c")->metadata.at("symmetryFunction").getString(), "");
    // permission and displayUnit require their identifier on the same line.
    EXPECT_EQ(errorOf("#usda 1.0\ndef \"W\" (\n    permission =\n    kind = \"x\"\n) {}\n"),
              "t.usda:4:5: expected an identifier after 'permission =' on line 3, found 'kind'");
}

TEST(OpenUsdGrammar, StringEscapesAsTfEscapeString) {
    // Octal: one to three digits, one byte.
    EXPECT_EQ(unescapeString(R"("invisib\154e")"), "invisible");
    EXPECT_EQ(unescapeString(R"("a\012b")"), "a\nb");
    EXPECT_EQ(unescapeString(R"("\0")"), std::string(1, '\0'));
    EXPECT_EQ(unescapeString(R"("\1012")"), "A2");                     // at most three digits
    EXPECT_EQ(unescapeString(R"("\18")"), std::string("\x01") + "8");  // 8 is not octal
    EXPECT_EQ(unescapeString(R"("\777")"), "\xFF");                    // modulo 256
    // Hex: every hex digit that follows, modulo 256.
    EXPECT_EQ(unescapeString(R"("\x6c")"), "l");
    EXPECT_EQ(unescapeString(R"("\x4142")"), "B");  // 0x4142 & 0xFF
    EXPECT_EQ(unescapeString(R"("\x41g")"), "Ag");
    EXPECT_EQ(unescapeString(R"("\xg")"), std::string("\0g", 2));
    // The rest: C escapes, and any other character stands for itself.
    EXPECT_EQ(unescapeString(R"("\a\b\f\n\r\t\v\\\"\'\q")"), "\a\b\f\n\r\t\v\\\"'q");
    auto layer = parse("#usda 1.0\ndef \"W\" {\n    token visibility = \"invisib\\154e\"\n}\n");
    EXPECT_EQ(*layer->prim("/W")->attribute("visibility")->defaultValue->getString(), "invisible");
}

TEST(OpenUsdGrammar, EscapedTripleAtInAssetPath) {
    auto layer = parse(R"(#usda 1.0
def "A" ( references = @@@./a\@@@b.usda@@@ ) {
    asset t = @@@tex\@@@1.png@@@
    asset u = @@@tex@1.png@@@
}
)");
    const PrimSpec* a = layer->prim("/A");
    ASSERT_EQ(a->references.explicitItems.size(), 1u);
    EXPECT_EQ(a->references.explicitItems[0].assetPath, "./a@@@b.usda");
    EXPECT_EQ(a->attribute("t")->defaultValue->getAsset()->authored, "tex@@@1.png");
    EXPECT_EQ(a->attribute("u")->defaultValue->getAsset()->authored, "tex@1.png");
}

TEST(OpenUsdGrammar, UnregisteredMetadataOfAnyShape) {
    auto layer = parse(R"(#usda 1.0
(
    myStudio:layerTags = [(a, "b"), [None]]
)
def Xform "W" (
    myStudio:tags = ("hero", "lod0")
    myStudio:ids = (a, b)
    myStudio:grid = [[1, 2], [3, 4]]
    myStudio:mixed = [1, "a"]
    myStudio:shapes = [(1, 2), (1, 2, 3),]
    myStudio:none = [None]
    myStudio:numbers = [1, 2]
)
{
    float a = 1 (myStudio:pair = ("x", 2))
}
)");
    auto text = [](const Value& v) {
        EXPECT_EQ(v.typeName(), "unregistered");
        return v.getString().value_or("?");
    };
    EXPECT_EQ(text(*layer->field("myStudio:layerTags")), R"([(a, "b"), [None]])");
    const PrimSpec* w = layer->prim("/W");
    EXPECT_EQ(text(w->metadata.at("myStudio:tags")), R"(("hero", "lod0"))");
    EXPECT_EQ(text(w->metadata.at("myStudio:ids")), "(a, b)");
    EXPECT_EQ(text(w->metadata.at("myStudio:grid")), "[[1, 2], [3, 4]]");
    EXPECT_EQ(text(w->metadata.at("myStudio:mixed")), R"([1, "a"])");
    EXPECT_EQ(text(w->metadata.at("myStudio:shapes")), "[(1, 2), (1, 2, 3),]");
    EXPECT_EQ(text(w->metadata.at("myStudio:none")), "[None]");
    EXPECT_EQ(w->metadata.at("myStudio:numbers").size(), 2u);  // still a number array
    EXPECT_EQ(text(w->attribute("a")->metadata.at("myStudio:pair")), R"(("x", 2))");
    // Registered fields keep their checks; text that is no value at all is still an error.
    EXPECT_EQ(errorOf("#usda 1.0\ndef \"W\" (\n    kind = [1, \"a\"]\n) {}\n"),
              "t.usda:3:16: expected array elements of one type, found '\"a\"'");
    EXPECT_EQ(errorOf("#usda 1.0\ndef \"W\" (\n    my:x = [1, (2, }]\n) {}\n"),
              "t.usda:3:20: expected a value, found '}'");
}

TEST(OpenUsdGrammar, UsdaVersionsUpTo1_1) {
    for (const char* header : {"#usda 1.0", "#usda 1.1", "#usda 1.0.3", "#usda  1.1 "})
        EXPECT_NO_THROW(parse(std::string(header) + "\ndef \"W\" {}\n")) << header;
    const std::string expected =
        "expected a USDA version from 1.0 to 1.1 (the versions this reader supports), found ";
    EXPECT_EQ(errorOf("#usda 1.2\n"), "t.usda:1:1: " + expected + "'#usda 1.2'");
    EXPECT_EQ(errorOf("#usda 1.1.1\n"), "t.usda:1:1: " + expected + "'#usda 1.1.1'");
    EXPECT_EQ(errorOf("#usda 0.9\n"), "t.usda:1:1: " + expected + "'#usda 0.9'");
    EXPECT_EQ(errorOf("#usda 1.0 extra\n"),
              "t.usda:1:1: expected '#usda 1.0', found '#usda 1.0 extra'");
    EXPECT_EQ(errorOf("#usda 1\n"), "t.usda:1:1: expected '#usda 1.0', found '#usda 1'");
}

TEST(OpenUsdGrammar, GroupValueType) {
    auto layer =
        parse("#usda 1.0\ndef Shader \"S\" {\n    group inputs:g\n    opaque inputs:o\n}\n");
    const AttributeSpec* g = layer->prim("/S")->attribute("inputs:g");
    ASSERT_NE(g, nullptr);
    EXPECT_EQ(g->typeName, "group");
    EXPECT_FALSE(g->defaultValue.has_value());
    EXPECT_EQ(errorOf("#usda 1.0\ndef \"S\" {\n    group g = 1\n}\n"),
              "t.usda:3:15: expected no value for an attribute of valueless type 'group', "
              "found '1'");
}

TEST(OpenUsdGrammar, AnimationBlockBlocksWeakerTimeSamplesOnly) {
    auto stage = Stage::openString(R"(#usda 1.0
def "Base" {
    double a = 1
    double a.timeSamples = { 1: 10, 2: 20 }
    double b.timeSamples = { 1: 10 }
    double c.timeSamples = { 1: 10 }
}
def "A" ( references = </Base> ) {
    double a = AnimationBlock
    double b = AnimationBlock
    double b.timeSamples = { 1: 5 }
    double c = AnimationBlock
}
)",
                                   "t.usda");
    const Prim* a = stage->prim("/A");
    ASSERT_NE(a, nullptr);
    // The block hides Base's samples and lets Base's default through.
    EXPECT_TRUE(a->attribute("a")->timeSamples().empty());
    EXPECT_EQ(a->attribute("a")->get(1.0).getDouble(), 1.0);
    EXPECT_EQ(a->attribute("a")->get().getDouble(), 1.0);
    // Samples in the blocking spec itself still win.
    EXPECT_EQ(a->attribute("b")->get(1.0).getDouble(), 5.0);
    // Nothing left: no value.
    EXPECT_FALSE(a->attribute("c")->hasValue());
    EXPECT_EQ(stage->prim("/Base")->attribute("a")->get(2.0).getDouble(), 20.0);
    auto layer = parse("#usda 1.0\ndef \"W\" {\n    double a = AnimationBlock\n}\n");
    EXPECT_TRUE(layer->prim("/W")->attribute("a")->animationBlock);
    EXPECT_FALSE(layer->prim("/W")->attribute("a")->defaultValue.has_value());
}

TEST(OpenUsdGrammar, TupleWithATrailingComma) {
    auto layer = parse(R"(#usda 1.0
def "W" {
    float3 a = (1, 2, 3,)
    float2[] b = [(1, 2,), (3, 4)]
    matrix2d m = ((1, 0,), (0, 1,),)
}
)");
    const PrimSpec* w = layer->prim("/W");
    EXPECT_EQ(*w->attribute("a")->defaultValue->getTuple(), (std::vector<double>{1, 2, 3}));
    EXPECT_EQ(*w->attribute("b")->defaultValue->numbers(), (std::vector<double>{1, 2, 3, 4}));
    EXPECT_EQ(*w->attribute("m")->defaultValue->getTuple(), (std::vector<double>{1, 0, 0, 1}));
    EXPECT_EQ(errorOf("#usda 1.0\ndef \"W\" {\n    float3 a = (1, 2,,)\n}\n"),
              "t.usda:3:22: expected a number, found ','");
}

TEST(OpenUsdGrammar, ClassicMacLineEnds) {
    // A lone CR ends a line everywhere: the header, '#' and '//' comments, statements, and in
    // line counting (also inside block comments and triple-quoted strings).
    auto layer = parse(
        "#usda 1.0\r( doc = \"\"\"a\rb\"\"\" )\r# comment\rdef Xform \"W\" // x\r{\r"
        "    /* c\r c */ float a = 1\r    float b\r    float c = 2\r}\r");
    const PrimSpec* w = layer->prim("/W");
    ASSERT_NE(w, nullptr);
    EXPECT_EQ(*w->attribute("a")->defaultValue->getDouble(), 1.0);
    EXPECT_FALSE(w->attribute("b")->defaultValue.has_value());
    EXPECT_EQ(*w->attribute("c")->defaultValue->getDouble(), 2.0);
    EXPECT_EQ(w->attribute("c")->location.str(), "t.usda:10:5");
    EXPECT_EQ(*layer->field("doc")->getString(), "a\rb");
    EXPECT_EQ(errorOf("#usda 1.0\rdef \"W\" {\r    float a = x\r}\r"),
              "t.usda:3:15: expected a number, found 'x'");
    EXPECT_EQ(errorOf("#usda 1.0\rdef \"W\" {\r    string s = \"ab\rc\"\r}\r"),
              "t.usda:3:19: expected '\"' closing the string opened at 3:16, found end of line");
    EXPECT_EQ(errorOf("#usda 1.0\r\rdef \"W\" {\r\n}\r\n}"),
              "t.usda:5:1: expected 'def', 'over' or 'class', found '}'");
}

TEST(OpenUsdGrammar, ValueConversionsOfSdfParserHelpers) {
    auto layer = parse(R"(#usda 1.0
def "A" {
    bool t1 = True
    bool t2 = "YES"
    bool t3 = 2.5
    bool t4 = nan
    bool f1 = no
    bool f2 = "0"
    bool f3 = 0.0
    bool[] bs = [true, FALSE, "yes", 0]
    int i1 = 1.9
    int i2 = -1.9
    int i3 = 2.5e3
    uint u = 7.5
    int2 i4 = (1.5, -2.5)
    float x = "-inf"
    double y = "nan"
    asset c = "tex.png"
    asset[] cs = ["a.png", @b.png@]
}
)");
    auto v = [&](std::string_view name) {
        return *layer->prim("/A")->attribute(name)->defaultValue;
    };
    for (const char* name : {"t1", "t2", "t3", "t4"}) EXPECT_EQ(v(name).getDouble(), 1.0) << name;
    for (const char* name : {"f1", "f2", "f3"}) EXPECT_EQ(v(name).getDouble(), 0.0) << name;
    EXPECT_EQ(*v("bs").numbers(), (std::vector<double>{1, 0, 1, 0}));
    EXPECT_EQ(v("i1").getInt(), 1);
    EXPECT_EQ(v("i2").getInt(), -1);
    EXPECT_EQ(v("i3").getInt(), 2500);
    EXPECT_EQ(v("u").getInt(), 7);
    EXPECT_EQ(*v("i4").getTuple(), (std::vector<double>{1, -2}));
    EXPECT_EQ(v("x").getDouble(), -HUGE_VAL);
    EXPECT_TRUE(std::isnan(*v("y").getDouble()));
    EXPECT_EQ(v("c").getAsset()->authored, "tex.png");
    ASSERT_EQ(v("cs").assets()->size(), 2u);
    EXPECT_EQ((*v("cs").assets())[0].authored, "a.png");
    // What does not convert is still an error.
    auto err = [](const std::string& decl) {
        return errorOf("#usda 1.0\ndef \"A\" {\n    " + decl + "\n}\n");
    };
    EXPECT_EQ(err("bool b = maybe"),
              "t.usda:3:14: expected a bool (a number, true/false, yes/no or 1/0), found 'maybe'");
    EXPECT_EQ(err("int i = 3e10"),
              "t.usda:3:13: expected an integer in [-2^31, 2^31 - 1] (int), "
              "found '3e10'");
    EXPECT_EQ(err("uint u = -1.5"),
              "t.usda:3:14: expected an integer in [0, 2^32 - 1] (uint), found '-1.5'");
    EXPECT_EQ(err("int i = inf"), "t.usda:3:13: expected an integer, found 'inf'");
    EXPECT_EQ(err("int i = 1e999"),
              "t.usda:3:13: expected a finite number for an integer, found '1e999'");
    EXPECT_EQ(err("float f = \"one\""), "t.usda:3:15: expected a number, found '\"one\"'");
    EXPECT_EQ(err("int i = \"1\""), "t.usda:3:13: expected an integer, found '\"1\"'");
}

TEST(OpenUsdGrammar, FiftyThousandPropertiesOnOnePrim) {
    // Each statement finds its property through a hash map (the scan of every earlier property
    // made this quadratic: 50k took 14 s). Correctness only; no timing here.
    constexpr int kCount = 50000;
    std::string text = "#usda 1.0\ndef \"A\" {\n";
    for (int i = 0; i < kCount; ++i) {
        const std::string n = std::to_string(i);
        text += "float a" + n + " = " + n + "\nrel r" + n + " = </A>\n";
    }
    // Later statements about earlier properties reach the same specs.
    text += "float a7.timeSamples = { 1: 2 }\nfloat a7.connect = </A.a8>\n";
    text += "rel r9 (doc = \"d\")\n}\n";
    auto layer = parse(text);
    const PrimSpec* a = layer->prim("/A");
    ASSERT_EQ(a->attributes.size(), static_cast<std::size_t>(kCount));
    ASSERT_EQ(a->relationships.size(), static_cast<std::size_t>(kCount));
    for (int i = 0; i < kCount; i += 4999) {
        const AttributeSpec& attr = a->attributes[static_cast<std::size_t>(i)];
        EXPECT_EQ(attr.name, "a" + std::to_string(i));
        EXPECT_EQ(*attr.defaultValue->getDouble(), static_cast<double>(i));
        EXPECT_EQ(a->relationships[static_cast<std::size_t>(i)].name, "r" + std::to_string(i));
    }
    const AttributeSpec& a7 = a->attributes[7];
    EXPECT_EQ(*a7.defaultValue->getDouble(), 7.0);
    EXPECT_EQ(a7.timeSamples.at(1.0).getDouble(), 2.0);
    EXPECT_TRUE(a7.hasConnections);
    EXPECT_EQ(*a->relationships[9].metadata.at("documentation").getString(), "d");
    EXPECT_TRUE(a->relationships[9].hasTargets);
    EXPECT_NE(errorOf("#usda 1.0\ndef \"A\" {\n float x = 1\n float y = 2\n float x = 3\n}\n")
                  .find("t.usda:5:8: expected a property given one value"),
              std::string::npos);
}

TEST(OpenUsdGrammar, LegacyTypeAliasesAndDottedPrimTypeNames) {
    auto layer = parse(R"(#usda 1.0
def Foo.Bar "A" (customData = { Vec3f v = (1, 2, 3) }) {
    Vec3f a = (1, 2, 3)
    Color[] c = [(0.5, 0.5, 0.5)]
    Matrix4d m = ((1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1))
    Transform t = ((1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1))
    PointIndex i = 3
    NormalFloat n = (0, 1, 0)
    Schema s = "x"
}
)");
    const PrimSpec* a = layer->prim("/A");
    EXPECT_EQ(a->typeName, "Foo.Bar");
    EXPECT_EQ(a->attribute("a")->typeName, "float3");
    EXPECT_EQ(a->attribute("c")->typeName, "color3d");
    EXPECT_TRUE(a->attribute("c")->isArray);
    EXPECT_EQ(a->attribute("m")->typeName, "matrix4d");
    EXPECT_EQ(a->attribute("t")->typeName, "matrix4d");
    EXPECT_EQ(a->attribute("i")->typeName, "int");
    EXPECT_EQ(a->attribute("n")->typeName, "vector3f");  // as OpenUSD's table (roles swapped)
    EXPECT_EQ(a->attribute("s")->typeName, "token");
    EXPECT_EQ(a->attribute("a")->defaultValue->typeName(), "float3");
    EXPECT_EQ(a->metadata.at("customData").find("v")->typeName(), "float3");
    EXPECT_EQ(errorOf("#usda 1.0\ndef Foo. \"A\" {}\n"),
              "t.usda:2:10: expected a type name after '.', found '\"A\"'");
}

}  // namespace
}  // namespace principled::usd
