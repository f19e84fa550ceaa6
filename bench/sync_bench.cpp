// SPDX-License-Identifier: Apache-2.0
// Incremental sync after one host edit against a full load of the same stage, both measured in
// this run (issue 5). The stage is generated: kMeshes grid meshes of about 1000 triangles each
// (about 1M triangles), kMaterials UsdPreviewSurface materials bound round-robin, under
// kGroups Xforms. Each incremental case is one edit through adapter::StageEditor plus
// RenderIndex::sync() (which includes the delegate's commit: top-level BVH, material and light
// tables); the figure "vsFullLoad" is its mean time divided by the fastest full load
// (parse + compose + populate + first sync, BM_FullLoad) of the same run, "editShare" the
// part spent in the editor (check, apply, mark) and "primsSynced" the prims the sync pulled.
//   BM_FullLoad                   host::RenderSession::openString of the generated text
//   BM_Edit_MaterialInput         inputs:diffuseColor of one material
//   BM_Edit_Transform             the local transform of one mesh
//   BM_Edit_GroupTransform        the transform of one Xform holding kMeshes/kGroups meshes
//   BM_Edit_Points                the points of one mesh (same count)
//   BM_Edit_Binding               material:binding of one mesh
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "delegate/hd/renderIndex.h"
#include "plugins/renderSession.h"
#include "scene_adapter/stageEditor.h"

using namespace principled;

