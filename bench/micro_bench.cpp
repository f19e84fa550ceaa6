// SPDX-License-Identifier: Apache-2.0
// Microbenchmarks of the renderer's hot paths, each next to a baseline measured in the same run
// (issue 7). Speed is stated as a ratio to that baseline, never as a timed test.
//   BVH build        Mtris/s (wall and per process CPU-second) at the delegate's qualities
//                    (MEDIUM for a first build, LOW for an edit's rebuild) and at HIGH, with
//                    the vertex and index arrays shared as the delegate does; baseline: copying
//                    the same vertex+index data. Also bytes per triangle of Embree memory
//                    (target < 100).
//   Ray casting      Mrays/s, incoherent (random origins and directions inside a closed mesh)
//                    against coherent (primary camera rays in scanline order), rtcIntersect1.
//   Subdivision      refined Mtris/s (SubdivTopology::refine, re-pose) per level.
//   USDA parse       MB/s of Stage::openString on a generated mesh scene; baseline: strtof over
//                    the same numbers (the floor for any text parser).
//   Texture lookup   M lookups/s through TextureCache at a point footprint (bilinear on the
//                    finest level): resident pixels (BM_TextureLookup) and OpenImageIO's texture
//                    system (BM_TextureLookup_oiioTextureSystem, resident budget 0), against a
//                    hand-written bilinear fetch from a float array in memory.
// BSDF eval/sample: bench/bsdf_bench.cpp (target bsdf_bench), not duplicated here.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <glm/glm.hpp>

#include "delegate/light.h"
#include "delegate/lightSampling.h"
#include "delegate/shading/textureCache.h"
#include "delegate/subdiv/subdivTopology.h"
#include "scene_adapter/usda/stage.h"
#include "tests/delegate/subdiv/subdivTestMeshes.h"

using namespace principled;

namespace {

// ---------------------------------------------------------------------------------------------
// Geometry: a UV sphere of about `tris` triangles (closed, so incoherent rays always hit).
struct TriMesh {
    std::vector<glm::vec3> p;
    std::vector<glm::uvec3> t;
};

TriMesh sphere(int tris) {
    const int rings = std::max(4, int(std::sqrt(tris / 2.0)));
    const int segs = std::max(4, tris / (2 * rings));
    TriMesh m;
    for (int i = 0; i <= rings; ++i) {
        const float th = float(M_PI) * float(i) / float(rings);
        for (int j = 0; j < segs; ++j) {
            const float ph = 2.0f * float(M_PI) * float(j) / float(segs);
            // A slightly bumpy sphere so the BVH is not trivially regular.
            const float r = 1.0f + 0.02f * std::sin(7.0f * th) * std::cos(5.0f * ph);
            m.p.emplace_back(r * std::sin(th) * std::cos(ph), r * std::cos(th), r * std::sin(th) * std::sin(ph));
        }
    }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segs; ++j) {
            unsigned a = i * segs + j, b = i * segs + (j + 1) % segs;
            unsigned c = (i + 1) * segs + j, d = (i + 1) * segs + (j + 1) % segs;
            m.t.push_back({a, c, b});
            m.t.push_back({b, c, d});
        }
    return m;
}

std::atomic<long long> gEmbreeBytes{0};
bool memoryMonitor(void*, ssize_t bytes, bool) {
    gEmbreeBytes += bytes;
    return true;
}

RTCDevice device() {
    static RTCDevice d = [] {
        RTCDevice dev = rtcNewDevice(nullptr);
        rtcSetDeviceMemoryMonitorFunction(dev, memoryMonitor, nullptr);
        return dev;
    }();
    return d;
}

