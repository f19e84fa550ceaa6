// SPDX-License-Identifier: Apache-2.0
#include "delegate/shading/materialProgram.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <map>
#include <set>
#include <new>
#include <thread>

#include "delegate/shading/colorSpace.h"
#include "testImages.h"

using namespace principled;
using namespace principled::shading;
using principled::shading::test::TempDir;
using principled::shading::test::writeImage;

// Counts heap allocations made while `gCounting` is set, to check evaluate() allocates nothing.
// GCC 12 flags malloc/free inside replaced global operators as mismatched: a false positive.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
namespace {
std::atomic<long> gAllocations{0};
thread_local bool gCounting = false;
}  // namespace

void* operator new(std::size_t n) {
    if (gCounting) ++gAllocations;
    if (void* p = std::malloc(n ? n : 1)) return p;
    throw std::bad_alloc();
}
void operator delete(void* p) noexcept {
    std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
    std::free(p);
}

namespace {

using hd::Token;
using hd::Value;

/// Builds networks by path: add nodes, then connect inputs to outputs.
struct Net {
    hd::MaterialNetwork net;

    Net() {
        add("/M/Surface", "UsdPreviewSurface");
        net.surfaceTerminal = hd::Path("/M/Surface");
    }
    hd::MaterialNode& node(const std::string& path) {
        for (auto& n : net.nodes)
            if (n.path.str() == path) return n;
        throw std::runtime_error("no node " + path);
    }
    Net& add(const std::string& path, const char* id, std::map<Token, Value> params = {}) {
        hd::MaterialNode n;
        n.path = hd::Path(path);
        n.identifier = Token(id);
        n.parameters = std::move(params);
        net.nodes.insert(net.nodes.begin(), n);  // upstream nodes first
        return *this;
    }
    Net& set(const std::string& path, const char* input, Value v) {
        node(path).parameters[Token(input)] = std::move(v);
        return *this;
    }
    Net& connect(const std::string& path, const char* input, const std::string& from,
                 const char* output) {
        node(path).inputConnections[Token(input)].push_back({hd::Path(from), Token(output)});
        return *this;
    }
    Net& surface(const char* input, Value v) { return set("/M/Surface", input, std::move(v)); }
    Net& surfaceFrom(const char* input, const std::string& from, const char* output) {
        return connect("/M/Surface", input, from, output);
    }
    Net& stReader(const char* path = "/M/St", std::map<Token, Value> extra = {}) {
        extra[Token("varname")] = Value(std::string("st"));
        return add(path, "UsdPrimvarReader_float2", std::move(extra));
    }
    Net& texture(const std::string& path, const std::string& file,
                 std::map<Token, Value> extra = {}) {
        extra[Token("file")] = Value(file);
        return add(path, "UsdUVTexture", std::move(extra));
    }
};

/// Primvars from a map; derivatives for "st" when set.
class Context : public ShadingContext {
  public:
    std::map<std::string, glm::vec4> values;
    bool hasDerivatives = false;
    glm::vec2 ddx{0.0f}, ddy{0.0f};

    bool primvar(const Token& name, int components, float* out) const override {
        auto it = values.find(name.str());
        if (it == values.end()) return false;
        for (int i = 0; i < components; ++i) out[i] = it->second[i];
        return true;
    }
    bool primvarDerivatives(const Token& name, glm::vec2* dx, glm::vec2* dy) const override {
        if (!hasDerivatives || name.str() != "st") return false;
        *dx = ddx;
        *dy = ddy;
        return true;
    }
};

constexpr int kSize = 4;

// 8-bit codes per texel (x, row from the top).
glm::vec3 code(int x, int row) {
    return glm::vec3(10 + 60 * x, 10 + 60 * row, 200) / 255.0f;
}
glm::vec3 decoded(int x, int row) {
    glm::vec3 c = code(x, row);
    return {srgbToLinear(c.x), srgbToLinear(c.y), srgbToLinear(c.z)};
}
glm::vec2 centre(int x, int row) {
    return {(x + 0.5f) / kSize, 1.0f - (row + 0.5f) / kSize};
}

void expectNear(const glm::vec3& a, const glm::vec3& b, float tol = 1e-4f) {
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(a[i], b[i], tol) << "component " << i;
}

void expectFinite(const ShadedMaterial& m) {
    const auto& p = m.params;
    for (float v :
         {p.baseColor.x, p.baseColor.y, p.baseColor.z, p.metallic, p.roughness, p.specular,
          p.specularTint, p.sheen, p.clearcoat, p.clearcoatGloss, p.ior, m.emission.x, m.emission.y,
          m.emission.z, m.opacity, m.tangentNormal.x, m.tangentNormal.y, m.tangentNormal.z})
        EXPECT_TRUE(std::isfinite(v));
}

class MaterialProgramTest : public ::testing::Test {
  protected:
    void SetUp() override {
        png = dir.file("tex.png");
        std::vector<float> px;
        for (int row = 0; row < kSize; ++row)
            for (int x = 0; x < kSize; ++x)
                for (int c = 0; c < 3; ++c) px.push_back(code(x, row)[c]);
        ASSERT_TRUE(writeImage(png, kSize, kSize, 3, px, OIIO::TypeDesc::UINT8));
    }
    MaterialProgram compile(const Net& n) { return MaterialProgram::compile(n.net, cache, &notes); }

    TempDir dir;
    std::string png;
    TextureCache cache;
    std::vector<std::string> notes;
    Context ctx;
};

bool anyNoteHas(const std::vector<std::string>& notes, const std::string& text) {
    for (const auto& n : notes)
        if (n.find(text) != std::string::npos) return true;
    return false;
}

}  // namespace

TEST_F(MaterialProgramTest, ConstantNetworkIsEvaluatedOnce) {
    Net n;
    n.surface("diffuseColor", Value(glm::vec3(0.2f, 0.4f, 2.0f)))
        .surface("metallic", Value(1.0f))
        .surface("roughness", Value(-3.0f))
        .surface("clearcoatRoughness", Value(0.3f))
        .surface("sheen", Value(0.7f));
    MaterialProgram p = compile(n);
    EXPECT_TRUE(p.isConstant());
    EXPECT_TRUE(p.primvarsRead().empty());
    ShadedMaterial m = p.evaluate(ctx);
    EXPECT_FLOAT_EQ(m.params.baseColor.z, 1.0f);
    EXPECT_FLOAT_EQ(m.params.metallic, 1.0f);
    EXPECT_FLOAT_EQ(m.params.roughness, 0.0f);
    EXPECT_NEAR(m.params.clearcoatAlpha, 0.09f, 1e-6f);  // clearcoatRoughness 0.3: GGX alpha 0.3^2
    EXPECT_FLOAT_EQ(m.params.sheen, 0.7f);
    EXPECT_TRUE(notes.empty());
}

