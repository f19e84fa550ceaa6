// SPDX-License-Identifier: Apache-2.0
// Composition: sublayers, references, payloads, inherits, specializes, variants, over, active,
// path remapping, cycles, missing files, relative asset resolution, LIVRPS strength order.
#include "scene_adapter/usda/composer.h"

#include <gtest/gtest.h>

#include <filesystem>

#include "testUtil.h"

namespace principled::usd {
namespace {

double number(const Stage& stage, std::string_view prim, std::string_view attr,
              double time = kDefaultTime) {
    const Prim* p = stage.prim(prim);
    EXPECT_NE(p, nullptr) << prim;
    if (!p) return -1e300;
    const Attribute* a = p->attribute(attr);
    EXPECT_NE(a, nullptr) << prim << "." << attr;
    if (!a) return -1e300;
    auto v = a->get(time).getDouble();
    EXPECT_TRUE(v.has_value()) << prim << "." << attr;
    return v.value_or(-1e300);
}

bool hasWarning(const Stage& stage, std::string_view text) {
    for (const Diagnostic& d : stage.warnings())
        if (d.str().find(text) != std::string::npos) return true;
    return false;
}

std::string allWarnings(const Stage& stage) {
    std::string out;
    for (const Diagnostic& d : stage.warnings()) out += d.str() + "\n";
    return out;
}

TEST(Composer, ReferenceToDefaultPrimAndExplicitPrim) {
    test::TempDir dir("ref");
    dir.write("asset.usda", R"(#usda 1.0
( defaultPrim = "Asset" )
def Xform "Asset" {
    double size = 2
    def Mesh "geo" { int n = 4 }
}
def "Other" { double size = 7 }
)");
    std::string root = dir.write("root.usda", R"(#usda 1.0
def "A" ( references = @asset.usda@ ) { }
def "B" ( references = @./asset.usda@</Other> ) { double size = 9 }
)");
    auto stage = Stage::open(root);
    EXPECT_TRUE(stage->warnings().empty()) << allWarnings(*stage);
    EXPECT_EQ(stage->prim("/A")->typeName(), "Xform");
    EXPECT_EQ(number(*stage, "/A", "size"), 2.0);
    EXPECT_EQ(number(*stage, "/A/geo", "n"), 4.0);
    EXPECT_EQ(stage->prim("/A/geo")->typeName(), "Mesh");
    EXPECT_EQ(number(*stage, "/B", "size"), 9.0);  // local beats the reference
    EXPECT_EQ(stage->prim("/B/geo"), nullptr);
    EXPECT_EQ(stage->layerFiles().size(), 2u);
}

TEST(Composer, InternalReferenceAndPathRemapping) {
    auto stage = Stage::openString(R"(#usda 1.0
def "Proto" {
    def Material "Mat" {
        token outputs:surface.connect = </Proto/Mat/Shader.outputs:surface>
        def Shader "Shader" { token outputs:surface }
    }
    def Mesh "mesh" {
        rel material:binding = </Proto/Mat>
        rel outside = </Elsewhere>
        rel relative = <../Mat>
    }
}
def "Inst" ( references = </Proto> ) { }
)",
                                   "mem.usda");
    const Prim* mesh = stage->prim("/Inst/mesh");
    ASSERT_NE(mesh, nullptr);
    EXPECT_EQ(mesh->relationship("material:binding")->targets(),
              (std::vector<std::string>{"/Inst/Mat"}));
    EXPECT_EQ(mesh->relationship("relative")->targets(), (std::vector<std::string>{"/Inst/Mat"}));
    // An internal reference keeps the layer stack's namespace outside the referenced prim (Pcp
    // adds the root identity for internal arcs): the target is kept as authored.
    EXPECT_EQ(mesh->relationship("outside")->targets(), (std::vector<std::string>{"/Elsewhere"}));
    EXPECT_FALSE(hasWarning(*stage, "lies outside the referenced prim")) << allWarnings(*stage);
    EXPECT_EQ(stage->prim("/Inst/Mat")->attribute("outputs:surface")->connections(),
              (std::vector<std::string>{"/Inst/Mat/Shader.outputs:surface"}));
    // The source is composed too, unmapped.
    EXPECT_EQ(stage->prim("/Proto/mesh")->relationship("material:binding")->targets(),
              (std::vector<std::string>{"/Proto/Mat"}));
}

TEST(Composer, AnExternalReferenceDropsTargetsOutsideTheReferencedPrim) {
    // Across layer stacks a path outside the referenced prim means nothing in the stage (a
    // different file's namespace): dropped with a warning. An internal reference in that file
    // keeps its own file's namespace, mapped on through the outer reference.
    test::TempDir dir("outside");
    dir.write("asset.usda", R"(#usda 1.0
( defaultPrim = "Asset" )
def "Asset" {
    def Material "Mat" { }
    def "Src" { rel material:binding = </Asset/Mat>  rel far = </Lib> }
    def "Copy" ( references = </Asset/Src> ) { }
}
def "Lib" { }
)");
    std::string root = dir.write("root.usda", R"(#usda 1.0
def "A" ( references = @asset.usda@ ) { }
)");
    auto stage = Stage::open(root);
    EXPECT_EQ(stage->prim("/A/Copy")->relationship("material:binding")->targets(),
              (std::vector<std::string>{"/A/Mat"}));
    EXPECT_TRUE(stage->prim("/A/Src")->relationship("far")->targets().empty());
    EXPECT_TRUE(hasWarning(*stage, "target </Lib> lies outside the referenced prim")) << allWarnings(*stage);
}

TEST(Composer, LayersOfOtherTimeCodesPerSecondKeepSecondsAsSeconds) {
    // A sublayer and a referenced layer at 48 time codes per second (one by framesPerSecond
    // alone) under a 24 tcps stage: stage time 12 (0.5 s) reads their time 24; with an authored
    // offset the ratio scales the arc (Pcp: scale *= outer tcps / inner tcps).
    test::TempDir dir("tcps");
    dir.write("sub48.usda", R"(#usda 1.0
( timeCodesPerSecond = 48 )
def "Sub" { double x.timeSamples = { 0: 0, 48: 48 } }
)");
    dir.write("fps48.usda", R"(#usda 1.0
( framesPerSecond = 48  defaultPrim = "Asset" )
def "Asset" { double x.timeSamples = { 0: 0, 48: 48 } }
)");
    std::string root = dir.write("root.usda", R"(#usda 1.0
( timeCodesPerSecond = 24  subLayers = [@sub48.usda@] )
def "Ref" ( references = @fps48.usda@ ) { }
def "Shifted" ( references = @fps48.usda@ (offset = 10) ) { }
)");
    auto stage = Stage::open(root);
    EXPECT_DOUBLE_EQ(number(*stage, "/Sub", "x", 12.0), 24.0);
    EXPECT_DOUBLE_EQ(number(*stage, "/Ref", "x", 12.0), 24.0);
    EXPECT_DOUBLE_EQ(number(*stage, "/Shifted", "x", 22.0), 24.0);  // stage = 10 + 0.5 * layer
}

TEST(Composer, OpinionsOnAnInstancesDescendantsAreIgnored) {
    // Scenegraph instancing: the descendants of an instanceable prim come from its arcs; overs
    // on them in the instance's layer stack (here the root layer, and inside a referenced
    // asset) do not apply, and prims they define do not appear. The instance's own
    // properties and root-stack class opinions reached by its arcs still do.
    test::TempDir dir("inst");
    dir.write("asset.usda", R"(#usda 1.0
( defaultPrim = "Asset" )
def "Asset" ( inherits = </_class_Asset> ) {
    def "Body" { double size = 1 }
    def "Knob" { double size = 2 }
}
)");
    dir.write("set.usda", R"(#usda 1.0
( defaultPrim = "Set" )
def "Set" {
    def "Inner" ( instanceable = true  references = @asset.usda@ ) {
        over "Body" { double size = 5 }
    }
}
)");
    std::string root = dir.write("root.usda", R"(#usda 1.0
class "_class_Asset" { over "Knob" { double size = 7 } }
def "First" ( instanceable = true  references = @asset.usda@ ) {
    double size = 3
    over "Body" { double size = 9 }
    over "Knob" ( active = false ) { }
    def "Extra" { }
}
def "Second" ( instanceable = true  references = @asset.usda@ ) { }
def "Set" ( references = @set.usda@ ) { over "Inner" { over "Body" { double size = 6 } } }
)");
    auto stage = Stage::open(root);
    EXPECT_EQ(number(*stage, "/First", "size"), 3.0);
    for (const char* inst : {"/First", "/Second", "/Set/Inner"}) {
        const std::string p = inst;
        EXPECT_EQ(number(*stage, p + "/Body", "size"), 1.0) << p;
        ASSERT_NE(stage->prim(p + "/Knob"), nullptr) << p;
        EXPECT_TRUE(stage->prim(p + "/Knob")->isActive()) << p;
        EXPECT_EQ(number(*stage, p + "/Knob", "size"), 7.0) << p;  // the implied root-stack class
    }
    EXPECT_EQ(stage->prim("/First/Extra"), nullptr);
    EXPECT_EQ(stage->prim("/First")->instanceKey(), stage->prim("/Second")->instanceKey());
}

TEST(Composer, AnInstanceablePrimWithoutAnArcOfItsOwnIsAnOrdinaryPrim) {
    // Nothing instanceable is brought in (no direct arc), so it is not an instance and its
    // children are composed as usual (they vanished when its local opinions were set aside).
    test::TempDir dir("noarc");
    dir.write("asset.usda", R"(#usda 1.0
( defaultPrim = "Asset" )
def "Asset" { def "Inner" ( instanceable = true ) { def "Leaf" { double size = 2 } } }
)");
    std::string root = dir.write("root.usda", R"(#usda 1.0
def "Local" ( instanceable = true ) { def "Child" { double size = 1 } }
def "Ref" ( references = @asset.usda@ ) { }
)");
    auto stage = Stage::open(root);
    EXPECT_FALSE(stage->prim("/Local")->isInstance());
    EXPECT_EQ(number(*stage, "/Local/Child", "size"), 1.0);
    EXPECT_FALSE(stage->prim("/Ref/Inner")->isInstance());
    EXPECT_EQ(number(*stage, "/Ref/Inner/Leaf", "size"), 2.0);
}

TEST(Composer, RelocatesAreReportedAsNotApplied) {
    auto stage = Stage::openString(R"(#usda 1.0
( relocates = { </A/B>: </A/C> } )
def "A" { def "B" { } }
)",
                                   "reloc.usda");
    EXPECT_TRUE(hasWarning(*stage, "reloc.usda:2:")) << allWarnings(*stage);
    EXPECT_TRUE(hasWarning(*stage, "relocates are not applied")) << allWarnings(*stage);
}