// As delegate/mesh.cpp and delegate/embreeInstance.cpp build a mesh's BLAS: ROBUST, the
// requested quality, and the vertex and index arrays shared with Embree (not copied).
RTCScene buildScene(const TriMesh& m, RTCBuildQuality q) {
    RTCScene s = rtcNewScene(device());
    rtcSetSceneFlags(s, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(s, q);
    RTCGeometry g = rtcNewGeometry(device(), RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(g, q);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, m.p.data(), 0,
                               sizeof(glm::vec3), m.p.size());
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, m.t.data(), 0,
                               sizeof(glm::uvec3), m.t.size());
    rtcCommitGeometry(g);
    rtcAttachGeometry(s, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(s);
    return s;
}

const TriMesh& bigMesh() {
    static TriMesh m = [] {
        TriMesh t = sphere(1 << 20);  // ~1M triangles
        t.p.reserve(t.p.size() + 1);  // Embree's 16-byte vertex loads stay inside (shared buffer)
        return t;
    }();
    return m;
}

// ---------------------------------------------------------------------------------------------
// BVH build.
double processCpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

void BM_BvhBuild(benchmark::State& state) {
    const TriMesh& m = bigMesh();
    const auto q = RTCBuildQuality(state.range(0));
    long long bytes = 0;
    double cpu = 0.0;  // process CPU (Embree's build threads included)
    for (auto _ : state) {
        const long long before = gEmbreeBytes.load();
        const double c0 = processCpuSeconds();
        RTCScene s = buildScene(m, q);
        cpu += processCpuSeconds() - c0;
        bytes = gEmbreeBytes.load() - before;
        benchmark::DoNotOptimize(s);
        state.PauseTiming();
        rtcReleaseScene(s);
        state.ResumeTiming();
    }
    state.counters["tris"] = double(m.t.size());
    state.counters["Mtris/s"] = benchmark::Counter(double(m.t.size()) * state.iterations() * 1e-6,
                                                   benchmark::Counter::kIsRate);
    state.counters["Mtris/CPU-s"] = double(m.t.size()) * state.iterations() * 1e-6 / cpu;
    state.counters["bytes/tri"] = double(bytes) / double(m.t.size());
}
BENCHMARK(BM_BvhBuild)->Arg(RTC_BUILD_QUALITY_HIGH)->Arg(RTC_BUILD_QUALITY_MEDIUM)->Arg(RTC_BUILD_QUALITY_LOW)
    ->ArgName("quality(0low,1med,2high)")->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// Baseline: the memcpy of the same buffers that every build starts with.
void BM_BvhBuild_baselineCopy(benchmark::State& state) {
    const TriMesh& m = bigMesh();
    std::vector<glm::vec3> p(m.p.size());
    std::vector<glm::uvec3> t(m.t.size());
    for (auto _ : state) {
        std::memcpy(p.data(), m.p.data(), m.p.size() * sizeof(glm::vec3));
        std::memcpy(t.data(), m.t.data(), m.t.size() * sizeof(glm::uvec3));
        benchmark::ClobberMemory();
    }
    state.counters["Mtris/s"] = benchmark::Counter(double(m.t.size()) * state.iterations() * 1e-6,
                                                   benchmark::Counter::kIsRate);
}
BENCHMARK(BM_BvhBuild_baselineCopy)->Unit(benchmark::kMillisecond)->UseRealTime();

// ---------------------------------------------------------------------------------------------
// Ray casting.
struct RaySet {
    std::vector<glm::vec3> o, d;
};

RaySet incoherentRays(size_t n) {
    RaySet r;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    while (r.o.size() < n) {
        glm::vec3 o(u(rng), u(rng), u(rng)), d(u(rng), u(rng), u(rng));
        if (glm::dot(o, o) > 0.5f || glm::dot(d, d) > 1.0f || glm::dot(d, d) < 1e-4f) continue;
        r.o.push_back(o);
        r.d.push_back(glm::normalize(d));
    }
    return r;
}

RaySet coherentRays(size_t n) {  // a pinhole camera at z = 3 looking at the sphere, scanline order
    RaySet r;
    const int w = int(std::sqrt(double(n)));
    for (int y = 0; y < w; ++y)
        for (int x = 0; x < w; ++x) {
            r.o.emplace_back(0.0f, 0.0f, 3.0f);
            r.d.push_back(glm::normalize(glm::vec3((x + 0.5f) / w - 0.5f, (y + 0.5f) / w - 0.5f, -1.0f)));
        }
    return r;
}

RTCScene castScene() {
    static RTCScene s = buildScene(bigMesh(), RTC_BUILD_QUALITY_MEDIUM);  // as the delegate
    return s;
}

void castAll(const RaySet& rays, bool occluded, benchmark::State& state) {
    RTCScene s = castScene();
    RTCIntersectContext ctx;
    size_t hits = 0;
    for (auto _ : state) {
        for (size_t i = 0; i < rays.o.size(); ++i) {
            if (occluded) {
                RTCRay ray{};
                ray.org_x = rays.o[i].x; ray.org_y = rays.o[i].y; ray.org_z = rays.o[i].z;
                ray.dir_x = rays.d[i].x; ray.dir_y = rays.d[i].y; ray.dir_z = rays.d[i].z;
                ray.tnear = 0.0f; ray.tfar = 1e30f; ray.mask = ~0u; ray.flags = 0;
                rtcInitIntersectContext(&ctx);
                rtcOccluded1(s, &ctx, &ray);
                hits += ray.tfar < 0.0f;
            } else {
                RTCRayHit rh{};
                rh.ray.org_x = rays.o[i].x; rh.ray.org_y = rays.o[i].y; rh.ray.org_z = rays.o[i].z;
                rh.ray.dir_x = rays.d[i].x; rh.ray.dir_y = rays.d[i].y; rh.ray.dir_z = rays.d[i].z;
                rh.ray.tnear = 0.0f; rh.ray.tfar = 1e30f; rh.ray.mask = ~0u; rh.ray.flags = 0;
                rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                rtcInitIntersectContext(&ctx);
                rtcIntersect1(s, &ctx, &rh);
                hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            }
        }
    }
    benchmark::DoNotOptimize(hits);
    state.counters["Mrays/s"] = benchmark::Counter(double(rays.o.size()) * state.iterations() * 1e-6,
                                                   benchmark::Counter::kIsRate);
    state.counters["hitFraction"] = double(hits) / double(rays.o.size() * state.iterations());
}

constexpr size_t kRays = 1 << 18;
void BM_RayCast_incoherent(benchmark::State& state) {
    static RaySet r = incoherentRays(kRays);
    castAll(r, false, state);
}
void BM_RayCast_incoherentOccluded(benchmark::State& state) {
    static RaySet r = incoherentRays(kRays);
    castAll(r, true, state);
}
void BM_RayCast_baselineCoherent(benchmark::State& state) {
    static RaySet r = coherentRays(kRays);
    castAll(r, false, state);
}
BENCHMARK(BM_RayCast_baselineCoherent)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RayCast_incoherent)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RayCast_incoherentOccluded)->Unit(benchmark::kMillisecond);