TEST_F(MaterialProgramTest, NonFiniteScalarsKeepTheirFallback) {
    Net n;
    n.surface("roughness", Value(NAN)).surface("metallic", Value(INFINITY));
    ShadedMaterial m = compile(n).evaluate(ctx);
    EXPECT_FLOAT_EQ(m.params.roughness, 0.5f);
    EXPECT_FLOAT_EQ(m.params.metallic, 0.0f);
    // A NaN texel on a scalar input keeps the authored value.
    std::string exr = dir.file("nan.exr");
    std::vector<float> px(4, NAN);
    ASSERT_TRUE(writeImage(exr, 2, 2, 1, px, OIIO::TypeDesc::FLOAT));
    Net t;
    t.stReader()
        .texture("/M/T", exr)
        .connect("/M/T", "st", "/M/St", "result")
        .surface("roughness", Value(0.25f))
        .surfaceFrom("roughness", "/M/T", "r")
        .surfaceFrom("diffuseColor", "/M/T", "rgb");
    ctx.values["st"] = glm::vec4(0.5f);
    m = compile(t).evaluate(ctx);
    EXPECT_FLOAT_EQ(m.params.roughness, 0.25f);
    expectFinite(m);
}

TEST_F(MaterialProgramTest, EmptyOrForeignNetworkGivesDefaultsWithANote) {
    hd::MaterialNetwork empty;
    MaterialProgram p = MaterialProgram::compile(empty, cache, &notes);
    EXPECT_TRUE(p.isConstant());
    EXPECT_FLOAT_EQ(p.evaluate(ctx).params.baseColor.x, 0.18f);
    EXPECT_EQ(notes.size(), 1u);
    Net n;
    n.node("/M/Surface").identifier = Token("ND_open_pbr_surface_surfaceshader");
    compile(n);
    EXPECT_TRUE(anyNoteHas(notes, "ND_open_pbr_surface_surfaceshader"));
}

TEST_F(MaterialProgramTest, TextureReadsStFromThePrimvar) {
    Net n;
    n.stReader().texture("/M/Tex", png).connect("/M/Tex", "st", "/M/St", "result");
    n.surfaceFrom("diffuseColor", "/M/Tex", "rgb").surfaceFrom("metallic", "/M/Tex", "g");
    MaterialProgram p = compile(n);
    EXPECT_FALSE(p.isConstant());
    ASSERT_EQ(p.primvarsRead().size(), 1u);
    EXPECT_EQ(p.primvarsRead()[0], Token("st"));
    for (int row = 0; row < kSize; ++row)
        for (int x = 0; x < kSize; ++x) {
            glm::vec2 st = centre(x, row);
            ctx.values["st"] = glm::vec4(st, 0, 0);
            ShadedMaterial m = p.evaluate(ctx);
            expectNear(m.params.baseColor, decoded(x, row));  // 8-bit RGB: sRGB decoded
            EXPECT_NEAR(m.params.metallic, decoded(x, row).y, 1e-4f);
        }
    EXPECT_TRUE(notes.empty()) << notes.front();
}

TEST_F(MaterialProgramTest, MissingPrimvarUsesTheReadersFallback) {
    Net n;
    n.stReader("/M/St", {{Token("fallback"), Value(centre(3, 3))}})
        .texture("/M/Tex", png)
        .connect("/M/Tex", "st", "/M/St", "result")
        .surfaceFrom("diffuseColor", "/M/Tex", "rgb");
    MaterialProgram p = compile(n);
    ctx.values["uv"] = glm::vec4(centre(0, 0), 0, 0);  // another name: not used
    expectNear(p.evaluate(ctx).params.baseColor, decoded(3, 3));
}

TEST_F(MaterialProgramTest, VarnameMayBeAToken) {
    Net n;
    n.add("/M/St", "UsdPrimvarReader_float2", {{Token("varname"), Value(Token("uv"))}})
        .texture("/M/Tex", png)
        .connect("/M/Tex", "st", "/M/St", "result")
        .surfaceFrom("diffuseColor", "/M/Tex", "rgb");
    MaterialProgram p = compile(n);
    ASSERT_EQ(p.primvarsRead().size(), 1u);
    EXPECT_EQ(p.primvarsRead()[0], Token("uv"));
    ctx.values["uv"] = glm::vec4(centre(2, 1), 0, 0);
    expectNear(p.evaluate(ctx).params.baseColor, decoded(2, 1));
}

TEST_F(MaterialProgramTest, Transform2dRotatesScalesTranslates) {
    // result = R(90) (in * 0.5) + (0.5, 0.25): in (0.25, 0.25) -> (0.375, 0.375) = texel (1, 2).
    Net n;
    n.stReader()
        .add("/M/Xf", "UsdTransform2d",
             {{Token("rotation"), Value(90.0f)},
              {Token("scale"), Value(glm::vec2(0.5f))},
              {Token("translation"), Value(glm::vec2(0.5f, 0.25f))}})
        .connect("/M/Xf", "in", "/M/St", "result")
        .texture("/M/Tex", png)
        .connect("/M/Tex", "st", "/M/Xf", "result")
        .surfaceFrom("diffuseColor", "/M/Tex", "rgb");
    MaterialProgram p = compile(n);
    ctx.values["st"] = glm::vec4(0.25f, 0.25f, 0, 0);
    expectNear(p.evaluate(ctx).params.baseColor, decoded(1, 2));

    Transform2d t = Transform2d::make(90.0f, glm::vec2(2.0f, 3.0f), glm::vec2(1.0f, 0.0f));
    glm::vec2 r = t.apply(glm::vec2(1.0f, 1.0f));  // (2,3) rotated CCW -> (-3,2), + (1,0)
    EXPECT_NEAR(r.x, -2.0f, 1e-5f);
    EXPECT_NEAR(r.y, 2.0f, 1e-5f);
}

TEST_F(MaterialProgramTest, ConstantSubgraphsFold) {
    // A texture at an authored st and a transform of a constant are looked up at compile time.
    Net n;
    n.texture("/M/A", png, {{Token("st"), Value(centre(2, 0))}})
        .add("/M/Xf", "UsdTransform2d",
             {{Token("in"), Value(glm::vec2(0.0f))}, {Token("translation"), Value(centre(1, 3))}})
        .texture("/M/B", png)
        .connect("/M/B", "st", "/M/Xf", "result")
        .surfaceFrom("diffuseColor", "/M/A", "rgb")
        .surfaceFrom("emissiveColor", "/M/B", "rgb");
    MaterialProgram p = compile(n);
    EXPECT_TRUE(p.isConstant());
    EXPECT_TRUE(p.primvarsRead().empty());
    ShadedMaterial m = p.evaluate(ctx);
    expectNear(m.params.baseColor, decoded(2, 0));
    expectNear(m.emission, decoded(1, 3));
}