TEST(Composer, ValueClipsAreReportedAsNotApplied) {
    auto stage = Stage::openString(R"(#usda 1.0
def Xform "Crowd" (
    clips = { dictionary default = { asset[] assetPaths = [@./clip.usda@]
                                      string primPath = "/Crowd" double2[] active = [(0, 0)] } }
)
{
}
)",
                                   "clips.usda");
    EXPECT_TRUE(hasWarning(*stage, "clips.usda:3:")) << allWarnings(*stage);
    EXPECT_TRUE(hasWarning(*stage, "value clips) are not applied: /Crowd")) << allWarnings(*stage);
}

TEST(Composer, InvalidLayerOffsetsAreReplacedByNoOffset) {
    // scale = 0 sent every sample to one time (the animation collapsed) and nan put NaN keys in
    // the sample map; Pcp reports such offsets and uses no offset instead.
    test::TempDir dir("badoffset");
    dir.write("anim.usda", R"(#usda 1.0
def "P" { double c.timeSamples = { 0: 0, 10: 10 } }
)");
    for (const char* offset : {"scale = 0", "offset = nan", "offset = 5; scale = inf"}) {
        std::string root = dir.write("root.usda", std::string("#usda 1.0\n( subLayers = [ @anim.usda@ (") + offset + ") ] )\n"
                                                  "def \"R\" ( references = @anim.usda@</P> (" + offset + ") ) { }\n");
        auto stage = Stage::open(root);
        EXPECT_TRUE(hasWarning(*stage, "invalid sublayer offset")) << offset << "\n" << allWarnings(*stage);
        EXPECT_TRUE(hasWarning(*stage, "invalid reference offset")) << offset << "\n" << allWarnings(*stage);
        for (const char* prim : {"/P", "/R"}) {
            const auto& samples = stage->prim(prim)->attribute("c")->timeSamples();
            ASSERT_EQ(samples.size(), 2u) << offset << " " << prim;
            EXPECT_EQ(samples.begin()->first, 0.0);
            EXPECT_EQ(samples.rbegin()->first, 10.0);
        }
    }
}