// ---------------------------------------------------------------------------------------------
// Subdivision refine (re-pose: the per-frame cost once the topology is built).
void BM_SubdivRefine(benchmark::State& state) {
    const int level = int(state.range(0));
    subdiv::test::Cage g = subdiv::test::grid(64);
    for (glm::vec3& p : g.points) p.z = 0.1f * std::sin(p.x) * std::cos(p.y);
    subdiv::BuildOptions o{level};
    std::string err;
    auto t = subdiv::SubdivTopology::create(g.topology, {}, g.points.size(), o, &err);
    if (!t) {
        state.SkipWithError(err.c_str());
        return;
    }
    subdiv::RefinedMesh m;
    for (auto _ : state) {
        t->refine(g.points, &m);
        benchmark::ClobberMemory();
    }
    state.counters["refinedTris"] = double(m.triangles.size());
    state.counters["Mtris/s"] = benchmark::Counter(double(m.triangles.size()) * state.iterations() * 1e-6,
                                                   benchmark::Counter::kIsRate);
}
BENCHMARK(BM_SubdivRefine)->Arg(1)->Arg(2)->Arg(3)->Arg(4)->ArgName("level")->Unit(benchmark::kMillisecond);

// ---------------------------------------------------------------------------------------------
// USDA parse.
const std::string& usdaText() {
    static std::string text = [] {
        const TriMesh m = sphere(100000);
        std::ostringstream s;
        s << "#usda 1.0\n(\n    upAxis = \"Y\"\n)\n\ndef Xform \"World\"\n{\n    def Mesh \"M\"\n    {\n";
        s << "        int[] faceVertexCounts = [";
        for (size_t i = 0; i < m.t.size(); ++i) s << (i ? ", " : "") << 3;
        s << "]\n        int[] faceVertexIndices = [";
        for (size_t i = 0; i < m.t.size(); ++i)
            s << (i ? ", " : "") << m.t[i].x << ", " << m.t[i].y << ", " << m.t[i].z;
        s << "]\n        point3f[] points = [";
        char buf[96];
        for (size_t i = 0; i < m.p.size(); ++i) {
            std::snprintf(buf, sizeof buf, "%s(%.6g, %.6g, %.6g)", i ? ", " : "", m.p[i].x, m.p[i].y, m.p[i].z);
            s << buf;
        }
        s << "]\n    }\n}\n";
        return s.str();
    }();
    return text;
}