TEST_F(MaterialProgramTest, MissingTextureUsesFallbackAndNotesThePath) {
    std::string missing = dir.file("gone.png");
    Net n;
    n.stReader()
        .texture("/M/Tex", missing, {{Token("fallback"), Value(glm::vec4(1, 0, 0, 1))}})
        .connect("/M/Tex", "st", "/M/St", "result")
        .surfaceFrom("diffuseColor", "/M/Tex", "rgb");
    n.node("/M/Tex").where = "look.usda:7:5";
    MaterialProgram p = compile(n);
    EXPECT_TRUE(p.isConstant());  // nothing left to look up
    expectNear(p.evaluate(ctx).params.baseColor, glm::vec3(1, 0, 0));
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find(missing), std::string::npos) << notes[0];
    EXPECT_EQ(notes[0].rfind("look.usda:7:5: /M/Tex: ", 0), 0u) << notes[0];  // where the texture node is
}

TEST_F(MaterialProgramTest, NormalMapWithScaleAndBias) {
    std::string exr = dir.file("normal.exr");
    std::vector<float> px;
    for (int i = 0; i < 4; ++i) px.insert(px.end(), {0.75f, 0.5f, 1.0f});
    ASSERT_TRUE(writeImage(exr, 2, 2, 3, px, OIIO::TypeDesc::FLOAT));
    Net n;
    n.stReader()
        .texture("/M/N", exr,
                 {{Token("scale"), Value(glm::vec4(2, 2, 2, 1))},
                  {Token("bias"), Value(glm::vec4(-1, -1, -1, 0))},
                  {Token("sourceColorSpace"), Value(Token("raw"))}})
        .connect("/M/N", "st", "/M/St", "result")
        .surfaceFrom("normal", "/M/N", "rgb");
    MaterialProgram p = compile(n);
    ctx.values["st"] = glm::vec4(0.5f);
    ShadedMaterial m = p.evaluate(ctx);
    EXPECT_TRUE(m.hasNormalMap);
    expectNear(m.tangentNormal, glm::normalize(glm::vec3(0.5f, 0.0f, 1.0f)));
    // Without a normal input the map is off.
    EXPECT_FALSE(compile(Net()).evaluate(ctx).hasNormalMap);
}

TEST_F(MaterialProgramTest, OpacityFromAlphaWithCutout) {
    std::string rgba = dir.file("leaf.png");
    std::vector<float> px = {1, 1, 1, 0.2f, 1, 1, 1, 0.8f, 1, 1, 1, 0.2f, 1, 1, 1, 0.8f};
    ASSERT_TRUE(writeImage(rgba, 2, 2, 4, px, OIIO::TypeDesc::UINT8));
    Net n;
    n.stReader()
        .texture("/M/T", rgba)
        .connect("/M/T", "st", "/M/St", "result")
        .surfaceFrom("diffuseColor", "/M/T", "rgb")
        .surfaceFrom("opacity", "/M/T", "a")
        .surface("opacityThreshold", Value(0.5f));
    MaterialProgram p = compile(n);
    ctx.values["st"] = glm::vec4(0.25f, 0.5f, 0, 0);  // left column: alpha 0.2
    ShadedMaterial left = p.evaluate(ctx);
    EXPECT_NEAR(left.opacity, 51.0f / 255.0f, 1e-4f);
    EXPECT_FLOAT_EQ(left.presence(), 0.0f);
    expectNear(left.params.baseColor, glm::vec3(1.0f));  // straight alpha: colour not darkened
    ctx.values["st"] = glm::vec4(0.75f, 0.5f, 0, 0);
    EXPECT_FLOAT_EQ(p.evaluate(ctx).presence(), 1.0f);
}

TEST_F(MaterialProgramTest, PrimvarReaderFeedsAColourAndNaNNeverLeaves) {
    Net n;
    n.add("/M/C", "UsdPrimvarReader_float3",
          {{Token("varname"), Value(std::string("displayColor"))},
           {Token("fallback"), Value(glm::vec3(0.5f))}})
        .add("/M/R", "UsdPrimvarReader_float", {{Token("varname"), Value(std::string("rough"))}})
        .surfaceFrom("diffuseColor", "/M/C", "result")
        .surfaceFrom("roughness", "/M/R", "result")
        .surfaceFrom("emissiveColor", "/M/R", "result");
    MaterialProgram p = compile(n);
    EXPECT_EQ(p.primvarsRead().size(), 2u);
    ctx.values["displayColor"] = glm::vec4(0.1f, 0.2f, 0.3f, 0);
    ctx.values["rough"] = glm::vec4(0.25f);
    ShadedMaterial m = p.evaluate(ctx);
    expectNear(m.params.baseColor, glm::vec3(0.1f, 0.2f, 0.3f));
    EXPECT_FLOAT_EQ(m.params.roughness, 0.25f);
    expectNear(m.emission, glm::vec3(0.25f));  // a float feeding a colour is splatted
    ctx.values["displayColor"] = glm::vec4(NAN, INFINITY, -INFINITY, 0);
    ctx.values["rough"] = glm::vec4(NAN);
    m = p.evaluate(ctx);
    expectFinite(m);
    EXPECT_NEAR(m.params.baseColor.x, 0.5f, 1e-6f);  // non-finite -> the reader's fallback
    ctx.values.clear();
    expectNear(p.evaluate(ctx).params.baseColor, glm::vec3(0.5f));
}

TEST_F(MaterialProgramTest, BadNetworksGiveNotesNotCrashes) {
    Net n;
    n.add("/M/Weird", "ND_noise2d_color3")
        .add("/M/A", "UsdTransform2d")
        .add("/M/B", "UsdTransform2d")
        .connect("/M/A", "in", "/M/B", "result")
        .connect("/M/B", "in", "/M/A", "result")
        .texture("/M/T", png)
        .connect("/M/T", "st", "/M/A", "result")
        .surfaceFrom("diffuseColor", "/M/Weird", "out")
        .surfaceFrom("roughness", "/M/T", "rgba_bogus")
        .surfaceFrom("metallic", "/M/Nowhere", "r")
        .surfaceFrom("clearcoat", "/M/T", "r")
        .surface("useSpecularWorkflow", Value(1))
        .surfaceFrom("opacityThreshold", "/M/T", "r")
        .surface("displacement", Value(0.1f))
        .surface("occlusion", Value(0.5f))
        .surface("madeUpInput", Value(1.0f));
    MaterialProgram p = compile(n);
    ShadedMaterial m = p.evaluate(ctx);
    expectFinite(m);
    EXPECT_FLOAT_EQ(m.params.baseColor.x, 0.18f);
    EXPECT_TRUE(m.specularWorkflow);
    EXPECT_TRUE(anyNoteHas(notes, "node 'ND_noise2d_color3' not supported"));
    EXPECT_TRUE(anyNoteHas(notes, "cycle"));
    EXPECT_TRUE(anyNoteHas(notes, "rgba_bogus"));
    EXPECT_TRUE(anyNoteHas(notes, "/M/Nowhere"));
    EXPECT_TRUE(anyNoteHas(notes, "interfaceOnly"));
    EXPECT_TRUE(anyNoteHas(notes, "displacement and occlusion ignored"));
    EXPECT_TRUE(anyNoteHas(notes, "madeUpInput"));
}