TEST(Composer, SubLayerStrengthAndOffsets) {
    test::TempDir dir("sub");
    dir.write("weak.usda", R"(#usda 1.0
def "P" {
    double a = 1
    double b = 1
    double c.timeSamples = { 0: 0, 10: 10 }
    def "OnlyWeak" {}
}
)");
    dir.write("strong.usda", R"(#usda 1.0
over "P" { double a = 2 }
)");
    std::string root = dir.write("root.usda", R"(#usda 1.0
( subLayers = [ @strong.usda@, @weak.usda@ (offset = 100; scale = 2) ] )
over "P" { double b = 3 }
)");
    auto stage = Stage::open(root);
    EXPECT_TRUE(stage->warnings().empty()) << allWarnings(*stage);
    EXPECT_EQ(number(*stage, "/P", "a"), 2.0);  // strong sublayer beats weak
    EXPECT_EQ(number(*stage, "/P", "b"), 3.0);  // root beats its sublayers
    EXPECT_TRUE(stage->prim("/P")->isDefined());
    EXPECT_NE(stage->prim("/P/OnlyWeak"), nullptr);
    // weak time 10 -> stage 10 * 2 + 100 = 120
    const auto& samples = stage->prim("/P")->attribute("c")->timeSamples();
    ASSERT_EQ(samples.size(), 2u);
    EXPECT_EQ(samples.begin()->first, 100.0);
    EXPECT_EQ(samples.rbegin()->first, 120.0);
    EXPECT_EQ(number(*stage, "/P", "c", 110.0), 5.0);
    EXPECT_EQ(stage->layerFiles().size(), 3u);
}

TEST(Composer, ReferenceOffsetsComposeWithTheAuthoringSublayer) {
    test::TempDir dir("refoffset");
    dir.write("anim.usda",
              "#usda 1.0\n( defaultPrim = \"A\" )\ndef \"A\" { double x.timeSamples = { 0: 0, 1: 1 "
              "} }\n");
    dir.write("sub.usda",
              "#usda 1.0\ndef \"P\" ( references = @anim.usda@ (offset = 5; scale = 2) ) {}\n");
    std::string root =
        dir.write("root.usda", "#usda 1.0\n( subLayers = [@sub.usda@ (offset = 100)] )\n");
    auto stage = Stage::open(root);
    const auto& samples = stage->prim("/P")->attribute("x")->timeSamples();
    ASSERT_EQ(samples.size(), 2u);
    EXPECT_EQ(samples.begin()->first, 105.0);   // 0 * 2 + 5 + 100
    EXPECT_EQ(samples.rbegin()->first, 107.0);  // 1 * 2 + 5 + 100
}

TEST(Composer, SubLayerCycleIsAnErrorAndTheRestLoads) {
    test::TempDir dir("subcycle");
    dir.write("b.usda", "#usda 1.0\n( subLayers = [@root.usda@] )\ndef \"B\" {}\n");
    std::string root =
        dir.write("root.usda", "#usda 1.0\n( subLayers = [@b.usda@] )\ndef \"R\" {}\n");
    auto stage = Stage::open(root);
    EXPECT_NE(stage->prim("/R"), nullptr);
    EXPECT_NE(stage->prim("/B"), nullptr);
    EXPECT_TRUE(hasWarning(*stage, "b.usda:2:16: error: sublayer cycle: "));
}

TEST(Composer, InheritsFromClass) {
    auto stage = Stage::openString(R"(#usda 1.0
class "_cls" {
    double size = 5
    double color = 1
    def "fromClass" {}
}
def "World" {
    def Cube "a" ( inherits = </_cls> ) { double color = 2 }
}
)",
                                   "mem.usda");
    EXPECT_TRUE(stage->prim("/_cls")->isAbstract());
    EXPECT_TRUE(stage->prim("/_cls/fromClass")->isAbstract());
    EXPECT_FALSE(stage->prim("/World/a")->isAbstract());
    EXPECT_EQ(number(*stage, "/World/a", "size"), 5.0);
    EXPECT_EQ(number(*stage, "/World/a", "color"), 2.0);
    ASSERT_NE(stage->prim("/World/a/fromClass"), nullptr);
    EXPECT_FALSE(stage->prim("/World/a/fromClass")->isAbstract());
    for (const Prim* p : stage->traverse()) EXPECT_NE(p->path().rfind("/_cls", 0), 0u) << p->path();
}

TEST(Composer, StrengthOrderLIVRPS) {
    // One attribute authored by every arc kind; removing the strongest opinion each time must
    // reveal the next: local, inherits, variants, references, payloads, specializes.
    auto build = [](const std::string& skip) {
        auto opinion = [&](const std::string& who) {
            return skip.find(who) == std::string::npos ? "string who = \"" + who + "\"" : "";
        };
        return "#usda 1.0\n"
               "class \"Inh\" { " +
               opinion("inherits") +
               " }\n"
               "def \"Ref\" { " +
               opinion("references") +
               " }\n"
               "def \"Pay\" { " +
               opinion("payloads") +
               " }\n"
               "def \"Spec\" { " +
               opinion("specializes") +
               " }\n"
               "def \"P\" (\n"
               "  inherits = </Inh>\n  references = </Ref>\n  payload = </Pay>\n"
               "  specializes = </Spec>\n  variants = { string v = \"x\" }\n"
               "  variantSets = \"v\"\n) {\n"
               "  " +
               opinion("local") +
               "\n"
               "  variantSet \"v\" = { \"x\" { " +
               opinion("variants") + " } }\n}\n";
    };
    const char* order[] = {"local",      "inherits", "variants",
                           "references", "payloads", "specializes"};
    std::string skip;
    for (const char* expected : order) {
        auto stage = Stage::openString(build(skip), "livrps.usda");
        const Attribute* who = stage->prim("/P")->attribute("who");
        ASSERT_NE(who, nullptr) << skip;
        EXPECT_EQ(*who->get().getString(), expected) << "skipping: " << skip;
        skip += std::string(expected) + " ";
    }
}