namespace {

constexpr int kMeshes = 1000;
constexpr int kGroups = 10;
constexpr int kMaterials = 10;
constexpr int kGrid = 22;  // kGrid x kGrid quads: 2 * 22 * 22 = 968 triangles per mesh

std::vector<double> gridPoints(int m, double lift) {
    std::vector<double> p;
    double ox = (m % 40) * 1.2, oy = (m / 40) * 1.2;
    for (int j = 0; j <= kGrid; ++j)
        for (int i = 0; i <= kGrid; ++i) {
            double x = double(i) / kGrid, y = double(j) / kGrid;
            p.insert(p.end(), {ox + x, oy + y, lift + 0.05 * std::sin(6.0 * (x + y))});
        }
    return p;
}

const std::string& sceneText() {
    static const std::string text = [] {
        std::string s = "#usda 1.0\n(\n    upAxis = \"Z\"\n)\ndef Xform \"World\"\n{\n";
        char buf[64];
        std::string counts, indices;
        for (int q = 0; q < kGrid * kGrid; ++q) {
            int i = q % kGrid, j = q / kGrid, a = j * (kGrid + 1) + i;
            counts += (q ? ", 4" : "4");
            std::snprintf(buf, sizeof buf, "%s%d, %d, %d, %d", q ? ", " : "", a, a + 1,
                          a + kGrid + 2, a + kGrid + 1);
            indices += buf;
        }
        for (int g = 0; g < kGroups; ++g) {
            s += "    def Xform \"G" + std::to_string(g) + "\"\n    {\n";
            for (int m = g * (kMeshes / kGroups); m < (g + 1) * (kMeshes / kGroups); ++m) {
                s += "        def Mesh \"M" + std::to_string(m) + "\"\n        {\n";
                s += "            uniform token subdivisionScheme = \"none\"\n";
                s += "            int[] faceVertexCounts = [" + counts + "]\n";
                s += "            int[] faceVertexIndices = [" + indices + "]\n";
                s += "            point3f[] points = [";
                std::vector<double> p = gridPoints(m, 0.0);
                for (size_t k = 0; k < p.size(); k += 3) {
                    std::snprintf(buf, sizeof buf, "%s(%.4g, %.4g, %.4g)", k ? ", " : "", p[k],
                                  p[k + 1], p[k + 2]);
                    s += buf;
                }
                s += "]\n";
                s += "            double3 xformOp:translate = (0, 0, 0)\n";
                s += "            uniform token[] xformOpOrder = [\"xformOp:translate\"]\n";
                s += "            rel material:binding = </World/Looks/L" +
                     std::to_string(m % kMaterials) + ">\n        }\n";
            }
            s += "    }\n";
        }
        s += "    def Scope \"Looks\"\n    {\n";
        for (int k = 0; k < kMaterials; ++k) {
            std::string l = "L" + std::to_string(k);
            s += "        def Material \"" + l + "\"\n        {\n";
            s += "            token outputs:surface.connect = </World/Looks/" + l +
                 "/S.outputs:surface>\n";
            s += "            def Shader \"S\"\n            {\n";
            s += "                uniform token info:id = \"UsdPreviewSurface\"\n";
            s += "                color3f inputs:diffuseColor = (0.5, 0.5, 0.5)\n";
            s += "                token outputs:surface\n            }\n        }\n";
        }
        s += "    }\n    def DistantLight \"Sun\"\n    {\n        float inputs:intensity = 2\n    "
             "}\n}\n";
        return s;
    }();
    return text;
}

host::SessionOptions options() {
    host::SessionOptions o;
    o.width = 64;
    o.height = 64;
    o.samplesPerPixel = 1;
    return o;
}

double gFullLoadSeconds = std::numeric_limits<double>::infinity();

void BM_FullLoad(benchmark::State& state) {
    const std::string& text = sceneText();
    for (auto _ : state) {
        auto t0 = std::chrono::steady_clock::now();
        auto s = host::RenderSession::openString(text, "sync_bench.usda", options());
        double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        gFullLoadSeconds = std::min(gFullLoadSeconds, secs);
        benchmark::DoNotOptimize(s.get());
        state.PauseTiming();
        s.reset();
        state.ResumeTiming();
    }
    state.counters["triangles"] = double(kMeshes) * 2 * kGrid * kGrid;
    state.counters["MB"] = double(text.size()) / 1e6;
}
BENCHMARK(BM_FullLoad)->Iterations(3)->Unit(benchmark::kMillisecond)->UseRealTime();

host::RenderSession& loaded() {
    static std::unique_ptr<host::RenderSession> s =
        host::RenderSession::openString(sceneText(), "sync_bench.usda", options());
    return *s;
}

/// Runs `edit(i)` then one sync per iteration; reports the mean against the full load.
template <typename Edit>
void incremental(benchmark::State& state, Edit&& edit) {
    host::RenderSession& s = loaded();
    double total = 0, editing = 0;
    long n = 0;
    size_t synced = 0;
    for (auto _ : state) {
        auto t0 = std::chrono::steady_clock::now();
        edit(s.editor(), n);
        auto t1 = std::chrono::steady_clock::now();
        s.index()->sync();
        total += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        editing += std::chrono::duration<double>(t1 - t0).count();
        synced = s.index()->lastSync().rprims.size() + s.index()->lastSync().sprims.size();
        ++n;
    }
    state.counters["primsSynced"] = double(synced);
    // The adapter's share: checking, applying and marking the edit (the rest is the sync).
    if (total > 0) state.counters["editShare"] = editing / total;
    if (n > 0 && std::isfinite(gFullLoadSeconds))
        state.counters["vsFullLoad"] = total / double(n) / gFullLoadSeconds;
}

void BM_Edit_MaterialInput(benchmark::State& state) {
    incremental(state, [](adapter::StageEditor& e, long i) {
        double v = 0.1 + 0.8 * double(i % 2);
        e.setAttribute("/World/Looks/L3/S", "inputs:diffuseColor",
                       adapter::EditValue::of({v, 0.2, 0.2}));
    });
}
BENCHMARK(BM_Edit_MaterialInput)->Unit(benchmark::kMicrosecond)->UseRealTime();

void BM_Edit_Transform(benchmark::State& state) {
    incremental(state, [](adapter::StageEditor& e, long i) {
        const double m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0.1 * double(i % 2), 1};
        e.setTransform("/World/G4/M437", m);
    });
}
BENCHMARK(BM_Edit_Transform)->Unit(benchmark::kMicrosecond)->UseRealTime();

void BM_Edit_GroupTransform(benchmark::State& state) {
    incremental(state, [](adapter::StageEditor& e, long i) {
        const double m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0.1 * double(i % 2), 1};
        e.setTransform("/World/G7", m);
    });
}
BENCHMARK(BM_Edit_GroupTransform)->Unit(benchmark::kMicrosecond)->UseRealTime();

void BM_Edit_Points(benchmark::State& state) {
    std::vector<double> a = gridPoints(512, 0.0), b = gridPoints(512, 0.3);
    incremental(state, [&](adapter::StageEditor& e, long i) {
        e.setAttribute("/World/G5/M512", "points", adapter::EditValue::of(i % 2 ? a : b));
    });
}
BENCHMARK(BM_Edit_Points)->Unit(benchmark::kMicrosecond)->UseRealTime();

void BM_Edit_Binding(benchmark::State& state) {
    incremental(state, [](adapter::StageEditor& e, long i) {
        e.bindMaterial("/World/G2/M250", i % 2 ? "/World/Looks/L1" : "/World/Looks/L2");
    });
}
BENCHMARK(BM_Edit_Binding)->Unit(benchmark::kMicrosecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