TEST_F(MaterialProgramTest, FootprintFollowsTheTransformChain) {
    // A 64x64 0/1 checker: a half-texture footprint averages to ~0.5; the same footprint
    // through a transform that scales st by 1/64 covers under a texel and keeps the texel.
    constexpr int size = 64;
    std::vector<float> px;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) px.push_back(static_cast<float>((x + y) & 1));
    std::string exr = dir.file("checker.exr");
    ASSERT_TRUE(writeImage(exr, size, size, 1, px, OIIO::TypeDesc::FLOAT));
    glm::vec2 texel(1.5f / size, 1.0f - 0.5f / size);  // (1, 0): value 1
    ctx.hasDerivatives = true;
    ctx.ddx = glm::vec2(0.5f, 0.0f);
    ctx.ddy = glm::vec2(0.0f, 0.5f);

    Net direct;
    direct.stReader()
        .texture(
            "/M/T", exr,
            {{Token("wrapS"), Value(Token("repeat"))}, {Token("wrapT"), Value(Token("repeat"))}})
        .connect("/M/T", "st", "/M/St", "result")
        .surfaceFrom("roughness", "/M/T", "r");
    ctx.values["st"] = glm::vec4(texel, 0, 0);
    EXPECT_NEAR(compile(direct).evaluate(ctx).params.roughness, 0.5f, 0.05f);

    Net scaled;
    scaled.stReader()
        .add("/M/Xf", "UsdTransform2d", {{Token("scale"), Value(glm::vec2(1.0f / size))}})
        .connect("/M/Xf", "in", "/M/St", "result")
        .texture(
            "/M/T", exr,
            {{Token("wrapS"), Value(Token("repeat"))}, {Token("wrapT"), Value(Token("repeat"))}})
        .connect("/M/T", "st", "/M/Xf", "result")
        .surfaceFrom("roughness", "/M/T", "r");
    ctx.values["st"] = glm::vec4(texel * float(size), 0, 0);
    EXPECT_GT(compile(scaled).evaluate(ctx).params.roughness, 0.9f);
}

TEST_F(MaterialProgramTest, EvaluateAllocatesNothingAndIsThreadSafe) {
    Net n;
    n.stReader()
        .add("/M/Xf", "UsdTransform2d", {{Token("rotation"), Value(30.0f)}})
        .connect("/M/Xf", "in", "/M/St", "result")
        .texture(
            "/M/Tex", png,
            {{Token("wrapS"), Value(Token("repeat"))}, {Token("wrapT"), Value(Token("repeat"))}})
        .connect("/M/Tex", "st", "/M/Xf", "result")
        .surfaceFrom("diffuseColor", "/M/Tex", "rgb")
        .surfaceFrom("roughness", "/M/Tex", "r");
    MaterialProgram p = compile(n);
    ctx.values["st"] = glm::vec4(0.3f, 0.6f, 0, 0);
    ShadedMaterial want = p.evaluate(ctx);  // warms the tile cache
    gAllocations = 0;
    gCounting = true;
    ShadedMaterial got = p.evaluate(ctx);
    gCounting = false;
    EXPECT_EQ(gAllocations.load(), 0);
    EXPECT_EQ(got.params.baseColor, want.params.baseColor);

    std::atomic<int> mismatches{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&, t] {
            Context local;
            for (int i = 0; i < 2000; ++i) {
                glm::vec2 st((i % 97) / 97.0f + t, (i % 89) / 89.0f);
                local.values["st"] = glm::vec4(st, 0, 0);
                ShadedMaterial a = p.evaluate(local);
                ShadedMaterial b = p.evaluate(local);
                if (a.params.baseColor != b.params.baseColor) ++mismatches;
            }
        });
    for (auto& th : threads) th.join();
    EXPECT_EQ(mismatches.load(), 0);
}

// usd-wg NormalsTextureBiasAndScale: three normal maps with different encodings and
// scale/bias must give the same tangent normals (the README: "should appear nearly the same").
TEST_F(MaterialProgramTest, UsdWgNormalMapEncodingsAgree) {
    const std::string root =
        PRINCIPLED_SOURCE_DIR "/../shared/usd-wg/test_assets/NormalsTextureBiasAndScale/";
    auto program = [&](const char* file, glm::vec4 scale, glm::vec4 bias) {
        Net n;
        n.add("/M/UV", "UsdPrimvarReader_float2", {{Token("varname"), Value(Token("st"))}})
            .texture("/M/N", root + file,
                     {{Token("scale"), Value(scale)},
                      {Token("bias"), Value(bias)},
                      {Token("sourceColorSpace"), Value(Token("raw"))},
                      {Token("wrapS"), Value(Token("repeat"))},
                      {Token("wrapT"), Value(Token("repeat"))}})
            .connect("/M/N", "st", "/M/UV", "result")
            .surfaceFrom("normal", "/M/N", "rgb")
            .surface("diffuseColor", Value(glm::vec3(0.486275f)))
            .surface("roughness", Value(1.0f));
        return compile(n);
    };
    MaterialProgram plain = program("r_normal_map.png", glm::vec4(2), glm::vec4(-1));
    MaterialProgram reversedX = program("r_normal_map_reversed_x_0_bias_z.png",
                                        glm::vec4(-2, 2, 1, 2), glm::vec4(1, -1, 0, -1));
    MaterialProgram reversedY =
        program("r_normal_map_reversed_y.png", glm::vec4(2, -2, 2, 2), glm::vec4(-1, 1, -1, -1));
    EXPECT_TRUE(notes.empty()) << notes.front();
    int tilted = 0;
    float worst = 0.0f;
    constexpr int n = 64;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            ctx.values["st"] = glm::vec4((x + 0.5f) / n, (y + 0.5f) / n, 0, 0);
            ShadedMaterial a = plain.evaluate(ctx);
            ShadedMaterial b = reversedX.evaluate(ctx);
            ShadedMaterial c = reversedY.evaluate(ctx);
            ASSERT_TRUE(a.hasNormalMap);
            worst = std::max({worst, glm::length(a.tangentNormal - b.tangentNormal),
                              glm::length(a.tangentNormal - c.tangentNormal)});
            if (a.tangentNormal.z < 0.95f) ++tilted;
        }
    EXPECT_LT(worst, 0.03f);        // 8-bit quantisation: 2/255 per component after scale 2
    EXPECT_GT(tilted, n * n / 50);  // the "R" relief is there
}