TEST(Composer, SpecializesIsWeakerThanReferencedOpinions) {
    auto stage = Stage::openString(R"(#usda 1.0
def "Base" { double v = 1  double w = 1 }
def "Ref" ( specializes = </Base> ) { }
def "Asset" { double v = 2 }
def "P" ( references = [</Ref>, </Asset>] ) { }
)",
                                   "spec.usda");
    EXPECT_EQ(number(*stage, "/P", "v"), 2.0);
    EXPECT_EQ(number(*stage, "/P", "w"), 1.0);
}

TEST(Composer, VariantSelectionAuthoredOverriddenAndNested) {
    const char* text = R"(#usda 1.0
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
                "edges" { over "shape" { int c = 1 } }
                "none" { over "shape" { int c = 0 } }
            }
        }
        "tri" { def Mesh "shape" { int n = 3 } }
    }
}
)";
    auto stage = Stage::openString(text, "v.usda");
    EXPECT_EQ(number(*stage, "/A/shape", "n"), 4.0);
    EXPECT_EQ(number(*stage, "/A/shape", "c"), 1.0);
    auto sel = stage->prim("/A")->variantSelections();
    EXPECT_EQ(sel["geo"], "quad");
    EXPECT_EQ(sel["creases"], "edges");

    StageOptions options;
    options.variantOverrides["/A"]["creases"] = "none";
    stage = Stage::openString(text, "v.usda", options);
    EXPECT_EQ(number(*stage, "/A/shape", "c"), 0.0);

    options.variantOverrides["/A"]["geo"] = "tri";
    stage = Stage::openString(text, "v.usda", options);
    EXPECT_EQ(number(*stage, "/A/shape", "n"), 3.0);
    EXPECT_EQ(stage->prim("/A/shape")->attribute("c"), nullptr);

    options.variantOverrides["/A"]["geo"] = "hex";
    stage = Stage::openString(text, "v.usda", options);
    EXPECT_EQ(stage->prim("/A/shape"), nullptr);
    EXPECT_TRUE(hasWarning(*stage, "variant set \"geo\" of /A has no variant \"hex\""));
}

TEST(Composer, NoSelectionMeansNoVariant) {
    auto stage = Stage::openString(R"(#usda 1.0
def "A" ( variantSets = "v" ) { variantSet "v" = { "x" { def "child" {} } } }
)",
                                   "v.usda");
    EXPECT_TRUE(stage->prim("/A")->children().empty());
    EXPECT_TRUE(stage->prim("/A")->variantSelections().empty());
}

TEST(Composer, InactivePrimsAreReportedButNotTraversed) {
    auto stage = Stage::openString(R"(#usda 1.0
def "World" {
    def Cube "off" ( active = false ) { def "child" {} }
    def Cube "on" { }
}
)",
                                   "a.usda");
    const Prim* off = stage->prim("/World/off");
    ASSERT_NE(off, nullptr);
    EXPECT_FALSE(off->isActive());
    EXPECT_TRUE(off->children().empty());
    EXPECT_EQ(stage->prim("/World/off/child"), nullptr);
    std::vector<std::string> paths;
    for (const Prim* p : stage->traverse()) paths.push_back(p->path());
    EXPECT_EQ(paths, (std::vector<std::string>{"/World", "/World/on"}));
}

TEST(Composer, OverOnlyPrimsAreNotDefined) {
    test::TempDir dir("over");
    dir.write("base.usda", "#usda 1.0\ndef Scope \"World\" { def Cube \"Cube\" {} }\n");
    std::string root = dir.write("root.usda", R"(#usda 1.0
( subLayers = [@base.usda@] )
over "World" {
    over "Cube" { double size = 3 }
    over Cube "undefinedCube" { }
}
)");
    auto stage = Stage::open(root);
    EXPECT_TRUE(stage->prim("/World/Cube")->isDefined());
    EXPECT_EQ(stage->prim("/World/Cube")->typeName(), "Cube");
    EXPECT_EQ(number(*stage, "/World/Cube", "size"), 3.0);
    EXPECT_FALSE(stage->prim("/World/undefinedCube")->isDefined());
    std::vector<std::string> paths;
    for (const Prim* p : stage->traverse()) paths.push_back(p->path());
    EXPECT_EQ(paths, (std::vector<std::string>{"/World", "/World/Cube"}));
}

TEST(Composer, ReferenceCycleIsReportedWithItsChain) {
    test::TempDir dir("cycle");
    dir.write("a.usda",
              "#usda 1.0\n( defaultPrim = \"A\" )\ndef \"A\" ( references = @b.usda@ ) {}\n");
    dir.write("b.usda",
              "#usda 1.0\n( defaultPrim = \"B\" )\ndef \"B\" ( references = @a.usda@ ) {}\n");
    std::string root =
        dir.write("root.usda", "#usda 1.0\ndef \"R\" ( references = @a.usda@ ) {}\n");
    auto stage = Stage::open(root);
    ASSERT_NE(stage->prim("/R"), nullptr);
    ASSERT_FALSE(stage->warnings().empty());
    const Diagnostic& d = stage->warnings().front();
    EXPECT_EQ(d.severity, Diagnostic::Severity::Error);
    std::string a = dir.path("a.usda"), b = dir.path("b.usda");
    EXPECT_EQ(d.str(),
              b + ":3:24: error: reference cycle: " + a + "</A> -> " + b + "</B> -> " + a + "</A>");
    // Internal self-reference and inherits of an ancestor.
    stage = Stage::openString(
        "#usda 1.0\ndef \"X\" { def \"Y\" ( references = </X> ) {} }\n"
        "def \"Z\" ( inherits = </Z> ) {}\n",
        "self.usda");
    EXPECT_TRUE(hasWarning(*stage,
                           "self.usda:2:34: error: reference cycle: self.usda</X/Y> -> "
                           "self.usda</X>"));
    EXPECT_TRUE(hasWarning(
        *stage, "self.usda:3:22: error: inherits cycle: self.usda</Z> -> self.usda</Z>"));
}

