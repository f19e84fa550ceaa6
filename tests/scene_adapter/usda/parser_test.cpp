// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/parser.h"

#include <gtest/gtest.h>

#include <cmath>

#include "testUtil.h"

namespace principled::usd {
namespace {

std::unique_ptr<Layer> parse(std::string_view text) {
    return parseLayer(text, "t.usda", "/tmp");
}

std::string errorOf(std::string_view text) {
    return test::parseErrorOf([&] { parse(text); });
}

const Value& defaultOf(const Layer& layer, std::string_view prim, std::string_view attr) {
    const PrimSpec* p = layer.prim(prim);
    EXPECT_NE(p, nullptr) << prim;
    const AttributeSpec* a = p ? p->attribute(attr) : nullptr;
    EXPECT_NE(a, nullptr) << attr;
    static const Value kEmpty;
    return a && a->defaultValue ? *a->defaultValue : kEmpty;
}

TEST(Parser, LayerMetadata) {
    auto layer = parse(R"(#usda 1.0
(
    """Layer documentation"""
    customLayerData = {
        string copyright = "me"
        dictionary nested = { int n = 3 }
    }
    defaultPrim = "World"
    upAxis = "Z"
    metersPerUnit = 1
    startTimeCode = 1
    endTimeCode = 48
    timeCodesPerSecond = 24
    framesPerSecond = 12
    subLayers = [
        @./a.usda@ (offset = 10; scale = 2),
        @b.usda@
    ]
)
)");
    EXPECT_EQ(layer->defaultPrim(), "World");
    EXPECT_EQ(*layer->field("upAxis")->getString(), "Z");
    EXPECT_EQ(*layer->field("metersPerUnit")->getDouble(), 1.0);
    EXPECT_EQ(*layer->field("endTimeCode")->getInt(), 48);
    EXPECT_EQ(*layer->field("doc")->getString(), "Layer documentation");
    const Value* cld = layer->field("customLayerData");
    ASSERT_NE(cld, nullptr);
    EXPECT_EQ(*cld->find("copyright")->getString(), "me");
    EXPECT_EQ(*cld->find("nested")->find("n")->getInt(), 3);
    ASSERT_EQ(layer->subLayers.size(), 2u);
    EXPECT_EQ(layer->subLayers[0].assetPath, "./a.usda");
    EXPECT_EQ(layer->subLayers[0].offset.offset, 10.0);
    EXPECT_EQ(layer->subLayers[0].offset.scale, 2.0);
    EXPECT_EQ(layer->subLayers[1].assetPath, "b.usda");
    EXPECT_EQ(layer->subLayers[1].location.str(), "t.usda:17:9");
}

TEST(Parser, ScalarTypes) {
    auto layer = parse(R"(#usda 1.0
def "P" {
    bool b = true
    bool b0 = 0
    uchar uc = 255
    int i = -7
    uint u = 7
    int64 i64 = -9000000000
    uint64 u64 = 18000000000
    half h = 0.5
    float f = 1.5e2
    double d = -0.25
    timecode tc = 12
    string s = "a\"b\n"
    token t = 'tok'
    asset a = @tex/wood.png@
    asset a3 = @@@odd@name.png@@@
    float posInf = inf
    float negInf = -inf
    double notANumber = nan
    float blocked = None
}
)");
    EXPECT_EQ(*defaultOf(*layer, "/P", "b").getBool(), true);
    EXPECT_EQ(*defaultOf(*layer, "/P", "b0").getBool(), false);
    EXPECT_EQ(*defaultOf(*layer, "/P", "uc").getInt(), 255);
    EXPECT_EQ(*defaultOf(*layer, "/P", "i").getInt(), -7);
    EXPECT_EQ(*defaultOf(*layer, "/P", "u").getInt(), 7);
    EXPECT_EQ(*defaultOf(*layer, "/P", "i64").getInt(), -9000000000LL);
    EXPECT_EQ(*defaultOf(*layer, "/P", "u64").getInt(), 18000000000LL);
    EXPECT_EQ(*defaultOf(*layer, "/P", "h").getDouble(), 0.5);
    EXPECT_EQ(*defaultOf(*layer, "/P", "f").getDouble(), 150.0);
    EXPECT_EQ(*defaultOf(*layer, "/P", "d").getDouble(), -0.25);
    EXPECT_EQ(*defaultOf(*layer, "/P", "tc").getDouble(), 12.0);
    EXPECT_EQ(*defaultOf(*layer, "/P", "s").getString(), "a\"b\n");
    EXPECT_EQ(*defaultOf(*layer, "/P", "t").getString(), "tok");
    EXPECT_EQ(defaultOf(*layer, "/P", "t").typeName(), "token");
    EXPECT_EQ(defaultOf(*layer, "/P", "a").getAsset()->authored, "tex/wood.png");
    EXPECT_EQ(defaultOf(*layer, "/P", "a").getAsset()->resolved, "");  // no such file
    EXPECT_EQ(defaultOf(*layer, "/P", "a3").getAsset()->authored, "odd@name.png");
    EXPECT_TRUE(std::isinf(*defaultOf(*layer, "/P", "posInf").getDouble()));
    EXPECT_LT(*defaultOf(*layer, "/P", "negInf").getDouble(), 0.0);
    EXPECT_TRUE(std::isnan(*defaultOf(*layer, "/P", "notANumber").getDouble()));
    EXPECT_TRUE(defaultOf(*layer, "/P", "blocked").isNone());
    EXPECT_EQ(defaultOf(*layer, "/P", "blocked").typeName(), "float");
    EXPECT_EQ(defaultOf(*layer, "/P", "i").location().str(), "t.usda:6:13");
}

TEST(Parser, TupleAndMatrixTypes) {
    const std::pair<const char*, int> tuples[] = {
        {"float2", 2},     {"float3", 3},     {"float4", 4},     {"double2", 2},
        {"double3", 3},    {"double4", 4},    {"half2", 2},      {"half3", 3},
        {"half4", 4},      {"int2", 2},       {"int3", 3},       {"int4", 4},
        {"point3f", 3},    {"point3d", 3},    {"point3h", 3},    {"normal3f", 3},
        {"normal3d", 3},   {"normal3h", 3},   {"vector3f", 3},   {"vector3d", 3},
        {"vector3h", 3},   {"color3f", 3},    {"color3d", 3},    {"color3h", 3},
        {"color4f", 4},    {"color4d", 4},    {"color4h", 4},    {"texCoord2f", 2},
        {"texCoord2d", 2}, {"texCoord2h", 2}, {"texCoord3f", 3}, {"texCoord3d", 3},
        {"texCoord3h", 3}, {"quatf", 4},      {"quatd", 4},      {"quath", 4}};
    for (const auto& [type, n] : tuples) {
        SCOPED_TRACE(type);
        std::string tuple = "(";
        for (int i = 0; i < n; ++i) tuple += (i ? ", " : "") + std::to_string(i + 1);
        tuple += ")";
        std::string text = std::string("#usda 1.0\ndef \"P\" {\n    ") + type + " v = " + tuple +
                           "\n    " + type + "[] arr = [" + tuple + ", " + tuple + "]\n}\n";
        auto layer = parse(text);
        const Value& v = defaultOf(*layer, "/P", "v");
        EXPECT_EQ(v.typeName(), type);
        ASSERT_TRUE(v.getTuple());
        ASSERT_EQ(v.getTuple()->size(), static_cast<std::size_t>(n));
        EXPECT_EQ((*v.getTuple())[static_cast<std::size_t>(n - 1)], n);
        const Value& arr = defaultOf(*layer, "/P", "arr");
        EXPECT_TRUE(arr.isArray());
        EXPECT_EQ(arr.components(), n);
        EXPECT_EQ(arr.size(), 2u);
        ASSERT_NE(arr.numbers(), nullptr);
        EXPECT_EQ(arr.numbers()->size(), static_cast<std::size_t>(2 * n));
    }
    auto layer = parse(R"(#usda 1.0
def "P" {
    matrix2d m2 = ((1, 2), (3, 4))
    matrix3d m3 = ((1, 0, 0), (0, 1, 0), (0, 0, 1))
    matrix4d m4 = ((1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (10, 20, 30, 1))
    frame4d fr = ((1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1))
    matrix4d[] ms = [((1, 0, 0, 0), (0, 1, 0, 0), (0, 0, 1, 0), (0, 0, 0, 1)), ((2, 0, 0, 0), (0, 2, 0, 0), (0, 0, 2, 0), (0, 0, 0, 1))]
    quatf q = (1, 0, 0, 0)
}
)");
    EXPECT_EQ(*defaultOf(*layer, "/P", "m2").getTuple(), (std::vector<double>{1, 2, 3, 4}));
    EXPECT_EQ(defaultOf(*layer, "/P", "m3").getTuple()->size(), 9u);
    auto m4 = *defaultOf(*layer, "/P", "m4").getTuple();
    ASSERT_EQ(m4.size(), 16u);
    EXPECT_EQ(m4[12], 10.0);  // row-major, translation in the last row
    EXPECT_EQ(m4[14], 30.0);
    EXPECT_EQ(defaultOf(*layer, "/P", "fr").getTuple()->size(), 16u);
    EXPECT_EQ(defaultOf(*layer, "/P", "ms").components(), 16);
    EXPECT_EQ(defaultOf(*layer, "/P", "ms").size(), 2u);
    EXPECT_EQ((*defaultOf(*layer, "/P", "ms").numbers())[16], 2.0);
    EXPECT_EQ((*defaultOf(*layer, "/P", "q").getTuple())[0], 1.0);  // real part first
}

TEST(Parser, ArrayTypes) {
    auto layer = parse(R"(#usda 1.0
def "P" {
    bool[] bs = [true, false, 1]
    int[] is = [1, -2, 3,]
    uint[] us = []
    float[] fs = [1.5, inf, -inf]
    string[] ss = ["a", "b"]
    token[] ts = ["x", 'y']
    asset[] as = [@a.png@, @b.png@]
    int[] blocked = None
}
)");
    EXPECT_EQ(*defaultOf(*layer, "/P", "bs").numbers(), (std::vector<double>{1, 0, 1}));
    EXPECT_EQ(*defaultOf(*layer, "/P", "is").numbers(), (std::vector<double>{1, -2, 3}));
    EXPECT_EQ(defaultOf(*layer, "/P", "us").size(), 0u);
    EXPECT_TRUE(defaultOf(*layer, "/P", "us").isArray());
    EXPECT_EQ(defaultOf(*layer, "/P", "fs").size(), 3u);
    EXPECT_EQ(*defaultOf(*layer, "/P", "ss").strings(), (std::vector<std::string>{"a", "b"}));
    EXPECT_EQ(*defaultOf(*layer, "/P", "ts").strings(), (std::vector<std::string>{"x", "y"}));
    EXPECT_EQ(defaultOf(*layer, "/P", "ts").typeName(), "token");
    ASSERT_NE(defaultOf(*layer, "/P", "as").assets(), nullptr);
    EXPECT_EQ(defaultOf(*layer, "/P", "as").assets()->at(1).authored, "b.png");
    EXPECT_EQ(defaultOf(*layer, "/P", "as").strings()->at(0), "a.png");
    EXPECT_TRUE(defaultOf(*layer, "/P", "blocked").isNone());
    EXPECT_TRUE(defaultOf(*layer, "/P", "blocked").isArray());
}

TEST(Parser, PrimSpecsAndMetadata) {
    auto layer = parse(R"(#usda 1.0
def Xform "World" (
    "documentation string"
    kind = "component"
    instanceable = true
    hidden = false
    active = false
    prepend apiSchemas = ["MaterialBindingAPI", "GeomModelAPI"]
    prepend references = [@./a.usda@</A> (offset = 5), </Local>]
    append payload = @p.usda@
    inherits = </_class>
    delete specializes = [</S1>, </S2>]
    variants = {
        string geo = "quad"
    }
    prepend variantSets = ["geo", "lod"]
    customData = { bool flag = 1 }
    assetInfo = { asset identifier = @./x.usd@ }
)
{
    over "Child" {}
    class Scope "Klass" {}
    def Mesh "m" {}
    reorder nameChildren = ["m", "Child"]
    reorder properties = ["b", "a"]
}
over "O" {}
class "C" {}
)");
    const PrimSpec* w = layer->prim("/World");
    ASSERT_NE(w, nullptr);
    EXPECT_EQ(w->specifier, Specifier::Def);
    EXPECT_EQ(w->typeName, "Xform");
    EXPECT_EQ(w->location.str(), "t.usda:2:1");
    EXPECT_EQ(*w->metadata.at("documentation").getString(), "documentation string");
    EXPECT_EQ(*w->metadata.at("kind").getString(), "component");
    EXPECT_EQ(*w->metadata.at("instanceable").getBool(), true);
    EXPECT_EQ(*w->metadata.at("hidden").getBool(), false);
    EXPECT_EQ(*w->metadata.at("active").getBool(), false);
    EXPECT_EQ(w->apiSchemas.prepended,
              (std::vector<std::string>{"MaterialBindingAPI", "GeomModelAPI"}));
    ASSERT_EQ(w->references.prepended.size(), 2u);
    EXPECT_EQ(w->references.prepended[0].assetPath, "./a.usda");
    EXPECT_EQ(w->references.prepended[0].primPath, "/A");
    EXPECT_EQ(w->references.prepended[0].offset.offset, 5.0);
    EXPECT_EQ(w->references.prepended[1].assetPath, "");
    EXPECT_EQ(w->references.prepended[1].primPath, "/Local");
    EXPECT_EQ(w->references.prepended[1].location.str(), "t.usda:9:56");
    ASSERT_EQ(w->payloads.appended.size(), 1u);
    EXPECT_TRUE(w->inherits.isExplicit);
    EXPECT_EQ(w->inherits.explicitItems.at(0).path, "/_class");
    EXPECT_EQ(w->specializes.deleted.size(), 2u);
    EXPECT_EQ(w->variantSelections.at("geo"), "quad");
    EXPECT_EQ(w->variantSetNames.prepended, (std::vector<std::string>{"geo", "lod"}));
    EXPECT_EQ(*w->metadata.at("customData").find("flag")->getBool(), true);
    EXPECT_EQ(w->metadata.at("assetInfo").find("identifier")->getAsset()->authored, "./x.usd");
    ASSERT_EQ(w->children.size(), 3u);
    EXPECT_EQ(w->children[0]->specifier, Specifier::Over);
    EXPECT_EQ(w->children[1]->specifier, Specifier::Class);
    EXPECT_EQ(w->children[1]->typeName, "Scope");
    EXPECT_EQ(*w->nameChildrenOrder, (std::vector<std::string>{"m", "Child"}));
    EXPECT_EQ(*w->propertyOrder, (std::vector<std::string>{"b", "a"}));
    EXPECT_EQ(layer->prim("/O")->specifier, Specifier::Over);
    EXPECT_EQ(layer->prim("/C")->specifier, Specifier::Class);
    EXPECT_EQ(layer->prim("/World/m")->typeName, "Mesh");
    EXPECT_EQ(layer->prim("/World/nope"), nullptr);
}

TEST(Parser, PropertiesConnectionsRelationshipsTimeSamples) {
    auto layer = parse(R"(#usda 1.0
def Mesh "M" {
    custom uniform token info:id = "UsdPreviewSurface"
    varying float3 v
    color3f inputs:diffuseColor.connect = </Mat/Tex.outputs:rgb>
    float inputs:x.connect = [</A.outputs:a>, </B.outputs:b>]
    prepend float inputs:y.connect = </C.outputs:c>
    float3[] points = [(0, 0, 0)] (
        interpolation = "vertex"
        elementSize = 1
        doc = """multi
line"""
        customData = { string note = "hi" }
        colorSpace = "raw"
        connectability = "interfaceOnly"
    )
    double3 xformOp:translate.timeSamples = {
        1: (0, 0, 0),
        24.5: (0, 5, 0),
        30: None,
    }
    double3 xformOp:translate = (1, 1, 1)
    rel material:binding = </Looks/Mat>
    rel proxyPrim
    rel empty = None
    rel many = [</a>, </b>]
    prepend rel extra = </c> (doc = "d")
    delete rel gone = </x>
}
)");
    const PrimSpec* m = layer->prim("/M");
    ASSERT_NE(m, nullptr);
    const AttributeSpec* id = m->attribute("info:id");
    ASSERT_NE(id, nullptr);
    EXPECT_TRUE(id->custom);
    EXPECT_EQ(id->variability, Variability::Uniform);
    EXPECT_FALSE(m->attribute("v")->defaultValue);
    const AttributeSpec* dc = m->attribute("inputs:diffuseColor");
    ASSERT_TRUE(dc->hasConnections);
    EXPECT_EQ(dc->connections->explicitItems.at(0).path, "/Mat/Tex.outputs:rgb");
    EXPECT_EQ(m->attribute("inputs:x")->connections->explicitItems.size(), 2u);
    EXPECT_EQ(m->attribute("inputs:y")->connections->prepended.at(0).path, "/C.outputs:c");
    const AttributeSpec* pts = m->attribute("points");
    EXPECT_EQ(*pts->metadata.at("interpolation").getString(), "vertex");
    EXPECT_EQ(*pts->metadata.at("elementSize").getInt(), 1);
    EXPECT_EQ(*pts->metadata.at("documentation").getString(), "multi\nline");
    EXPECT_EQ(*pts->metadata.at("customData").find("note")->getString(), "hi");
    EXPECT_EQ(*pts->metadata.at("colorSpace").getString(), "raw");
    const AttributeSpec* tr = m->attribute("xformOp:translate");
    ASSERT_TRUE(tr->hasTimeSamples);
    ASSERT_EQ(tr->timeSamples.size(), 3u);
    EXPECT_EQ((*tr->timeSamples.at(24.5).getTuple())[1], 5.0);
    EXPECT_TRUE(tr->timeSamples.at(30).isNone());
    EXPECT_EQ((*tr->defaultValue->getTuple())[0], 1.0);  // same attribute, merged
    EXPECT_EQ(m->relationship("material:binding")->targets.explicitItems.at(0).path, "/Looks/Mat");
    EXPECT_FALSE(m->relationship("proxyPrim")->hasTargets);
    EXPECT_TRUE(m->relationship("empty")->targets.isExplicit);
    EXPECT_TRUE(m->relationship("empty")->targets.explicitItems.empty());
    EXPECT_EQ(m->relationship("many")->targets.explicitItems.size(), 2u);
    EXPECT_EQ(m->relationship("extra")->targets.prepended.size(), 1u);
    EXPECT_EQ(*m->relationship("extra")->metadata.at("documentation").getString(), "d");
    EXPECT_EQ(m->relationship("gone")->targets.deleted.size(), 1u);
}

TEST(Parser, NestedVariantSets) {
    auto layer = parse(R"(#usda 1.0
def "A" (
    variants = { string geo = "quad" }
    prepend variantSets = "geo"
)
{
    variantSet "geo" = {
        "quad" (
            variants = { string creases = "edges" }
            prepend variantSets = "creases"
        ) {
            def Mesh "shape" { int n = 4 }
            variantSet "creases" = {
                "edges" { over "shape" { int[] creaseIndices = [0, 1] } }
                "none" {}
            }
        }
        "tri" {
            def Mesh "shape" { int n = 3 }
        }
    }
}
)");
    const PrimSpec* quad = layer->prim("/A{geo=quad}");
    ASSERT_NE(quad, nullptr);
    EXPECT_TRUE(quad->isVariant);
    EXPECT_EQ(quad->variantSelections.at("creases"), "edges");
    EXPECT_EQ(*defaultOf(*layer, "/A{geo=tri}/shape", "n").getInt(), 3);
    EXPECT_EQ(defaultOf(*layer, "/A{geo=quad}{creases=edges}/shape", "creaseIndices").size(), 2u);
    EXPECT_NE(layer->prim("/A{geo=quad}{creases=none}"), nullptr);
    EXPECT_EQ(layer->prim("/A{geo=hex}"), nullptr);
}

TEST(Parser, DictionariesCommentsStrings) {
    auto layer = parse(R"(#usda 1.0
# a comment
// another comment
/* a block
   comment */
def "P" (  # trailing comment
    customData = {
        dictionary inner = {
            double[] values = [1, 2]
            string "quoted key" = 'single'
        }
        int n = 1; token t = "x"
    }
)
{
    string s1 = """triple "quoted" text"""
    string s2 = '''single triple'''
    string s3 = "tab\there \x41 \\ \' "
    string s4 = ""
}
)");
    const PrimSpec* p = layer->prim("/P");
    const Value& cd = p->metadata.at("customData");
    EXPECT_EQ(cd.find("inner")->find("values")->size(), 2u);
    EXPECT_EQ(*cd.find("inner")->find("quoted key")->getString(), "single");
    EXPECT_EQ(*cd.find("n")->getInt(), 1);
    EXPECT_EQ(cd.find("t")->typeName(), "token");
    EXPECT_EQ(*defaultOf(*layer, "/P", "s1").getString(), "triple \"quoted\" text");
    EXPECT_EQ(*defaultOf(*layer, "/P", "s2").getString(), "single triple");
    EXPECT_EQ(*defaultOf(*layer, "/P", "s3").getString(), "tab\there A \\ ' ");
    EXPECT_EQ(*defaultOf(*layer, "/P", "s4").getString(), "");
}

TEST(Parser, UntypedMapMetadata) {
    auto layer = parse(R"(#usda 1.0
(
    relocates = { </A/b>: </A/c>, </X>: </Y> }
)
def "P" ( prefixSubstitutions = { "$ROOT": "/assets", "$V": "2" } ) {}
)");
    EXPECT_EQ(*layer->field("relocates")->find("/A/b")->getPath(), "/A/c");
    EXPECT_EQ(*layer->prim("/P")->metadata.at("prefixSubstitutions").find("$ROOT")->getString(),
              "/assets");
}

TEST(Parser, HeaderAndBinaryRefusal) {
    EXPECT_NO_THROW(parse("#usda 1.0"));
    EXPECT_NO_THROW(parse("\xEF\xBB\xBF#usda 1.0\r\ndef \"A\" {}\r\n"));
    EXPECT_EQ(errorOf("#usda 2.0\n"),
              "t.usda:1:1: expected a USDA version from 1.0 to 1.1 (the versions this reader "
              "supports), found '#usda 2.0'");
    EXPECT_EQ(errorOf(""), "t.usda:1:1: expected '#usda 1.0', found end of file");
    try {
        parse(std::string("PXR-USDC\0\0\0", 11));
        FAIL() << "crate accepted";
    } catch (const ParseError&) {
        FAIL() << "crate must not be a syntax error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("text format (usda) is required"), std::string::npos);
    }
    try {
        parse(std::string("PK\x03\x04zipdata", 11));
        FAIL() << "usdz accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("USDZ"), std::string::npos);
    }
}

struct BadInput {
    const char* name;
    const char* text;
    const char* error;
};

class ParserErrors : public ::testing::TestWithParam<BadInput> {};

TEST_P(ParserErrors, ExactMessage) {
    EXPECT_EQ(errorOf(GetParam().text), GetParam().error);
}

INSTANTIATE_TEST_SUITE_P(
    Malformed, ParserErrors,
    ::testing::Values(
        BadInput{"UnbalancedBrace", "#usda 1.0\ndef Xform \"A\" {\n  float x = 1\n",
                 "t.usda:4:1: expected '}', found end of file"},
        BadInput{"UnbalancedBraceNoNewline", "#usda 1.0\ndef \"A\" {\n  def \"B\" {}",
                 "t.usda:3:13: expected '}', found end of file"},
        BadInput{"ExtraBrace", "#usda 1.0\ndef \"A\" { }\n}",
                 "t.usda:3:1: expected 'def', 'over' or 'class', found '}'"},
        BadInput{"UnbalancedParen", "#usda 1.0\ndef Xform \"A\" (\n  kind = \"x\"\n{\n}\n",
                 "t.usda:4:1: expected a prim metadata name or ')', found '{'"},
        BadInput{"UnbalancedTupleParen", "#usda 1.0\ndef \"A\" {\n  float3 x = (1, 2, 3\n}\n",
                 "t.usda:4:1: expected ')', found '}'"},
        BadInput{"UnbalancedBracket", "#usda 1.0\ndef \"A\" {\n  float[] x = [1, 2, 3\n}\n",
                 "t.usda:4:1: expected ',' or ']', found '}'"},
        BadInput{"BadNumber", "#usda 1.0\ndef \"A\" {\n  float x = 1.2.3\n}\n",
                 "t.usda:3:13: expected a number, found '1.2.3'"},
        BadInput{"BadNumberSuffix", "#usda 1.0\ndef \"A\" {\n  double3 x = (1, 2x, 3)\n}\n",
                 "t.usda:3:19: expected a number, found '2x'"},
        BadInput{"NonIntegerInt", "#usda 1.0\ndef \"A\" {\n  int x = nan\n}\n",
                 "t.usda:3:11: expected an integer, found 'nan'"},
        BadInput{"NegativeUnsigned", "#usda 1.0\ndef \"A\" {\n  uint x = -1\n}\n",
                 "t.usda:3:12: expected an unsigned integer, found '-1'"},
        BadInput{"UnterminatedString", "#usda 1.0\ndef \"A\" {\n  string x = \"abc\n}\n",
                 "t.usda:3:18: expected '\"' closing the string opened at 3:14, found end of line"},
        BadInput{
            "UnterminatedTripleString", "#usda 1.0\ndef \"A\" {\n  string x = \"\"\"abc\n}\n",
            "t.usda:5:1: expected '\"\"\"' closing the string opened at 3:14, found end of file"},
        BadInput{
            "UnterminatedAsset", "#usda 1.0\ndef \"A\" {\n  asset x = @a.png\n}\n",
            "t.usda:3:19: expected '@' closing the asset path opened at 3:13, found end of line"},
        BadInput{"UnterminatedPath", "#usda 1.0\ndef \"A\" {\n  rel r = </a/b\n}\n",
                 "t.usda:3:16: expected '>' closing the path opened at 3:11, found end of line"},
        BadInput{"UnterminatedComment", "#usda 1.0\n/* never closed\n",
                 "t.usda:3:1: expected '*/' closing the comment opened at 2:1, found end of file"},
        BadInput{"MissingEquals", "#usda 1.0\ndef \"A\" {\n  float x 1\n}\n",
                 "t.usda:3:11: expected '=', found '1'"},
        BadInput{"MissingEqualsMetadata", "#usda 1.0\ndef \"A\" (\n  kind \"x\"\n) {}\n",
                 "t.usda:3:8: expected '=', found '\"x\"'"},
        BadInput{"TruncatedValue", "#usda 1.0\ndef \"A\" {\n  float x = ",
                 "t.usda:3:13: expected a number, found end of file"},
        BadInput{"TruncatedHeader", "#usda 1.0\ndef \"A\" (",
                 "t.usda:2:10: expected a prim metadata name or ')', found end of file"},
        BadInput{"TruncatedName", "#usda 1.0\ndef Xform",
                 "t.usda:2:10: expected a quoted prim name, found end of file"},
        BadInput{"Garbage", "#usda 1.0\n$%^ garbage",
                 "t.usda:2:1: expected 'def', 'over' or 'class', found '$'"},
        BadInput{"BinaryGarbage", "#usda 1.0\n\x01\x02\xff",
                 "t.usda:2:1: expected 'def', 'over' or 'class', found '\\x01'"},
        BadInput{"NoHeader", "def \"A\" {}",
                 "t.usda:1:1: expected '#usda 1.0', found 'def \"A\" {}'"},
        BadInput{"UnknownType", "#usda 1.0\ndef \"A\" {\n  foo x = 1\n}\n",
                 "t.usda:3:3: expected a value type name or 'rel', found 'foo'"},
        BadInput{"WrongValueKind", "#usda 1.0\ndef \"A\" {\n  string s = 1\n}\n",
                 "t.usda:3:14: expected a quoted string, found '1'"},
        BadInput{"TupleArity", "#usda 1.0\ndef \"A\" {\n  float2 x = (1, 2, 3)\n}\n",
                 "t.usda:3:21: expected ')', found '3'"},
        BadInput{"BadPrimName", "#usda 1.0\ndef \"a/b\" {}\n",
                 "t.usda:2:5: expected a valid prim name (an identifier), found '\"a/b\"'"},
        BadInput{"BadField", "#usda 1.0\ndef \"A\" {\n  float x.spline = 1\n}\n",
                 "t.usda:3:11: expected 'connect' or 'timeSamples', found 'spline'"},
        BadInput{"BadTimeSamples", "#usda 1.0\ndef \"A\" {\n  float x.timeSamples = { 1 (2) }\n}\n",
                 "t.usda:3:29: expected ':', found '('"},
        BadInput{"BadVariantSet", "#usda 1.0\ndef \"A\" {\n  variantSet \"v\" = { x }\n}\n",
                 "t.usda:3:22: expected a quoted variant name or '}', found 'x'"},
        BadInput{"DuplicatePrim", "#usda 1.0\ndef \"A\" {}\nover \"A\" {}\n",
                 "t.usda:3:6: expected a unique prim name ('A' is already defined at 2:1), found "
                 "'\"A\"'"},
        BadInput{"MixedList", "#usda 1.0\n( customLayerData = { int x = 1 } doc = [1, \"a\"] )\n",
                 "t.usda:2:45: expected array elements of one type, found '\"a\"'"},
        BadInput{"DictInList", "#usda 1.0\n( doc = [{}] )\n",
                 "t.usda:2:10: expected numbers, strings, assets or paths in a list, found '{ }'"},
        BadInput{"BadReference", "#usda 1.0\ndef \"A\" (\n  references = 3\n) {}\n",
                 "t.usda:3:16: expected an asset path '@...@' or a prim path '<...>', found '3'"}),
    [](const ::testing::TestParamInfo<BadInput>& p) { return std::string(p.param.name); });

TEST(Parser, DeepNestingIsRefused) {
    std::string prims = "#usda 1.0\n";
    for (int i = 0; i < 1000; ++i) prims += "def \"a\" {\n";
    EXPECT_EQ(errorOf(prims), "t.usda:130:1: expected at most 128 nested levels, found 'def'");
    std::string brackets = "#usda 1.0\n(\n customLayerData = " + std::string(100000, '[');
    EXPECT_EQ(errorOf(brackets), "t.usda:3:147: expected at most 128 nested levels, found '['");
    std::string dicts = "#usda 1.0\n(\n customLayerData = {";
    for (int i = 0; i < 1000; ++i) dicts += " dictionary d = {";
    EXPECT_NE(errorOf(dicts).find("expected at most 128 nested levels"), std::string::npos);
    std::string variants = "#usda 1.0\ndef \"A\" {";
    for (int i = 0; i < 1000; ++i) variants += " variantSet \"v\" = { \"x\" {";
    EXPECT_NE(errorOf(variants).find("expected at most 128 nested levels"), std::string::npos);
}

TEST(Parser, RandomGarbageNeverCrashes) {
    // Deterministic LCG (Knuth MMIX constants) mutating a valid layer.
    const std::string base = R"(#usda 1.0
( defaultPrim = "W" subLayers = [@a.usda@] )
def Xform "W" ( kind = "component" prepend references = @r.usda@</X> variants = { string v = "a" } )
{
    float3[] points = [(1, 2, 3), (4, 5, 6)] ( interpolation = "vertex" )
    double3 xformOp:translate.timeSamples = { 1: (0, 0, 0), 2: (1, 1, 1) }
    rel material:binding = </M>
    variantSet "v" = { "a" { def "C" { string s = "x\n" } } }
}
)";
    std::uint64_t state = 42;
    auto rnd = [&state] {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<std::uint32_t>(state >> 33);
    };
    const char alphabet[] = "{}()[]<>@\"'=,:;.#/ \n\\-1e9aZ_\x01\xff";
    for (int iter = 0; iter < 3000; ++iter) {
        std::string text = base;
        int edits = 1 + static_cast<int>(rnd() % 4);
        for (int e = 0; e < edits; ++e) {
            std::size_t pos = rnd() % text.size();
            switch (rnd() % 3) {
                case 0:
                    text.erase(pos, 1 + rnd() % 8);
                    break;
                case 1:
                    text.insert(pos, 1, alphabet[rnd() % (sizeof(alphabet) - 1)]);
                    break;
                default:
                    text.resize(pos);
                    break;
            }
            if (text.empty()) text.push_back('#');
        }
        try {
            parse(text);
        } catch (const ParseError& err) {
            std::string what = err.what();
            ASSERT_EQ(what.rfind("t.usda:", 0), 0u) << what;
            ASSERT_NE(what.find(": expected "), std::string::npos) << what;
            ASSERT_NE(what.find(", found "), std::string::npos) << what;
        }
    }
}

TEST(Parser, LargeArray) {
    // ~2M numbers: 666,667 float3 points.
    const int count = 666667;
    std::string text = "#usda 1.0\ndef Mesh \"M\" {\n    point3f[] points = [";
    text.reserve(static_cast<std::size_t>(count) * 40);
    for (int i = 0; i < count; ++i) {
        if (i) text += ", ";
        text += '(';
        text += std::to_string(i);
        text += ".5, -";
        text += std::to_string(i % 1000);
        text += "e-3, 1.25)";
    }
    text += "]\n}\n";
    auto layer = parse(text);
    const Value& pts = defaultOf(*layer, "/M", "points");
    ASSERT_EQ(pts.size(), static_cast<std::size_t>(count));
    ASSERT_EQ(pts.components(), 3);
    const auto& n = *pts.numbers();
    EXPECT_EQ(n[0], 0.5);
    EXPECT_EQ(n[3 * 12345], 12345.5);
    EXPECT_DOUBLE_EQ(n[3 * 12345 + 1], -0.345);
    EXPECT_EQ(n.back(), 1.25);
}

}  // namespace
}  // namespace principled::usd