TEST_F(MaterialProgramTest, PresenceRunsOnlyWhatOpacityNeeds) {
    // Shadow rays ask for presence alone: it must equal evaluate().presence() and must not read
    // the inputs that only feed other slots (here the "rough" primvar).
    std::string rgba = dir.file("leaf_presence.png");
    std::vector<float> px = {1, 0, 0, 0.2f, 0, 1, 0, 0.8f, 0, 0, 1, 0.6f, 1, 1, 1, 0.4f};
    ASSERT_TRUE(writeImage(rgba, 2, 2, 4, px, OIIO::TypeDesc::UINT8));
    Net n;
    n.stReader()
        .texture("/M/T", rgba)
        .connect("/M/T", "st", "/M/St", "result")
        .add("/M/R", "UsdPrimvarReader_float", {{Token("varname"), Value(std::string("rough"))}})
        .surfaceFrom("diffuseColor", "/M/T", "rgb")
        .surfaceFrom("roughness", "/M/R", "result")
        .surfaceFrom("opacity", "/M/T", "a");
    MaterialProgram p = compile(n);
    class Counting : public Context {
      public:
        mutable std::set<std::string> read;
        bool primvar(const Token& name, int components, float* out) const override {
            read.insert(name.str());
            return Context::primvar(name, components, out);
        }
    } counting;
    counting.values["rough"] = glm::vec4(0.3f);
    for (float s : {0.1f, 0.3f, 0.6f, 0.9f})
        for (float t : {0.2f, 0.7f}) {
            counting.values["st"] = glm::vec4(s, t, 0, 0);
            float expected = p.evaluate(counting).presence();
            counting.read.clear();
            EXPECT_FLOAT_EQ(p.presence(counting), expected) << s << "," << t;
            EXPECT_EQ(counting.read.count("rough"), 0u);
            EXPECT_EQ(counting.read.count("st"), 1u);
        }
    // Without an opacity input, presence is the constant's and reads nothing.
    Net plain;
    plain.add("/M/R", "UsdPrimvarReader_float", {{Token("varname"), Value(std::string("rough"))}})
        .surfaceFrom("roughness", "/M/R", "result");
    MaterialProgram q = compile(plain);
    counting.read.clear();
    EXPECT_FLOAT_EQ(q.presence(counting), 1.0f);
    EXPECT_TRUE(counting.read.empty());
}

// ---- MaterialX surfaces and nodes (materialxNodes.cpp, standardSurface.cpp) ----

namespace {

/// A network whose surface is ND_standard_surface_surfaceshader (the Net helper's node, renamed).
Net standardSurface() {
    Net n;
    n.node("/M/Surface").identifier = Token("ND_standard_surface_surfaceshader");
    return n;
}

/// An ND_image_color3 of `file` read at an ND_texcoord_vector2, feeding base_color.
Net imageIntoBaseColor(const std::string& file, std::map<Token, Value> extra = {}) {
    Net n = standardSurface();
    extra[Token("file")] = Value(file);
    n.add("/M/Uv", "ND_texcoord_vector2")
        .add("/M/Img", "ND_image_color3", std::move(extra))
        .connect("/M/Img", "texcoord", "/M/Uv", "out")
        .surfaceFrom("base_color", "/M/Img", "out");
    return n;
}

}  // namespace

TEST_F(MaterialProgramTest, StandardSurfaceConstantsMapOntoDisney) {
    Net n = standardSurface();
    n.surface("base_color", Value(glm::vec3(0.8f, 0.1f, 0.1f)))
        .surface("metalness", Value(1.0f))
        .surface("specular_roughness", Value(0.3f))
        .surface("coat_color", Value(glm::vec3(1.0f)));
    MaterialProgram p = compile(n);
    EXPECT_TRUE(p.isConstant());
    ShadedMaterial m = p.evaluate(ctx);
    expectNear(m.params.baseColor, glm::vec3(0.8f, 0.1f, 0.1f), 1e-6f);  // base 1 (1.0.1)
    EXPECT_FLOAT_EQ(m.params.metallic, 1.0f);
    EXPECT_FLOAT_EQ(m.params.roughness, 0.3f);
    EXPECT_NEAR(m.params.specular, 0.5f, 1e-6f);        // specular 1, IOR 1.5
    // coat_roughness 0.1: the GGX alpha 0.01, as the coat's alpha.
    EXPECT_NEAR(m.params.clearcoatAlpha, 0.01f, 1e-6f);
    EXPECT_NEAR(m.params.clearcoatGloss, 0.09f / 0.099f, 1e-5f);
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find("inputs not used: coat_color"), std::string::npos) << notes[0];
}

TEST_F(MaterialProgramTest, UsdPreviewSurfaceUnderItsMaterialXNameMapsTheSame) {
    auto build = [&](const char* surfaceId, const char* textureId) {
        Net n;
        n.node("/M/Surface").identifier = Token(surfaceId);
        n.stReader()
            .add("/M/Tex", textureId, {{Token("file"), Value(png)}})
            .connect("/M/Tex", "st", "/M/St", "result")
            .surfaceFrom("diffuseColor", "/M/Tex", "rgb")
            .surface("roughness", Value(0.35f))
            .surface("clearcoat", Value(0.6f))
            .surface("sheen", Value(0.2f));
        return n;
    };
    MaterialProgram usd = compile(build("UsdPreviewSurface", "UsdUVTexture"));
    MaterialProgram mtlx = compile(build("ND_UsdPreviewSurface_surfaceshader", "ND_UsdUVTexture"));
    EXPECT_TRUE(notes.empty()) << notes.front();
    ctx.values["st"] = glm::vec4(centre(2, 1), 0, 0);
    ShadedMaterial a = usd.evaluate(ctx), b = mtlx.evaluate(ctx);
    expectNear(b.params.baseColor, decoded(2, 1));
    expectNear(b.params.baseColor, a.params.baseColor, 0.0f);
    EXPECT_EQ(b.params.roughness, a.params.roughness);
    EXPECT_EQ(b.params.clearcoat, a.params.clearcoat);
    EXPECT_EQ(b.params.sheen, a.params.sheen);
    EXPECT_EQ(b.params.specular, a.params.specular);
}

