// SPDX-License-Identifier: Apache-2.0
// Edit latency like a viewport host sees it (issue 7: "first progressive image of the default
// scene in under 100 ms; a material edit shows a new image in under 100 ms"). One process, one
// host::RenderSession at 640x360 and 1 sample per pixel (each step() is one displayed image):
//   first image   open the default scene (parse + compose + populate + sync + commit) and run
//                 the first 1-spp pass, then read the color buffer (a fresh session each time)
//   material      inputs:diffuseColor of one material   -> step() -> color()
//   light         inputs:intensity of the sky dome          -> step() -> color()
//   transform     one sphere's transform                -> step() -> color()
//   camera        the camera's transform                -> step() -> color()
//   no edit       step() with nothing edited (the pass must not restart: no new samples)
// Wall (steady_clock) and process CPU time (every thread) in ms; best and median of N; each
// edit's best is also given as a fraction of the first image's best in the same run.
//   latency_bench [scene.usda] [--repeat N] [--json out.json]
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "delegate/hd/renderIndex.h"
#include "plugins/renderSession.h"
#include "scene_adapter/stageEditor.h"

using namespace principled;

namespace {

double cpuNow() {
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}
double wallNow() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct Figures {
    std::string name;
    std::vector<double> wall, cpu;  // ms
    std::vector<double> syncWall, syncCpu;  // ms: edit + RenderIndex::sync() (commit included)
    double best(const std::vector<double>& v) const { return *std::min_element(v.begin(), v.end()); }
    double median(std::vector<double> v) const {
        std::sort(v.begin(), v.end());
        return v[v.size() / 2];
    }
};

double checksum(const host::RenderSession& s) {
    const float* c = s.color();
    double sum = 0.0;
    for (size_t i = 0; i < size_t(s.width()) * size_t(s.height()) * 4; ++i) sum += c[i] * double(i % 977 + 1);
    return sum;
}

// USD row-vector matrix: rotation about X by `deg`, then translation t.
void cameraMatrix(double deg, double tx, double ty, double tz, double m[16]) {
    double a = deg * 3.14159265358979323846 / 180.0, c = std::cos(a), s = std::sin(a);
    double v[16] = {1, 0, 0, 0, 0, c, s, 0, 0, -s, c, 0, tx, ty, tz, 1};
    std::memcpy(m, v, sizeof v);
}

}  // namespace