TEST(Composer, MissingFilesAreWarningsAndTheRestLoads) {
    test::TempDir dir("missing");
    std::string root = dir.write("root.usda", R"(#usda 1.0
( subLayers = [@nope_sub.usda@] )
def "A" ( references = @nope.usda@ ) { double x = 1 }
def "B" ( payload = @nope_payload.usda@</X> ) { }
def "C" { }
)");
    auto stage = Stage::open(root);
    EXPECT_EQ(number(*stage, "/A", "x"), 1.0);
    EXPECT_NE(stage->prim("/C"), nullptr);
    EXPECT_TRUE(hasWarning(*stage, root + ":2:16: warning: sublayer @nope_sub.usda@ not found"));
    EXPECT_TRUE(hasWarning(*stage, root + ":3:24: warning: reference @nope.usda@ not found"));
    EXPECT_TRUE(hasWarning(*stage, root + ":4:21: warning: payload @nope_payload.usda@ not found"));
}

TEST(Composer, BrokenReferencedLayerIsAnErrorDiagnostic) {
    test::TempDir dir("broken");
    dir.write("bad.usda", "#usda 1.0\ndef \"X\" {\n");
    dir.write("crate.usd", std::string("PXR-USDC\0\0", 10));
    std::string root = dir.write("root.usda", R"(#usda 1.0
def "A" ( references = @bad.usda@</X> ) { }
def "B" ( references = @crate.usd@</X> ) { }
)");
    auto stage = Stage::open(root);
    EXPECT_NE(stage->prim("/A"), nullptr);
    EXPECT_TRUE(hasWarning(*stage, "bad.usda:3:1: expected '}', found end of file"));
    EXPECT_TRUE(hasWarning(*stage, "text format (usda) is required"));
}

TEST(Composer, RelativeAssetsResolveAgainstTheAuthoringLayer) {
    test::TempDir dir("assets");
    dir.write("lib/textures/wood.png", "png");
    dir.write("lib/looks.usda", R"(#usda 1.0
def "Looks" {
    asset inputs:file = @textures/wood.png@
    asset[] files = [@./textures/wood.png@, @missing.png@]
    def "Deep" ( references = @../other/deep.usda@ ) {}
}
)");
    dir.write(
        "other/deep.usda",
        "#usda 1.0\n( defaultPrim = \"D\" )\ndef \"D\" { asset f = @../lib/textures/wood.png@ }\n");
    std::string root = dir.write("scene/root.usda", R"(#usda 1.0
( subLayers = [@../lib/looks.usda@] )
)");
    auto stage = Stage::open(root);
    EXPECT_TRUE(stage->warnings().empty()) << allWarnings(*stage);
    std::string wood = dir.path("lib/textures/wood.png");
    auto file = stage->prim("/Looks")->attribute("inputs:file")->get().getAsset();
    ASSERT_TRUE(file);
    EXPECT_EQ(file->authored, "textures/wood.png");
    EXPECT_EQ(file->resolved, wood);
    const auto* files = stage->prim("/Looks")->attribute("files")->get().assets();
    ASSERT_NE(files, nullptr);
    EXPECT_EQ(files->at(0).resolved, wood);
    EXPECT_EQ(files->at(1).resolved, "");
    EXPECT_EQ(stage->prim("/Looks/Deep")->attribute("f")->get().getAsset()->resolved, wood);
}

TEST(Composer, TimeSamplesBeatWeakerDefaultsAndStrongerDefaultsBeatSamples) {
    test::TempDir dir("time");
    dir.write("weak.usda", R"(#usda 1.0
def "P" {
    double a = 7
    double b.timeSamples = { 0: 0, 10: 10 }
}
)");
    std::string root = dir.write("root.usda", R"(#usda 1.0
( subLayers = [@weak.usda@] )
over "P" {
    double a.timeSamples = { 0: 0, 10: 100 }
    double b = 3
}
)");
    auto stage = Stage::open(root);
    const Attribute* a = stage->prim("/P")->attribute("a");
    EXPECT_EQ(a->timeSamples().size(), 2u);
    EXPECT_EQ(*a->get(5.0).getDouble(), 50.0);
    EXPECT_EQ(*a->get(kDefaultTime).getDouble(), 7.0);  // default time reads the default
    const Attribute* b = stage->prim("/P")->attribute("b");
    EXPECT_TRUE(b->timeSamples().empty());
    EXPECT_EQ(*b->get(5.0).getDouble(), 3.0);
}

TEST(Composer, ListOpsComposeAcrossLayers) {
    test::TempDir dir("listops");
    dir.write("weak.usda", R"(#usda 1.0
def "P" ( prepend apiSchemas = ["A", "B"] ) {
    rel r = [</x>, </y>]
}
)");
    std::string root = dir.write("root.usda", R"(#usda 1.0
( subLayers = [@weak.usda@] )
over "P" ( prepend apiSchemas = ["C"]  delete apiSchemas = ["A"] ) {
    append rel r = </z>
    delete rel r = </x>
}
)");
    auto stage = Stage::open(root);
    EXPECT_EQ(stage->prim("/P")->appliedSchemas(), (std::vector<std::string>{"C", "B"}));
    EXPECT_EQ(stage->prim("/P")->relationship("r")->targets(),
              (std::vector<std::string>{"/y", "/z"}));
}

TEST(Composer, ChildOrderAndReorder) {
    auto stage = Stage::openString(R"(#usda 1.0
def "Ref" { def "a" {} def "b" {} }
def "P" ( references = </Ref> ) {
    def "c" {}
    def "a" {}
}
def "Q" { def "x" {} def "y" {} def "z" {} reorder nameChildren = ["z", "x"] }
reorder rootPrims = ["Q", "P"]
)",
                                   "order.usda");
    std::vector<std::string> names;
    for (const Prim* c : stage->prim("/P")->children()) names.push_back(c->name());
    EXPECT_EQ(names, (std::vector<std::string>{"a", "b", "c"}));
    names.clear();
    for (const Prim* c : stage->prim("/Q")->children()) names.push_back(c->name());
    EXPECT_EQ(names, (std::vector<std::string>{"z", "x", "y"}));
    names.clear();
    for (const Prim* c : stage->pseudoRoot()->children()) names.push_back(c->name());
    EXPECT_EQ(names, (std::vector<std::string>{"Ref", "Q", "P"}));
}

