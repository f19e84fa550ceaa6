// SPDX-License-Identifier: Apache-2.0
// Texture and material-program throughput, single thread (docs/materials.md records results).
#include <benchmark/benchmark.h>

#include <map>
#include <random>

#include "delegate/shading/materialProgram.h"
#include "testImages.h"

using namespace principled;
using namespace principled::shading;

namespace {

constexpr int kSize = 1024;  // texture resolution
constexpr int kPoints = 4096;

// One texture file per format, written once per process.
struct Fixture {
    test::TempDir dir;
    std::string png8, exr;
    std::vector<glm::vec2> st;

    Fixture() {
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> u(0.0f, 1.0f);
        std::vector<float> px(size_t(kSize) * kSize * 3);
        for (float& v : px) v = u(rng);
        png8 = dir.file("noise8.png");
        exr = dir.file("noise.exr");
        test::writeImage(png8, kSize, kSize, 3, px, OIIO::TypeDesc::UINT8);
        test::writeImage(exr, kSize, kSize, 3, px, OIIO::TypeDesc::FLOAT);
        for (int i = 0; i < kPoints; ++i) st.emplace_back(u(rng), u(rng));
    }
    static Fixture& get() {
        static Fixture f;
        return f;
    }
};

class StContext : public ShadingContext {
  public:
    glm::vec2 st{0.0f};
    glm::vec2 d{0.0f};
    bool primvar(const hd::Token&, int components, float* out) const override {
        out[0] = st.x;
        if (components > 1) out[1] = st.y;
        return true;
    }
    bool primvarDerivatives(const hd::Token&, glm::vec2* dx, glm::vec2* dy) const override {
        *dx = glm::vec2(d.x, 0.0f);
        *dy = glm::vec2(0.0f, d.y);
        return d != glm::vec2(0.0f);
    }
};

// state.range(0): 0 = 8-bit PNG, 1 = float EXR; range(1): footprint in texels (0 = point).
void textureSample(benchmark::State& state) {
    Fixture& f = Fixture::get();
    TextureCache cache;
    const Texture* t = cache.open(state.range(0) ? f.exr : f.png8).texture;
    float fp = float(state.range(1)) / kSize;
    glm::vec4 footprint(fp, 0.0f, 0.0f, fp);
    int i = 0;
    for (auto _ : state) {
        glm::vec4 c = cache.sample(*t, Wrap::Repeat, Wrap::Repeat, f.st[i], footprint);
        benchmark::DoNotOptimize(c);
        i = (i + 1) & (kPoints - 1);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(textureSample)->ArgsProduct({{0, 1}, {0, 1, 8}});

// Scanline-coherent st (one texel apart, as neighbouring camera rays on a facing plane).
void textureSampleCoherent(benchmark::State& state) {
    Fixture& f = Fixture::get();
    TextureCache cache;
    const Texture* t = cache.open(state.range(0) ? f.exr : f.png8).texture;
    int i = 0;
    for (auto _ : state) {
        glm::vec2 st((i & (kSize - 1)) + 0.5f, (i >> 10 & (kSize - 1)) + 0.5f);
        glm::vec4 c = cache.sample(*t, Wrap::Repeat, Wrap::Repeat, st / float(kSize));
        benchmark::DoNotOptimize(c);
        ++i;
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(textureSampleCoherent)->Arg(0)->Arg(1);

hd::MaterialNetwork texturedNetwork(const std::string& file) {
    hd::MaterialNetwork net;
    hd::MaterialNode st, tex, surf;
    st.path = hd::Path("/M/St");
    st.identifier = hd::Token("UsdPrimvarReader_float2");
    st.parameters[hd::Token("varname")] = hd::Value(std::string("st"));
    tex.path = hd::Path("/M/Tex");
    tex.identifier = hd::Token("UsdUVTexture");
    tex.parameters[hd::Token("file")] = hd::Value(file);
    tex.parameters[hd::Token("wrapS")] = hd::Value(hd::Token("repeat"));
    tex.parameters[hd::Token("wrapT")] = hd::Value(hd::Token("repeat"));
    tex.inputConnections[hd::Token("st")] = {{st.path, hd::Token("result")}};
    surf.path = hd::Path("/M/Surface");
    surf.identifier = hd::Token("UsdPreviewSurface");
    surf.inputConnections[hd::Token("diffuseColor")] = {{tex.path, hd::Token("rgb")}};
    surf.inputConnections[hd::Token("roughness")] = {{tex.path, hd::Token("g")}};
    net.nodes = {st, tex, surf};
    net.surfaceTerminal = surf.path;
    return net;
}

// Evaluates the program of `net` at the fixture's st points, one per iteration.
void evaluateAtPoints(benchmark::State& state, const hd::MaterialNetwork& net) {
    Fixture& f = Fixture::get();
    TextureCache cache;
    std::vector<std::string> notes;
    MaterialProgram p = MaterialProgram::compile(net, cache, &notes);
    StContext ctx;
    int i = 0;
    for (auto _ : state) {
        ctx.st = f.st[i];
        ShadedMaterial m = p.evaluate(ctx);
        benchmark::DoNotOptimize(m);
        i = (i + 1) & (kPoints - 1);
    }
    state.SetItemsProcessed(state.iterations());
}

// A UsdPreviewSurface with a primvar-driven sRGB texture on diffuseColor and roughness.
void evaluateTextured(benchmark::State& state) {
    evaluateAtPoints(state, texturedNetwork(Fixture::get().png8));
}
BENCHMARK(evaluateTextured);

// The same lookup through MaterialX nodes: texcoord -> ND_image_color3 -> Standard Surface
// base_color, times a base weight of 0.9 (one MulAdd op per evaluation).
hd::MaterialNetwork standardSurfaceNetwork(const std::string& file) {
    hd::MaterialNetwork net;
    hd::MaterialNode uv, img, surf;
    uv.path = hd::Path("/M/Uv");
    uv.identifier = hd::Token("ND_texcoord_vector2");
    img.path = hd::Path("/M/Img");
    img.identifier = hd::Token("ND_image_color3");
    img.parameters[hd::Token("file")] = hd::Value(file);
    img.inputConnections[hd::Token("texcoord")] = {{uv.path, hd::Token("out")}};
    surf.path = hd::Path("/M/Surface");
    surf.identifier = hd::Token("ND_standard_surface_surfaceshader");
    surf.parameters[hd::Token("base")] = hd::Value(0.9f);
    surf.inputConnections[hd::Token("base_color")] = {{img.path, hd::Token("out")}};
    net.nodes = {uv, img, surf};
    net.surfaceTerminal = surf.path;
    return net;
}

void evaluateStandardSurfaceTextured(benchmark::State& state) {
    evaluateAtPoints(state, standardSurfaceNetwork(Fixture::get().png8));
}
BENCHMARK(evaluateStandardSurfaceTextured);

void evaluateConstant(benchmark::State& state) {
    TextureCache cache;
    std::vector<std::string> notes;
    hd::MaterialNetwork net;
    hd::MaterialNode surf;
    surf.path = hd::Path("/M/Surface");
    surf.identifier = hd::Token("UsdPreviewSurface");
    surf.parameters[hd::Token("roughness")] = hd::Value(0.3f);
    net.nodes = {surf};
    net.surfaceTerminal = surf.path;
    MaterialProgram p = MaterialProgram::compile(net, cache, &notes);
    StContext ctx;
    for (auto _ : state) {
        ShadedMaterial m = p.evaluate(ctx);
        benchmark::DoNotOptimize(m);
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(evaluateConstant);

}  // namespace

BENCHMARK_MAIN();