TEST_F(MaterialProgramTest, MaterialXImageAtTexcoordSamplesTheTexture) {
    MaterialProgram p = compile(imageIntoBaseColor(png));
    EXPECT_FALSE(p.isConstant());
    ASSERT_EQ(p.primvarsRead().size(), 1u);
    EXPECT_EQ(p.primvarsRead()[0], Token("st"));
    for (int row = 0; row < kSize; ++row)
        for (int x = 0; x < kSize; ++x) {
            ctx.values["st"] = glm::vec4(centre(x, row), 0, 0);
            // 8-bit RGB without a colour space: decoded as sRGB; base 1 (1.0.1 default).
            expectNear(p.evaluate(ctx).params.baseColor, decoded(x, row));
        }
    EXPECT_TRUE(notes.empty()) << notes.front();
    // Without a texcoord node the image reads the default UV set "st" itself.
    Net implicit = standardSurface();
    implicit.add("/M/Img", "ND_image_color3", {{Token("file"), Value(png)}})
        .surfaceFrom("base_color", "/M/Img", "out");
    MaterialProgram q = compile(implicit);
    ASSERT_EQ(q.primvarsRead().size(), 1u);
    ctx.values["st"] = glm::vec4(centre(3, 0), 0, 0);
    expectNear(q.evaluate(ctx).params.baseColor, decoded(3, 0));
}

TEST_F(MaterialProgramTest, MaterialXImageColourSpaceAndWeight) {
    // lin_rec709 reads the codes as linear values; a base weight of 0.5 halves them.
    Net n = imageIntoBaseColor(png, {{Token("colorSpace:file"), Value(Token("lin_rec709"))}});
    n.surface("base", Value(0.5f));
    MaterialProgram p = compile(n);
    ctx.values["st"] = glm::vec4(centre(1, 2), 0, 0);
    expectNear(p.evaluate(ctx).params.baseColor, 0.5f * code(1, 2));
    // srgb_texture decodes; a varying base (a float image: data, read raw even from an 8-bit
    // PNG without a colour space) multiplies per point.
    Net v = imageIntoBaseColor(png, {{Token("colorSpace:file"), Value(Token("srgb_texture"))}});
    v.add("/M/W", "ND_image_float", {{Token("file"), Value(png)}})
        .connect("/M/W", "texcoord", "/M/Uv", "out")
        .surfaceFrom("base", "/M/W", "out");
    MaterialProgram q = compile(v);
    ctx.values["st"] = glm::vec4(centre(3, 1), 0, 0);
    expectNear(q.evaluate(ctx).params.baseColor, code(3, 1).x * decoded(3, 1));
    EXPECT_TRUE(notes.empty()) << notes.front();
}

TEST_F(MaterialProgramTest, MaterialXTiledImageAndGeomprop) {
    // uv from the "uv" primvar; tiled twice with an offset: (uv * 2 - 0.5) wraps periodically.
    Net n = standardSurface();
    n.add("/M/Uv", "ND_geompropvalue_vector2", {{Token("geomprop"), Value(std::string("uv"))}})
        .add("/M/Img", "ND_tiledimage_color3",
             {{Token("file"), Value(png)},
              {Token("uvtiling"), Value(glm::vec2(2.0f))},
              {Token("uvoffset"), Value(glm::vec2(0.5f, 0.0f))}})
        .connect("/M/Img", "texcoord", "/M/Uv", "out")
        .surfaceFrom("base_color", "/M/Img", "out");
    MaterialProgram p = compile(n);
    ASSERT_EQ(p.primvarsRead().size(), 1u);
    EXPECT_EQ(p.primvarsRead()[0], Token("uv"));
    glm::vec2 target = centre(1, 3);                         // (0.375, 0.125)
    glm::vec2 uv = (target + glm::vec2(0.5f, 0.0f)) / 2.0f;  // inverse of uv * 2 - offset
    ctx.values["uv"] = glm::vec4(uv, 0, 0);
    expectNear(p.evaluate(ctx).params.baseColor, decoded(1, 3));
    ctx.values["uv"] = glm::vec4(uv + glm::vec2(0.5f, 0.0f), 0, 0);  // one tile on: periodic
    expectNear(p.evaluate(ctx).params.baseColor, decoded(1, 3));
}

TEST_F(MaterialProgramTest, MaterialXNormalMapAndOpacity) {
    std::string exr = dir.file("mx_normal.exr");
    std::vector<float> px;
    for (int i = 0; i < 4; ++i) px.insert(px.end(), {0.75f, 0.5f, 1.0f});
    ASSERT_TRUE(writeImage(exr, 2, 2, 3, px, OIIO::TypeDesc::FLOAT));
    std::string alpha = dir.file("mx_alpha.exr");
    std::vector<float> a = {0.0f, 0.3f, 0.6f, 0.9f};
    ASSERT_TRUE(writeImage(alpha, 2, 2, 1, a, OIIO::TypeDesc::FLOAT));
    Net n = standardSurface();
    n.add("/M/N", "ND_image_vector3", {{Token("file"), Value(exr)}})
        .add("/M/Map", "ND_normalmap", {{Token("scale"), Value(2.0f)}})
        .connect("/M/Map", "in", "/M/N", "out")
        .surfaceFrom("normal", "/M/Map", "out")
        .add("/M/A", "ND_image_float", {{Token("file"), Value(alpha)}})
        .surfaceFrom("opacity", "/M/A", "out");
    MaterialProgram p = compile(n);
    EXPECT_TRUE(p.mayBePartlyPresent());
    ctx.values["st"] = glm::vec4(0.25f, 0.75f, 0, 0);  // top-left texel: alpha 0
    ShadedMaterial m = p.evaluate(ctx);
    EXPECT_TRUE(m.hasNormalMap);
    // (2 * 0.75 - 1) * scale 2 = 1 in x; z = 2 * 1 - 1 = 1.
    expectNear(m.tangentNormal, glm::normalize(glm::vec3(1.0f, 0.0f, 1.0f)));
    EXPECT_NEAR(m.opacity, 0.0f, 1e-5f);
    EXPECT_FLOAT_EQ(p.presence(ctx), m.presence());
    ctx.values["st"] = glm::vec4(0.75f, 0.25f, 0, 0);  // bottom-right texel: alpha 0.9
    EXPECT_NEAR(p.evaluate(ctx).opacity, 0.9f, 1e-5f);
    EXPECT_NEAR(p.presence(ctx), 0.9f, 1e-5f);
    EXPECT_TRUE(notes.empty()) << notes.front();
}