TEST(Composer, AncestralReferenceAndArcsInsideReferencedPrims) {
    test::TempDir dir("ancestral");
    dir.write("asset.usda", R"(#usda 1.0
( defaultPrim = "Asset" )
def "Asset" {
    def "Part" ( inherits = </Asset/_base> ) { }
    class "_base" { double size = 4 }
}
)");
    std::string root = dir.write("root.usda", R"(#usda 1.0
def "Inst" ( references = @asset.usda@ ) {
    over "Part" { double extra = 1 }
}
)");
    auto stage = Stage::open(root);
    EXPECT_EQ(number(*stage, "/Inst/Part", "size"), 4.0);
    EXPECT_EQ(number(*stage, "/Inst/Part", "extra"), 1.0);
    EXPECT_TRUE(stage->prim("/Inst/_base")->isAbstract());
}

TEST(Composer, CorpusStageComposition) {
    const std::string base = test::corpusDir() + "/test_assets/foundation/stage_composition/";
    {
        auto s = Stage::open(base + "class_inherit.usda");
        auto color = [&](const char* p) {
            return (*s->prim(p)->attribute("primvars:displayColor")->get().numbers())[1];
        };
        EXPECT_EQ(color("/World/cubeWithoutSetColor"), 0.8);  // green from the class
        EXPECT_EQ(color("/World/cubeWithSetColor"), 0.0);     // local red
        EXPECT_TRUE(s->prim("/_myClass")->isAbstract());
    }
    {
        auto s = Stage::open(base + "inherit_and_specialize.usda");
        const Prim* src = s->prim("/World/cubeSceneReferenced/source");
        ASSERT_NE(src, nullptr);
        EXPECT_EQ((*src->attribute("primvars:displayColor")->get().numbers())[1], 0.8);
        EXPECT_EQ(src->typeName(), "Cube");
        EXPECT_NE(s->prim("/World/cubeSceneReferenced/specializes"), nullptr);
    }
    {
        auto s = Stage::open(base + "references_prim/reference_prim_in_other_file.usda");
        EXPECT_EQ(s->prim("/World/Cube_with_reference")->typeName(), "Cube");
        EXPECT_TRUE(hasWarning(*s, "reference target </World/Cube_does_not_exist> not found"));
        EXPECT_TRUE(hasWarning(*s, "reference @file_does_not_exist.usda@ not found"));
    }
    for (const char* dir : {"subLayer/sublayer", "references/reference", "payload/payload"}) {
        for (const char* where : {"_same_folder", "_child_folder", "_parent_folder"}) {
            std::string file = base + dir + where + ".usda";
            SCOPED_TRACE(file);
            auto s = Stage::open(file);
            EXPECT_TRUE(s->warnings().empty()) << allWarnings(*s);
            ASSERT_NE(s->prim("/World/Cube"), nullptr);
            EXPECT_EQ(s->prim("/World/Cube")->typeName(), "Cube");
            EXPECT_EQ(s->layerFiles().size(), 2u);
        }
        std::string invalid = base + dir + "_invalid.usda";
        auto s = Stage::open(invalid);
        ASSERT_EQ(s->warnings().size(), 1u) << allWarnings(*s);
        EXPECT_EQ(s->warnings()[0].where.file, invalid);
        EXPECT_NE(s->warnings()[0].message.find("@file_does_not_exist.usda@ not found"),
                  std::string::npos);
        EXPECT_EQ(s->prim("/World/cube")->typeName(), "Cube");  // the rest still loads
    }
    {
        auto s = Stage::open(base + "active.usda");
        EXPECT_FALSE(s->prim("/World/CubeInactive")->isActive());
        EXPECT_TRUE(s->prim("/World/CubeActive")->isActive());
        std::vector<std::string> paths;
        for (const Prim* p : s->traverse()) paths.push_back(p->path());
        EXPECT_EQ(paths, (std::vector<std::string>{"/World", "/World/CubeActive"}));
    }
    {
        auto s = Stage::open(base + "over.usda");
        EXPECT_TRUE(s->prim("/World")->isDefined());
        EXPECT_EQ(s->prim("/World")->typeName(), "Scope");
        EXPECT_EQ((*s->prim("/World/Cube")->attribute("primvars:displayColor")->get().numbers())[2],
                  0.8);  // blue from the over
        EXPECT_TRUE(s->prim("/World/definedCube")->isDefined());
        EXPECT_FALSE(s->prim("/World/undefinedCube")->isDefined());
        EXPECT_EQ(s->prim("/World/undefinedCube")->typeName(), "Cube");
    }
    {
        auto s = Stage::open(base + "purpose.usda");
        EXPECT_EQ(s->prim("/World/CubeIsGuide")->attribute("purpose")->get().getString(), "guide");
    }
}

TEST(Composer, PyramidAssetWithPayloadsReferencesAndNestedVariants) {
    const std::string file =
        test::corpusDir() + "/full_assets/SubdivisionSurfaces/Pyramid/Pyramid.usd";
    auto stage = Stage::open(file);
    EXPECT_TRUE(stage->warnings().empty()) << allWarnings(*stage);
    const Prim* shape = stage->prim("/Pyramid/geo/shape");
    ASSERT_NE(shape, nullptr);
    EXPECT_EQ(shape->typeName(), "Mesh");
    EXPECT_EQ(shape->attribute("points")->get().size(), 20u);
    EXPECT_EQ(shape->relationship("material:binding")->targets(),
              (std::vector<std::string>{"/Pyramid/mtl/PyramidMaterial"}));
    EXPECT_EQ(shape->appliedSchemas(), (std::vector<std::string>{"MaterialBindingAPI"}));
    EXPECT_EQ(
        stage->prim("/Pyramid/mtl/PyramidMaterial")->attribute("outputs:surface")->connections(),
        (std::vector<std::string>{
            "/Pyramid/mtl/PyramidMaterial/usdpreviewsurface1.outputs:surface"}));
    EXPECT_EQ(*stage->prim("/Pyramid")->metadata("kind")->getString(), "component");
    EXPECT_TRUE(stage->prim("/__class__")->isAbstract());
    EXPECT_EQ(stage->layerFiles().size(), 4u);

    StageOptions options;
    options.variantOverrides["/Pyramid"]["creases"] = "edges";
    stage = Stage::open(file, options);
    EXPECT_EQ(stage->prim("/Pyramid/geo/shape")->attribute("creaseIndices")->get().size(), 12u);
    options.variantOverrides["/Pyramid"]["geo"] = "quad_holes";
    stage = Stage::open(file, options);
    EXPECT_EQ(stage->prim("/Pyramid/geo/shape")->attribute("holeIndices")->get().size(), 4u);
    EXPECT_EQ(stage->prim("/Pyramid/geo/shape")->attribute("points")->get().size(), 16u);
}