namespace principled::usd {

TEST(Parser, IntegersOutsideTheirDeclaredTypeAreErrors) {
    EXPECT_EQ(errorOf("#usda 1.0\ndef \"A\" { int[] c = [4, 4294967300] }\n"),
              "t.usda:2:25: expected an integer in [-2^31, 2^31 - 1] (int), found '4294967300'");
    EXPECT_NE(errorOf("#usda 1.0\ndef \"A\" { uchar c = 256 }\n").find("(uchar)"), std::string::npos);
    EXPECT_NE(errorOf("#usda 1.0\ndef \"A\" { uint c = -1 }\n").find("unsigned"), std::string::npos);
    EXPECT_NE(errorOf("#usda 1.0\ndef \"A\" { int64 c = 1e300 }\n").find("(int64)"), std::string::npos);
    // In range: kept exactly.
    auto layer = parseLayer("#usda 1.0\ndef \"A\" { int64 c = 4294967297\n int d = -2147483648 }\n", "t.usda", "/tmp");
    EXPECT_EQ(layer->prim("/A")->attribute("c")->defaultValue->getInt(), 4294967297);
    EXPECT_EQ(layer->prim("/A")->attribute("d")->defaultValue->getInt(), -2147483648LL);
}

TEST(Parser, APropertyGivenTwoValuesInOneSpecIsAnError) {
    EXPECT_EQ(errorOf("#usda 1.0\ndef \"A\" {\n int[] n = [4]\n int[] n = [3]\n}\n"),
              "t.usda:4:8: expected a property given one value ('n' already has one, declared at 3:2), found 'n'");
    // A value, its time samples and its connection are one property's parts.
    auto layer = parseLayer("#usda 1.0\ndef \"A\" {\n double x = 1\n double x.timeSamples = { 0: 2 }\n"
                            " double x.connect = </B.y>\n}\n",
                            "t.usda", "/tmp");
    EXPECT_TRUE(layer->prim("/A")->attribute("x")->hasTimeSamples);
}

}  // namespace principled::usd