void BM_UsdaParse(benchmark::State& state) {
    const std::string& text = usdaText();
    for (auto _ : state) {
        auto stage = usd::Stage::openString(text, "bench.usda");
        benchmark::DoNotOptimize(stage.get());
    }
    state.counters["MB"] = double(text.size()) * 1e-6;
    state.counters["MB/s"] = benchmark::Counter(double(text.size()) * state.iterations() * 1e-6,
                                                benchmark::Counter::kIsRate);
}
// Baseline: strtof over every number of the same text, skipping punctuation.
void BM_UsdaParse_baselineStrtof(benchmark::State& state) {
    const std::string& text = usdaText();
    for (auto _ : state) {
        float sum = 0;
        const char* p = text.c_str();
        while (*p) {
            if ((*p >= '0' && *p <= '9') || *p == '-' || *p == '.') {
                char* end;
                sum += std::strtof(p, &end);
                p = end == p ? p + 1 : end;
            } else {
                ++p;
            }
        }
        benchmark::DoNotOptimize(sum);
    }
    state.counters["MB/s"] = benchmark::Counter(double(text.size()) * state.iterations() * 1e-6,
                                                benchmark::Counter::kIsRate);
}
BENCHMARK(BM_UsdaParse_baselineStrtof)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_UsdaParse)->Unit(benchmark::kMillisecond);

// ---------------------------------------------------------------------------------------------
// Texture lookup.
constexpr int kTex = 512;
const std::vector<float>& texels() {
    static std::vector<float> t = [] {
        std::vector<float> v(size_t(kTex) * kTex * 3);
        for (int y = 0; y < kTex; ++y)
            for (int x = 0; x < kTex; ++x)
                for (int c = 0; c < 3; ++c)
                    v[(size_t(y) * kTex + x) * 3 + c] = float(((x / 32 + y / 32) & 1) ^ (c == 1)) * 0.8f + 0.1f;
        return v;
    }();
    return t;
}

struct TempFile {
    std::string path;
    ~TempFile() { std::remove(path.c_str()); }
};

std::string texturePath() {
    static TempFile file{[] {
        std::string p = "/tmp/principled_bench_tex_" + std::to_string(::getpid()) + ".exr";
        auto out = OIIO::ImageOutput::create(p);
        OIIO::ImageSpec spec(kTex, kTex, 3, OIIO::TypeDesc::FLOAT);
        out->open(p, spec);
        out->write_image(OIIO::TypeDesc::FLOAT, texels().data());
        out->close();
        return p;
    }()};
    return file.path;
}

std::vector<glm::vec2> randomSt(size_t n) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<glm::vec2> st(n);
    for (auto& s : st) s = {u(rng), u(rng)};
    return st;
}

constexpr size_t kLookups = 1 << 16;
void textureLookups(benchmark::State& state, shading::TextureCache& cache) {
    auto r = cache.open(texturePath());
    if (!r.texture) {
        state.SkipWithError(r.error.c_str());
        return;
    }
    static std::vector<glm::vec2> st = randomSt(kLookups);
    glm::vec4 acc(0.0f);
    for (auto _ : state)
        for (const glm::vec2& s : st)
            acc += cache.sample(*r.texture, shading::Wrap::Repeat, shading::Wrap::Repeat, s);
    benchmark::DoNotOptimize(acc);
    state.counters["Mlookups/s"] = benchmark::Counter(double(st.size()) * state.iterations() * 1e-6,
                                                      benchmark::Counter::kIsRate);
}
void BM_TextureLookup(benchmark::State& state) {
    static shading::TextureCache cache;  // the file fits the resident budget
    textureLookups(state, cache);
}
void BM_TextureLookup_oiioTextureSystem(benchmark::State& state) {
    static shading::TextureCache cache([] {
        shading::TextureCache::Options o;
        o.maxResidentMB = 0.0;  // every lookup through OpenImageIO's texture system
        return o;
    }());
    textureLookups(state, cache);
}
void BM_TextureLookup_baselineBilinear(benchmark::State& state) {
    const std::vector<float>& t = texels();
    static std::vector<glm::vec2> st = randomSt(kLookups);
    glm::vec3 acc(0.0f);
    auto at = [&](int x, int y) {
        x = (x % kTex + kTex) % kTex;
        y = (y % kTex + kTex) % kTex;
        const float* p = &t[(size_t(y) * kTex + x) * 3];
        return glm::vec3(p[0], p[1], p[2]);
    };
    for (auto _ : state)
        for (const glm::vec2& s : st) {
            const float fx = s.x * kTex - 0.5f, fy = (1.0f - s.y) * kTex - 0.5f;
            const int x = int(std::floor(fx)), y = int(std::floor(fy));
            const float ax = fx - float(x), ay = fy - float(y);
            acc += glm::mix(glm::mix(at(x, y), at(x + 1, y), ax), glm::mix(at(x, y + 1), at(x + 1, y + 1), ax), ay);
        }
    benchmark::DoNotOptimize(acc);
    state.counters["Mlookups/s"] = benchmark::Counter(double(st.size()) * state.iterations() * 1e-6,
                                                      benchmark::Counter::kIsRate);
}
BENCHMARK(BM_TextureLookup_baselineBilinear)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_TextureLookup)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_TextureLookup_oiioTextureSystem)->Unit(benchmark::kMicrosecond);