TEST(Composer, DictionariesMergeAcrossOpinionsAndPayloadsCanBeSkipped) {
    auto stage = Stage::openString(R"(#usda 1.0
def "Ref" ( customData = { int a = 1  int b = 1  dictionary d = { int x = 1  int y = 1 } } ) {
    double v = 1 ( customData = { string from = "ref" string only = "ref" } )
}
def "Pay" { double p = 1 }
def "P" ( references = </Ref>  payload = </Pay>
          customData = { int b = 2  dictionary d = { int y = 2 } } ) {
    double v ( customData = { string from = "local" } )
}
)",
                                   "dict.usda");
    const Value* cd = stage->prim("/P")->metadata("customData");
    ASSERT_NE(cd, nullptr);
    EXPECT_EQ(cd->find("a")->getInt(), 1);
    EXPECT_EQ(cd->find("b")->getInt(), 2);
    EXPECT_EQ(cd->find("d")->find("x")->getInt(), 1);
    EXPECT_EQ(cd->find("d")->find("y")->getInt(), 2);
    const Value* vcd = stage->prim("/P")->attribute("v")->metadata("customData");
    EXPECT_EQ(vcd->find("from")->getString(), "local");
    EXPECT_EQ(vcd->find("only")->getString(), "ref");
    EXPECT_NE(stage->prim("/P")->attribute("p"), nullptr);
    StageOptions noPayloads;
    noPayloads.loadPayloads = false;
    stage = Stage::openString(R"(#usda 1.0
def "Pay" { double p = 1 }
def "P" ( payload = </Pay> ) { }
)",
                              "dict.usda", noPayloads);
    EXPECT_EQ(stage->prim("/P")->attribute("p"), nullptr);
}

TEST(Composer, ImpliedInheritsReachTheRootLayerStack) {
    test::TempDir dir("implied");
    dir.write("asset.usda", R"(#usda 1.0
( defaultPrim = "Asset" )
def "Asset" ( inherits = </_class_Asset> ) {
    double size = 1
    def "Part" ( inherits = </Asset/_local> ) {}
    class "_local" { double q = 1 }
}
class "_class_Asset" { double color = 1  double size = 5 }
)");
    std::string root = dir.write("root.usda", R"(#usda 1.0
def "A" ( references = @asset.usda@ ) { over "_local" { double q = 4 } }
def "B" ( references = @asset.usda@ ) { double color = 3 }
class "_class_Asset" { double color = 2  double extra = 7 }
)");
    auto stage = Stage::open(root);
    EXPECT_TRUE(stage->warnings().empty()) << allWarnings(*stage);
    EXPECT_EQ(number(*stage, "/A", "color"), 2.0);  // root class beats the asset's class
    EXPECT_EQ(number(*stage, "/A", "extra"), 7.0);
    EXPECT_EQ(number(*stage, "/A", "size"), 1.0);    // the asset's own opinion beats both classes
    EXPECT_EQ(number(*stage, "/B", "color"), 3.0);   // local beats every class
    EXPECT_EQ(number(*stage, "/A/Part", "q"), 4.0);  // a local class mapped to /A/_local
    EXPECT_EQ(number(*stage, "/B/Part", "q"), 1.0);
}

TEST(Composer, ImpliedSpecializesThroughInternalReference) {
    auto s = Stage::open(test::corpusDir() +
                         "/test_assets/foundation/stage_composition/inherit_and_specialize.usda");
    // The referenced copy specializes /World/cubeSceneReferenced/source (green), not the red
    // original; its own yellow opinion still wins.
    const Prim* spec = s->prim("/World/cubeSceneReferenced/specializes");
    ASSERT_NE(spec, nullptr);
    EXPECT_EQ((*spec->attribute("primvars:displayColor")->get().numbers())[1], 0.8);
}

TEST(Composer, InstanceKeysGroupIdenticalInstances) {
    auto stage = Stage::openString(R"(#usda 1.0
def "Tree" ( variantSets = "lod"  variants = { string lod = "hi" } ) {
    variantSet "lod" = { "hi" { def Mesh "m" {} } "lo" { def Mesh "m" {} } }
}
def "A" ( instanceable = true  references = </Tree> ) { double3 xformOp:translate = (1, 0, 0) }
def "B" ( instanceable = true  references = </Tree> ) { double3 xformOp:translate = (2, 0, 0) }
def "C" ( instanceable = true  references = </Tree>  variants = { string lod = "lo" } ) { }
def "D" ( references = </Tree> ) { }
)",
                                   "inst.usda");
    const Prim* a = stage->prim("/A");
    EXPECT_TRUE(a->isInstance());
    EXPECT_EQ(a->instanceKey(), stage->prim("/B")->instanceKey());
    EXPECT_NE(a->instanceKey(), stage->prim("/C")->instanceKey());
    EXPECT_FALSE(stage->prim("/D")->isInstance());
    EXPECT_NE(stage->prim("/A/m"), nullptr);  // still expanded
}

TEST(Composer, SubRootReferencesBringAncestralOpinions) {
    test::TempDir dir("subroot");
    dir.write("lib.usda", R"(#usda 1.0
def "Lib" ( variantSets = "look"  variants = { string look = "red" } ) {
    variantSet "look" = {
        "red" { over "Chair" { double r = 1  rel mat = </Lib/Chair/Mat> } }
        "blue" { over "Chair" { double r = 0 } }
    }
    def "Chair" { double legs = 4  def "Mat" {} }
}
)");
    std::string root = dir.write("root.usda", R"(#usda 1.0
def "MyChair" ( references = @lib.usda@</Lib/Chair> ) { }
def "Loop" { def "A" ( references = </Cycle/B> ) {} }
def "Cycle" { def "B" ( references = </Loop/A> ) {} }
)");
    auto stage = Stage::open(root);
    EXPECT_EQ(number(*stage, "/MyChair", "legs"), 4.0);
    EXPECT_EQ(number(*stage, "/MyChair", "r"), 1.0);  // from the ancestor's variant
    EXPECT_EQ(stage->prim("/MyChair")->relationship("mat")->targets(),
              (std::vector<std::string>{"/MyChair/Mat"}));
    EXPECT_TRUE(hasWarning(*stage, "reference cycle")) << allWarnings(*stage);
    EXPECT_NE(stage->prim("/Loop/A"), nullptr);
}