TEST_F(MaterialProgramTest, ShaderIdsThatAreNotMaterialXNodesAreNotedNotFatal) {
    // A shader with no info:id (or a short one) feeding the surface: a note, the constant.
    for (const char* id : {"", "ab", "ND_"}) {
        notes.clear();
        Net n;
        n.node("/M/Surface").identifier = Token("UsdPreviewSurface");
        n.add("/M/Odd", id)
            .surface("diffuseColor", Value(glm::vec3(0.2f, 0.3f, 0.4f)))
            .surfaceFrom("diffuseColor", "/M/Odd", "out");
        MaterialProgram p = compile(n);
        expectNear(p.evaluate(ctx).params.baseColor, glm::vec3(0.2f, 0.3f, 0.4f), 1e-6f);
        EXPECT_TRUE(anyNoteHas(notes, "not supported")) << "id '" << id << "'";
    }
}

TEST_F(MaterialProgramTest, ColorSpaceMetadataIsNotAnUnusedInput) {
    Net n;
    n.node("/M/Surface").identifier = Token("UsdPreviewSurface");
    n.surface("diffuseColor", Value(glm::vec3(0.5f))).surface("colorSpace:diffuseColor", Value(std::string("lin_rec709")));
    compile(n);
    EXPECT_FALSE(anyNoteHas(notes, "colorSpace")) << notes.front();
}

TEST_F(MaterialProgramTest, MaterialXArithmeticNodes) {
    // base_color = mix(fg = tint * 2 (multiply_color3FA), bg = 1 - (0, 0, 1) (invert),
    // mix = 0.25); roughness = constant 0.3 + 0.1 (add); metalness = 0.9 - 0.4 (subtract).
    Net n = standardSurface();
    n.add("/M/Tint", "ND_geompropvalue_color3", {{Token("geomprop"), Value(std::string("tint"))}})
        .add("/M/Twice", "ND_multiply_color3FA", {{Token("in2"), Value(2.0f)}})
        .connect("/M/Twice", "in1", "/M/Tint", "out")
        .add("/M/Inv", "ND_invert_color3", {{Token("in"), Value(glm::vec3(0.0f, 0.0f, 1.0f))}})
        .add("/M/Mix", "ND_mix_color3", {{Token("mix"), Value(0.25f)}})
        .connect("/M/Mix", "fg", "/M/Twice", "out")
        .connect("/M/Mix", "bg", "/M/Inv", "out")
        .surfaceFrom("base_color", "/M/Mix", "out")
        .add("/M/C", "ND_constant_float", {{Token("value"), Value(0.3f)}})
        .add("/M/Add", "ND_add_float", {{Token("in2"), Value(0.1f)}})
        .connect("/M/Add", "in1", "/M/C", "out")
        .surfaceFrom("specular_roughness", "/M/Add", "out")
        .add("/M/Sub", "ND_subtract_float", {{Token("in1"), Value(0.9f)}, {Token("in2"), Value(0.4f)}})
        .surfaceFrom("metalness", "/M/Sub", "out");
    MaterialProgram p = compile(n);
    EXPECT_FALSE(p.isConstant());
    ctx.values["tint"] = glm::vec4(0.1f, 0.2f, 0.3f, 0.0f);
    ShadedMaterial m = p.evaluate(ctx);
    // Standard Surface: base (1, the 1.0.1 default) * base_color.
    expectNear(m.params.baseColor, glm::vec3(1.0f, 1.0f, 0.0f) + (glm::vec3(0.2f, 0.4f, 0.6f) - glm::vec3(1.0f, 1.0f, 0.0f)) * 0.25f);
    EXPECT_NEAR(m.params.roughness, 0.4f, 1e-6f);
    EXPECT_NEAR(m.params.metallic, 0.5f, 1e-6f);
    EXPECT_TRUE(notes.empty()) << notes.front();
}

TEST_F(MaterialProgramTest, MaterialXDividePowerMinMaxClamp) {
    // roughness = clamp(g / 0.5, 0.1, 0.7); metalness = max(min(g, 0.3), 0.2); base_color =
    // (tint)^2 (power with a float exponent); coat = 1 / 0 (not finite: 0).
    Net n = standardSurface();
    n.add("/M/G", "ND_geompropvalue_float", {{Token("geomprop"), Value(std::string("g"))}})
        .add("/M/Div", "ND_divide_float", {{Token("in2"), Value(0.5f)}})
        .connect("/M/Div", "in1", "/M/G", "out")
        .add("/M/Clamp", "ND_clamp_float", {{Token("low"), Value(0.1f)}, {Token("high"), Value(0.7f)}})
        .connect("/M/Clamp", "in", "/M/Div", "out")
        .surfaceFrom("specular_roughness", "/M/Clamp", "out")
        .add("/M/Min", "ND_min_float", {{Token("in2"), Value(0.3f)}})
        .connect("/M/Min", "in1", "/M/G", "out")
        .add("/M/Max", "ND_max_float", {{Token("in2"), Value(0.2f)}})
        .connect("/M/Max", "in1", "/M/Min", "out")
        .surfaceFrom("metalness", "/M/Max", "out")
        .add("/M/Tint", "ND_geompropvalue_color3", {{Token("geomprop"), Value(std::string("tint"))}})
        .add("/M/Sq", "ND_power_color3FA", {{Token("in2"), Value(2.0f)}})
        .connect("/M/Sq", "in1", "/M/Tint", "out")
        .surfaceFrom("base_color", "/M/Sq", "out")
        .add("/M/Inf", "ND_divide_float", {{Token("in1"), Value(1.0f)}, {Token("in2"), Value(0.0f)}})
        .surfaceFrom("coat", "/M/Inf", "out");
    MaterialProgram p = compile(n);
    ctx.values["tint"] = glm::vec4(0.5f, 0.2f, 0.9f, 0.0f);
    for (float g : {0.02f, 0.2f, 0.5f}) {
        ctx.values["g"] = glm::vec4(g);
        ShadedMaterial m = p.evaluate(ctx);
        EXPECT_NEAR(m.params.roughness, std::clamp(g / 0.5f, 0.1f, 0.7f), 1e-6f) << g;
        EXPECT_NEAR(m.params.metallic, std::max(std::min(g, 0.3f), 0.2f), 1e-6f) << g;
        expectNear(m.params.baseColor, glm::vec3(0.25f, 0.04f, 0.81f));
        EXPECT_EQ(m.params.clearcoat, 0.0f);
    }
    EXPECT_TRUE(notes.empty()) << notes.front();
}

