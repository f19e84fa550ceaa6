// SPDX-License-Identifier: Apache-2.0
// Microbenchmarks of the BSDF library: ns per eval (with pdf) and per sample, per model and
// variant, plus construction. Directions are precomputed so only the BSDF is timed.
#include <benchmark/benchmark.h>

#include <vector>

#include "bsdf/bsdf.h"
#include "bsdf/rng.h"
#include "bsdf/warp.h"

namespace {

using namespace principled::bsdf;

struct Variant {
    const char* name;
    MaterialParams params;
    Options options;
};

std::vector<Variant> variants() {
    std::vector<Variant> v;
    MaterialParams plastic;
    plastic.baseColor = {0.8f, 0.5f, 0.3f};
    plastic.roughness = 0.4f;
    Options disney;
    v.push_back({"disney_plastic", plastic, disney});
    Options legacy = disney;
    legacy.legacySpecularG = true;
    v.push_back({"disney_plastic_legacyG", plastic, legacy});
    Options classic = disney;
    classic.vndfSampling = false;
    v.push_back({"disney_plastic_classicSampling", plastic, classic});
    MaterialParams full = plastic;
    full.sheen = 1.0f;
    full.clearcoat = 1.0f;
    full.anisotropic = 0.5f;
    full.subsurface = 0.5f;
    v.push_back({"disney_full_5lobes", full, disney});
    MaterialParams glass = plastic;
    glass.specTrans = 1.0f;
    v.push_back({"disney_roughGlass", glass, disney});
    MaterialParams metal = plastic;
    metal.metallic = 1.0f;
    v.push_back({"disney_metal", metal, disney});
    MaterialParams tinyCoat = plastic;
    tinyCoat.clearcoat = 1e-5f;
    Options noPrune = disney;
    noPrune.pruneLobes = false;
    v.push_back({"disney_tinyClearcoat_pruned", tinyCoat, disney});
    v.push_back({"disney_tinyClearcoat_unpruned", tinyCoat, noPrune});
    Options ue4;
    ue4.model = Model::UE4;
    v.push_back({"ue4_plastic", plastic, ue4});
    v.push_back({"ue4_metal", metal, ue4});
    return v;
}

constexpr int kDirs = 4096;

struct Dirs {
    std::vector<glm::vec3> wo, wi;
    std::vector<glm::vec3> u;
    Dirs() {
        Pcg32 rng(3);
        for (int i = 0; i < kDirs; ++i) {
            glm::vec3 a = squareToCosineHemisphere({rng.uniform(), rng.uniform()});
            glm::vec3 b = squareToCosineHemisphere({rng.uniform(), rng.uniform()});
            wo.push_back(a);
            wi.push_back(b);
            u.push_back({rng.uniform(), rng.uniform(), rng.uniform()});
        }
    }
};
const Dirs& dirs() {
    static Dirs d;
    return d;
}

void BM_Eval(benchmark::State& state, Variant v) {
    Bsdf b(v.params, v.options);
    const Dirs& d = dirs();
    int i = 0;
    for (auto _ : state) {
        float pdf;
        glm::vec3 f = b.eval(d.wo[i], d.wi[i], &pdf);
        benchmark::DoNotOptimize(f);
        benchmark::DoNotOptimize(pdf);
        i = (i + 1) & (kDirs - 1);
    }
}

void BM_Sample(benchmark::State& state, Variant v) {
    Bsdf b(v.params, v.options);
    const Dirs& d = dirs();
    int i = 0;
    for (auto _ : state) {
        auto s = b.sample(d.wo[i], d.u[i].z, {d.u[i].x, d.u[i].y});
        benchmark::DoNotOptimize(s);
        i = (i + 1) & (kDirs - 1);
    }
}

void BM_Construct(benchmark::State& state, Variant v) {
    for (auto _ : state) {
        Bsdf b(v.params, v.options);
        benchmark::DoNotOptimize(b);
    }
}

int registerAll() {
    for (const Variant& v : variants()) {
        benchmark::RegisterBenchmark((std::string("eval/") + v.name).c_str(), BM_Eval, v);
        benchmark::RegisterBenchmark((std::string("sample/") + v.name).c_str(), BM_Sample, v);
        benchmark::RegisterBenchmark((std::string("construct/") + v.name).c_str(), BM_Construct, v);
    }
    return 0;
}
const int kRegistered = registerAll();

}  // namespace

BENCHMARK_MAIN();