TEST(Composer, ManyVariantSetsAndDiamondsStayBounded) {
    // 2000 variant sets on one prim, and a diamond of internal references 12 levels deep
    // (4096 paths): both hit the per-prim node budget instead of running away.
    std::string text = "#usda 1.0\ndef \"V\" ( variantSets = [";
    for (int i = 0; i < 2000; ++i) text += (i ? ", \"s" : "\"s") + std::to_string(i) + "\"";
    text += "] variants = {";
    for (int i = 0; i < 2000; ++i) text += " string s" + std::to_string(i) + " = \"x\"";
    text += " } ) {\n";
    for (int i = 0; i < 2000; ++i)
        text += "variantSet \"s" + std::to_string(i) + "\" = { \"x\" { double a" +
                std::to_string(i) + " = 1 } }\n";
    text += "}\n";
    for (int i = 0; i < 12; ++i)
        text += "def \"D" + std::to_string(i) + "\" ( references = [</D" + std::to_string(i + 1) +
                ">, </E" + std::to_string(i + 1) + ">] ) {}\ndef \"E" + std::to_string(i) +
                "\" ( references = [</D" + std::to_string(i + 1) + ">, </E" +
                std::to_string(i + 1) + ">] ) {}\n";
    text += "def \"D12\" { double leaf = 1 }\ndef \"E12\" { double leaf = 2 }\n";
    auto stage = Stage::openString(text, "big.usda");
    EXPECT_NE(stage->prim("/V")->attribute("a0"), nullptr);
    EXPECT_TRUE(hasWarning(*stage, "composition too complex"));
    EXPECT_EQ(number(*stage, "/D0", "leaf"), 1.0);
}

TEST(Composer, ExponentialNamespaceHitsThePrimBudget) {
    // Each level references the next twice: 2^40 prims if nothing stopped it.
    std::string text = "#usda 1.0\n";
    for (int i = 0; i < 40; ++i)
        text += "def \"N" + std::to_string(i) + "\" { def \"a\" ( references = </N" +
                std::to_string(i + 1) + "> ) {} def \"b\" ( references = </N" +
                std::to_string(i + 1) + "> ) {} }\n";
    text += "def \"N40\" {}\n";
    StageOptions options;
    options.maxPrims = 5000;
    auto stage = Stage::openString(text, "exp.usda", options);
    int errors = 0;
    for (const Diagnostic& d : stage->warnings())
        if (d.message.find("too many prims (StageOptions::maxPrims = 5000)") != std::string::npos)
            ++errors;
    EXPECT_EQ(errors, 1);
    EXPECT_NE(stage->prim("/N0"), nullptr);
}

TEST(Composer, LongReferenceChainsAreBounded) {
    test::TempDir dir("chain");
    const int files = 300;
    for (int i = 0; i < files; ++i)
        dir.write("f" + std::to_string(i) + ".usda",
                  "#usda 1.0\n( defaultPrim = \"P\" )\ndef \"P\" ( references = @f" +
                      std::to_string(i + 1) + ".usda@ ) { double d" + std::to_string(i) +
                      " = 1 }\n");
    dir.write("f" + std::to_string(files) + ".usda",
              "#usda 1.0\n( defaultPrim = \"P\" )\ndef \"P\" {}\n");
    auto stage = Stage::open(dir.path("f0.usda"));
    EXPECT_NE(stage->prim("/P")->attribute("d200"), nullptr);
    EXPECT_TRUE(hasWarning(*stage, "composition arcs nested more than 256 deep"));
    StageOptions few;
    few.maxLayers = 10;
    stage = Stage::open(dir.path("f0.usda"), few);
    EXPECT_TRUE(hasWarning(*stage, "too many layers (StageOptions::maxLayers = 10)"));
}

TEST(Composer, MutatedCompositionNeverCrashes) {
    const std::string base = R"(#usda 1.0
( defaultPrim = "W" startTimeCode = 1 )
class "C" { double c = 1  def "k" {} }
def "Base" ( specializes = </C> ) { rel r = </Base/x>  def "x" { double v.timeSamples = { 1: 1, 2: 2 } } }
def Xform "W" ( inherits = </C>  prepend references = [</Base>, </W2>]  payload = </Base>
    variants = { string v = "a" }  prepend variantSets = "v" )
{
    variantSet "v" = { "a" ( references = </Base> ) { def "va" { float f.connect = </W.c> } } "b" {} }
    def "child" ( references = </W> ) {}
}
def "W2" ( inherits = </W> ) { over "x" ( active = false ) {} }
)";
    std::uint64_t state = 7;
    auto rnd = [&state] {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<std::uint32_t>(state >> 33);
    };
    const std::string pieces[] = {"</W>",
                                  "</Base>",
                                  "</C>",
                                  "</W/child>",
                                  "{",
                                  "}",
                                  "(",
                                  ")",
                                  "\"",
                                  "=",
                                  "def \"Z\" ",
                                  "over ",
                                  "class ",
                                  "inherits = ",
                                  "references = ",
                                  "variants = ",
                                  "active = false "};
    int composed = 0;
    for (int iter = 0; iter < 1500; ++iter) {
        std::string text = base;
        int edits = 1 + static_cast<int>(rnd() % 3);
        for (int e = 0; e < edits; ++e) {
            std::size_t pos = rnd() % text.size();
            if (rnd() % 2) {
                text.erase(pos, 1 + rnd() % 6);
            } else {
                text.insert(pos, pieces[rnd() % (sizeof(pieces) / sizeof(pieces[0]))]);
            }
        }
        try {
            auto stage = Stage::openString(text, "m.usda");
            for (const Prim* p : stage->traverse())
                for (const Attribute* a : p->attributes()) (void)a->get(1.5);
            ++composed;
        } catch (const ParseError&) {
        }
    }
    EXPECT_GT(composed, 100);
}

}  // namespace
}  // namespace principled::usd