TEST_F(MaterialProgramTest, MaterialXExtractAndSeparatePickComponents) {
    // An "ORM"-style colour: roughness = extract(index 1), metalness = separate3's outb, and
    // coat = extract(index 0) of a separate3 output (a component of a component).
    Net n = standardSurface();
    n.add("/M/Orm", "ND_geompropvalue_color3", {{Token("geomprop"), Value(std::string("orm"))}})
        .add("/M/Rough", "ND_extract_color3", {{Token("index"), Value(1)}})
        .connect("/M/Rough", "in", "/M/Orm", "out")
        .surfaceFrom("specular_roughness", "/M/Rough", "out")
        .add("/M/Sep", "ND_separate3_color3")
        .connect("/M/Sep", "in", "/M/Orm", "out")
        .surfaceFrom("metalness", "/M/Sep", "outb")
        .add("/M/Ex", "ND_extract_vector2", {{Token("index"), Value(0)}})
        .connect("/M/Ex", "in", "/M/Sep", "outg")
        .surfaceFrom("coat", "/M/Ex", "out");
    MaterialProgram p = compile(n);
    ctx.values["orm"] = glm::vec4(0.1f, 0.2f, 0.3f, 0.0f);
    ShadedMaterial m = p.evaluate(ctx);
    EXPECT_NEAR(m.params.roughness, 0.2f, 1e-6f);
    EXPECT_NEAR(m.params.metallic, 0.3f, 1e-6f);
    EXPECT_NEAR(m.params.clearcoat, 0.2f, 1e-6f);
    EXPECT_TRUE(notes.empty()) << notes.front();
}

TEST_F(MaterialProgramTest, MaterialXUnsupportedNodeNotesAndKeepsTheConstant) {
    Net n = standardSurface();
    n.node("/M/Surface").where = "look.usda:12:9";
    n.add("/M/Mul", "ND_noise2d_color3")
        .surface("base_color", Value(glm::vec3(0.2f, 0.3f, 0.4f)))
        .surfaceFrom("base_color", "/M/Mul", "out");
    n.node("/M/Mul").where = "look.usda:20:5";
    MaterialProgram p = compile(n);
    EXPECT_TRUE(p.isConstant());
    expectNear(p.evaluate(ctx).params.baseColor, glm::vec3(0.2f, 0.3f, 0.4f), 1e-6f);
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_EQ(notes[0],
              "look.usda:20:5: /M/Mul: node 'ND_noise2d_color3' not supported; inputs it feeds "
              "use their authored value or default");
    // A missing image file gives the node's default, with a note naming the node.
    notes.clear();
    Net missing = imageIntoBaseColor(dir.file("gone.png"),
                                     {{Token("default"), Value(glm::vec3(0.0f, 0.5f, 0.0f))}});
    MaterialProgram q = compile(missing);
    EXPECT_TRUE(q.isConstant());
    expectNear(q.evaluate(ctx).params.baseColor, glm::vec3(0.0f, 0.5f, 0.0f), 1e-6f);
    EXPECT_TRUE(anyNoteHas(notes, "/M/Img: ")) << notes.front();
}

TEST_F(MaterialProgramTest, MaterialXAddressModesAndUnsupportedSettingsAreNoted) {
    // Periodic (the default) wraps st 1.375 onto 0.375; clamp holds the last column.
    MaterialProgram periodic = compile(imageIntoBaseColor(png));
    MaterialProgram clamped =
        compile(imageIntoBaseColor(png, {{Token("uaddressmode"), Value(std::string("clamp"))}}));
    glm::vec2 st = centre(1, 2) + glm::vec2(1.0f, 0.0f);
    ctx.values["st"] = glm::vec4(st, 0, 0);
    expectNear(periodic.evaluate(ctx).params.baseColor, decoded(1, 2));
    expectNear(clamped.evaluate(ctx).params.baseColor, decoded(3, 2));
    EXPECT_TRUE(notes.empty()) << notes.front();
    // Closest filtering, an unknown colour space and constant addressing with a non-black
    // default are each noted once; the image still samples.
    MaterialProgram p = compile(
        imageIntoBaseColor(png, {{Token("filtertype"), Value(std::string("closest"))},
                                 {Token("colorSpace:file"), Value(Token("acescg"))},
                                 {Token("vaddressmode"), Value(std::string("constant"))},
                                 {Token("default"), Value(glm::vec3(0.5f))}}));
    EXPECT_EQ(notes.size(), 3u);
    EXPECT_TRUE(anyNoteHas(notes, "filtertype 'closest'"));
    EXPECT_TRUE(anyNoteHas(notes, "colorspace 'acescg'"));
    EXPECT_TRUE(anyNoteHas(notes, "vaddressmode 'constant'"));
    ctx.values["st"] = glm::vec4(centre(2, 2), 0, 0);
    expectNear(p.evaluate(ctx).params.baseColor, decoded(2, 2));  // 8-bit: auto decodes sRGB
}

TEST_F(MaterialProgramTest, MaterialXPlace2dMovesTexcoords) {
    // place2d between texcoord and image, with the given inputs; the image feeds base_color.
    auto placed = [&](std::map<Token, Value> place) {
        Net n = imageIntoBaseColor(png);
        n.add("/M/Place", "ND_place2d_vector2", std::move(place))
            .connect("/M/Place", "texcoord", "/M/Uv", "out");
        n.node("/M/Img").inputConnections.clear();
        n.connect("/M/Img", "texcoord", "/M/Place", "out");
        return compile(n);
    };
    // SRT: (uv - pivot) / scale, rotated, - offset, + pivot. Scale 0.5, offset (0.25, 0):
    // out = 2 uv - (0.25, 0).
    MaterialProgram srt = placed({{Token("scale"), Value(glm::vec2(0.5f))},
                                  {Token("offset"), Value(glm::vec2(0.25f, 0.0f))}});
    glm::vec2 target = centre(1, 3);
    ctx.values["st"] = glm::vec4((target + glm::vec2(0.25f, 0.0f)) / 2.0f, 0, 0);
    expectNear(srt.evaluate(ctx).params.baseColor, decoded(1, 3));
    // TRS: (uv - pivot - offset) rotated, / scale, + pivot: out = 2 (uv - (0.25, 0)).
    MaterialProgram trs = placed({{Token("scale"), Value(glm::vec2(0.5f))},
                                  {Token("offset"), Value(glm::vec2(0.25f, 0.0f))},
                                  {Token("operationorder"), Value(1)}});
    target = centre(2, 0);
    ctx.values["st"] = glm::vec4(target / 2.0f + glm::vec2(0.25f, 0.0f), 0, 0);
    expectNear(trs.evaluate(ctx).params.baseColor, decoded(2, 0));
    // 90 degrees about the centre, clockwise as MaterialX's rotate2d: (x, y) -> (y, -x).
    MaterialProgram rot = placed({{Token("rotate"), Value(90.0f)},
                                  {Token("pivot"), Value(glm::vec2(0.5f))}});
    ctx.values["st"] = glm::vec4(centre(1, 2), 0, 0);  // (-0.125, -0.125) from the pivot
    expectNear(rot.evaluate(ctx).params.baseColor, decoded(1, 1));  // (-0.125, +0.125)
    EXPECT_TRUE(notes.empty()) << notes.front();
}