// Mesh light sampling (delegate/lightSampling.cpp): scenes/cornell.usda's light, a 0.5 x 0.5
// quad of two triangles at y = 1.999, sampled from points spread through the box [-1, 1] x
// [0, 2] x [-1, 1] (~9 % within the 2 bounding radii where solid-angle sampling is used).
// Baseline in the same run: the same light with lightSolidAngle=0 (area sampling: one triangle
// pick, one point, no trigonometry).
struct CornellLight {
    embree::GeometryRecord mesh;
    embree::LightRecord light;
    std::vector<glm::vec3> points;
    explicit CornellLight(bool solidAngle) {
        mesh.points = {{-0.25f, 1.999f, -0.25f}, {0.25f, 1.999f, -0.25f}, {0.25f, 1.999f, 0.25f}, {-0.25f, 1.999f, 0.25f}};
        mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
        light.kind = embree::LightRecord::Kind::Mesh;
        light.solidAngleSampling = solidAngle;
        light.mesh = &mesh;
        light.meshTriangles = std::make_shared<std::vector<uint32_t>>(std::vector<uint32_t>{0, 1});
        light.meshAreaCdf = std::make_shared<std::vector<float>>(std::vector<float>{0.0f, 0.5f, 1.0f});
        light.area = 0.25f;
        light.center = glm::vec3(0.0f, 1.999f, 0.0f);
        light.radius = 0.25f * std::sqrt(2.0f);
        embree::prepareMeshLight(&light);
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> U(0.0f, 1.0f);
        for (int i = 0; i < 4096; ++i) points.push_back({2.0f * U(rng) - 1.0f, 1.99f * U(rng), 2.0f * U(rng) - 1.0f});
    }
};
void meshLightSamples(benchmark::State& state, bool solidAngle) {
    static CornellLight scenes[2] = {CornellLight(false), CornellLight(true)};
    const CornellLight& c = scenes[solidAngle ? 1 : 0];
    std::mt19937 rng(9);
    std::uniform_real_distribution<float> U(0.0f, 0.99999994f);
    std::vector<glm::vec2> us(c.points.size());
    for (auto& u : us) u = {U(rng), U(rng)};
    float acc = 0.0f;
    for (auto _ : state)
        for (size_t i = 0; i < c.points.size(); ++i) {
            embree::LightSample ls;
            if (embree::sampleLight(c.light, c.points[i], glm::vec3(0, 1, 0), us[i], &ls)) acc += ls.pdf + ls.wi.x;
        }
    benchmark::DoNotOptimize(acc);
    state.counters["Msamples/s"] = benchmark::Counter(double(c.points.size()) * state.iterations() * 1e-6,
                                                      benchmark::Counter::kIsRate);
}
void BM_MeshLightSample(benchmark::State& state) { meshLightSamples(state, true); }
void BM_MeshLightSample_baselineArea(benchmark::State& state) { meshLightSamples(state, false); }
BENCHMARK(BM_MeshLightSample_baselineArea)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MeshLightSample)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