int main(int argc, char** argv) {
    std::string scene = PRINCIPLED_DEFAULT_SCENE_PATH, json;
    int repeat = 15;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        if (a == "--repeat" && i + 1 < argc) repeat = std::max(1, std::atoi(argv[++i]));
        else if (a == "--json" && i + 1 < argc) json = argv[++i];
        else scene = a;
    }
    host::SessionOptions o;
    o.width = 640;
    o.height = 360;
    o.samplesPerPixel = 1;

    bool ok = true;
    std::ostringstream js;
    for (int mode = 0; mode < 2; ++mode) {
    // mode 0: commits rebuild every table (PRINCIPLED_FULL_COMMIT=1, the behaviour before
    // incremental commits); mode 1: incremental. Same binary, same run.
    setenv("PRINCIPLED_FULL_COMMIT", mode == 0 ? "1" : "0", 1);
    const char* modeName = mode == 0 ? "full commit (before)" : "incremental (after)";
    std::vector<Figures> out;
    // First image: a fresh session each time.
    Figures first{"first image"};
    for (int r = 0; r < std::max(3, repeat / 3); ++r) {
        double w0 = wallNow(), c0 = cpuNow();
        auto s = host::RenderSession::openFile(scene, o);
        s->step();
        volatile float sink = s->color()[0];
        (void)sink;
        first.wall.push_back((wallNow() - w0) * 1e3);
        first.cpu.push_back((cpuNow() - c0) * 1e3);
    }
    out.push_back(first);

    auto s = host::RenderSession::openFile(scene, o);
    s->step();
    adapter::StageEditor& ed = s->editor();
    auto measure = [&](const std::string& name, const std::function<void(int)>& edit, bool expectNew) {
        Figures f{name};
        for (int r = 0; r < repeat; ++r) {
            double before = checksum(*s);
            auto stats0 = s->stats();
            double w0 = wallNow(), c0 = cpuNow();
            edit(r);
            s->index()->sync();  // timed apart; step()'s own sync is then a no-op
            f.syncWall.push_back((wallNow() - w0) * 1e3);
            f.syncCpu.push_back((cpuNow() - c0) * 1e3);
            s->step();
            volatile float sink = s->color()[0];
            (void)sink;
            f.wall.push_back((wallNow() - w0) * 1e3);
            f.cpu.push_back((cpuNow() - c0) * 1e3);
            auto stats1 = s->stats();
            bool rendered = stats1["samples"] > stats0["samples"];
            bool changed = checksum(*s) != before;
            if (rendered != expectNew || (expectNew && !changed)) {
                std::fprintf(stderr, "%s: %s\n", name.c_str(),
                             expectNew ? "no new image after the edit" : "the pass restarted without an edit");
                ok = false;
            }
        }
        out.push_back(f);
    };
    measure("material (diffuseColor)", [&](int r) {
        double g = 0.2 + 0.6 * double(r % 7) / 7.0;
        ed.setAttribute("/World/Looks/Reference/Surface", "inputs:diffuseColor", adapter::EditValue::of({g, 0.4, 0.1}));
    }, true);
    measure("light (sky intensity)", [&](int r) {
        ed.setAttribute("/World/Sky", "inputs:intensity", adapter::EditValue::of({0.65 + 0.05 * (r % 8)}));
    }, true);
    measure("transform (one sphere)", [&](int r) {
        double m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -3.45, 0.55 + 0.05 * (r % 9), 0, 1};
        ed.setTransform("/World/Reference", m);
    }, true);
    measure("camera move", [&](int r) {
        double m[16];
        cameraMatrix(-7.0, 0.02 * (r % 11 + 1), 1.6, 9.0, m);
        ed.setTransform("/World/Camera", m);
    }, true);
    measure("no edit", [&](int) {}, false);

    double base = first.best(first.wall);
    std::printf("== %s: %s at %dx%d, 1 spp, best / median of %d (first image: %zu fresh sessions)\n",
                modeName, scene.c_str(), o.width, o.height, repeat, first.wall.size());
    std::printf("%-26s %10s %10s %10s %10s %10s %12s %12s\n", "", "wall best", "wall med", "CPU best", "CPU med",
                "vs first", "sync wall", "sync CPU");
    for (const auto& f : out) {
        std::printf("%-26s %8.2fms %8.2fms %8.2fms %8.2fms %10.3f", f.name.c_str(), f.best(f.wall),
                    f.median(f.wall), f.best(f.cpu), f.median(f.cpu), f.best(f.wall) / base);
        if (!f.syncWall.empty()) std::printf(" %10.3fms %10.3fms", f.best(f.syncWall), f.best(f.syncCpu));
        std::printf("\n");
    }
    auto st = s->stats();
    std::printf("stats after the edits:");
    for (const char* k : {"topLevelCommits", "blasBuilds", "meshesRebuilt", "materialTableBuilds",
                          "materialUpdates", "lightTableBuilds", "meshLightBuilds", "lightDistributionBuilds"})
        std::printf(" %s=%g", k, st[k]);
    std::printf("\n");
    js << (mode ? ",\n" : "") << "    \"" << (mode == 0 ? "fullCommit" : "incremental") << "\": [\n";
    for (size_t i = 0; i < out.size(); ++i) {
        const auto& f = out[i];
        js << "      {\"name\": \"" << f.name << "\", \"wallBest\": " << f.best(f.wall)
           << ", \"wallMedian\": " << f.median(f.wall) << ", \"cpuBest\": " << f.best(f.cpu)
           << ", \"cpuMedian\": " << f.median(f.cpu) << ", \"vsFirstImage\": " << f.best(f.wall) / base;
        if (!f.syncWall.empty())
            js << ", \"syncWallBest\": " << f.best(f.syncWall) << ", \"syncCpuBest\": " << f.best(f.syncCpu);
        js << "}" << (i + 1 < out.size() ? "," : "") << "\n";
    }
    js << "    ]";
    }
    if (!json.empty()) {
        std::ofstream j(json);
        j << "{\n  \"command\": \"build/bin/latency_bench --repeat " << repeat << " --json docs/perf/latency.json\",\n"
          << "  \"scene\": \"" << scene.substr(scene.find_last_of('/') + 1) << "\",\n  \"width\": " << o.width
          << ",\n  \"height\": " << o.height << ",\n  \"spp\": 1,\n  \"repeat\": " << repeat
          << ",\n  \"unit\": \"ms\",\n  \"modes\": {\n" << js.str() << "\n  }\n}\n";
    }
    return ok ? 0 : 1;
}
