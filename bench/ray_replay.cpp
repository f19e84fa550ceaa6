// SPDX-License-Identifier: Apache-2.0
// ray_replay: the physical limit of a frame (issue 7). Renders a scene with the path tracer,
// then renders it again with a RayRecorder that stores every ray per thread (origin, direction,
// tnear, tfar, shadow or not), and casts exactly those rays through the same committed Embree
// scene (RenderSession::delegate()->snapshot().scene) with rtcIntersect1 / rtcOccluded1: no
// shading, no sampling, no AOV writes, the same thread count. path-tracer time / replay time
// says how far the renderer is from what Embree alone would take.
//
//   ray_replay SCENE.usda [--spp N] [--res WxH] [--threads T] [--repeat R] [--json FILE]
//              [--set KEY=VALUE]... [--refine-level L]
#include <embree3/rtcore.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "delegate/rayRecorder.h"
#include "delegate/renderDelegate.h"
#include "delegate/renderPass.h"
#include "plugins/renderSession.h"

using namespace principled;

namespace {

struct RecordedRay {
    glm::vec3 o;
    float tnear;
    glm::vec3 d;
    float tfar;  // the shadow flag is kept in a parallel array
};

class PerThreadRecorder : public embree::RayRecorder {
public:
    struct Buffer {
        std::vector<RecordedRay> rays;
        std::vector<uint8_t> shadow;
    };
    void record(const glm::vec3& origin, const glm::vec3& direction, float tnear, float tfar,
                bool shadow) override {
        Buffer& b = _local.local();
        b.rays.push_back({origin, tnear, direction, tfar});
        b.shadow.push_back(shadow ? 1 : 0);
    }
    tbb::enumerable_thread_specific<Buffer>& buffers() { return _local; }

private:
    tbb::enumerable_thread_specific<Buffer> _local;
};

double cpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}
double wallSeconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct Times {
    double wall = 0, cpu = 0;
};

// Steps a session to convergence. The scene sync (parse, subdivision, BVH) happens when the
// session is opened, so this times sampling passes only; main() checks that with a 1-spp render.
Times renderToEnd(host::RenderSession& s) {
    const double w0 = wallSeconds(), c0 = cpuSeconds();
    while (!s.step()) {
    }
    return {wallSeconds() - w0, cpuSeconds() - c0};
}

}  // namespace

int main(int argc, char** argv) {
    std::string scene, jsonPath;
    host::SessionOptions o;
    o.width = 256;
    o.height = 256;
    o.samplesPerPixel = 16;
    int threads = 2, repeat = 1;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "ray_replay: %s needs a value\n", a.c_str());
                std::exit(1);
            }
            return argv[++i];
        };
        if (a == "--spp") o.samplesPerPixel = std::stoi(next());
        else if (a == "--res") {
            std::string r = next();
            o.width = std::stoi(r.substr(0, r.find('x')));
            o.height = std::stoi(r.substr(r.find('x') + 1));
        } else if (a == "--threads") threads = std::stoi(next());
        else if (a == "--repeat") repeat = std::stoi(next());
        else if (a == "--json") jsonPath = next();
        else if (a == "--refine-level") o.refineLevel = std::stoi(next());
        else if (a == "--max-depth") o.maxDepth = std::stoi(next());
        else if (a == "--set") {
            std::string kv = next();
            o.settings[kv.substr(0, kv.find('='))] = kv.substr(kv.find('=') + 1);
        } else if (!a.empty() && a[0] != '-') scene = a;
        else {
            std::fprintf(stderr, "ray_replay: unknown option %s\n", a.c_str());
            return 1;
        }
    }
    if (scene.empty()) {
        std::fprintf(stderr, "usage: ray_replay SCENE.usda [--spp N] [--res WxH] [--threads T] [--json FILE]\n");
        return 1;
    }
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));

    // 1. The path tracer, untouched (no recorder), best of `repeat`. A 1-spp render first warms
    //    the caches and estimates any sync work left inside step() (reported as syncEstimate and
    //    subtracted).
    Times pt{1e30, 1e30}, sync{1e30, 1e30};
    for (int r = 0; r < repeat; ++r) {
        host::SessionOptions one = o;
        one.samplesPerPixel = 1;
        auto s1 = host::RenderSession::openFile(scene, one);
        Times t1 = renderToEnd(*s1);
        auto s = host::RenderSession::openFile(scene, o);
        Times t = renderToEnd(*s);
        if (t.wall < pt.wall) pt = t, sync = t1;
    }
    // 2. Record every ray of the same render.
    PerThreadRecorder rec;
    auto s = host::RenderSession::openFile(scene, o);
    s->pass()->setRayRecorder(&rec);
    Times recorded = renderToEnd(*s);
    s->pass()->setRayRecorder(nullptr);
    RTCScene rtc = s->delegate()->snapshot().scene;

    struct Chunk {
        const RecordedRay* rays;
        const uint8_t* shadow;
        size_t n;
    };
    std::vector<Chunk> chunks;
    size_t total = 0, shadowRays = 0;
    for (auto& b : rec.buffers()) {
        for (size_t i = 0; i < b.rays.size(); i += 4096)
            chunks.push_back({&b.rays[i], &b.shadow[i], std::min<size_t>(4096, b.rays.size() - i)});
        total += b.rays.size();
        for (uint8_t f : b.shadow) shadowRays += f;
    }
    // Interleave chunks of different threads, as the render did.
    std::vector<Chunk> order;
    {
        std::vector<std::vector<Chunk>> per;
        for (auto& b : rec.buffers()) {
            per.emplace_back();
            for (size_t i = 0; i < b.rays.size(); i += 4096)
                per.back().push_back({&b.rays[i], &b.shadow[i], std::min<size_t>(4096, b.rays.size() - i)});
        }
        for (size_t k = 0;; ++k) {
            bool any = false;
            for (auto& p : per)
                if (k < p.size()) order.push_back(p[k]), any = true;
            if (!any) break;
        }
    }

    // 3. Replay.
    std::atomic<size_t> hits{0};
    Times replay{1e30, 1e30};
    for (int r = 0; r < std::max(repeat, 2); ++r) {
        hits = 0;
        const double w0 = wallSeconds(), c0 = cpuSeconds();
        tbb::parallel_for(size_t(0), order.size(), [&](size_t c) {
            const Chunk& ch = order[c];
            RTCIntersectContext ctx;
            size_t h = 0;
            for (size_t i = 0; i < ch.n; ++i) {
                const RecordedRay& q = ch.rays[i];
                rtcInitIntersectContext(&ctx);
                if (ch.shadow[i]) {
                    RTCRay ray{};
                    ray.org_x = q.o.x; ray.org_y = q.o.y; ray.org_z = q.o.z;
                    ray.dir_x = q.d.x; ray.dir_y = q.d.y; ray.dir_z = q.d.z;
                    ray.tnear = q.tnear; ray.tfar = q.tfar; ray.mask = ~0u; ray.flags = 0;
                    rtcOccluded1(rtc, &ctx, &ray);
                    h += ray.tfar < 0.0f;
                } else {
                    RTCRayHit rh{};
                    rh.ray.org_x = q.o.x; rh.ray.org_y = q.o.y; rh.ray.org_z = q.o.z;
                    rh.ray.dir_x = q.d.x; rh.ray.dir_y = q.d.y; rh.ray.dir_z = q.d.z;
                    rh.ray.tnear = q.tnear; rh.ray.tfar = q.tfar; rh.ray.mask = ~0u; rh.ray.flags = 0;
                    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
                    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
                    rtcIntersect1(rtc, &ctx, &rh);
                    h += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
                }
            }
            hits += h;
        });
        Times t{wallSeconds() - w0, cpuSeconds() - c0};
        if (t.wall < replay.wall) replay = t;
    }

    // Path-tracer time net of the scene sync (estimated by the 1-spp render, which includes
    // the sync and one sample).
    const double spp = double(o.samplesPerPixel);
    const double syncWall = std::max(0.0, sync.wall - pt.wall / spp);
    const double syncCpu = std::max(0.0, sync.cpu - pt.cpu / spp);
    const double ptWall = pt.wall - syncWall, ptCpu = pt.cpu - syncCpu;
    auto stats = s->stats();
    nlohmann::json j;
    j["scene"] = scene;
    j["width"] = o.width;
    j["height"] = o.height;
    j["spp"] = o.samplesPerPixel;
    j["threads"] = threads;
    j["settings"] = o.settings;
    j["rays"] = total;
    j["shadowRays"] = shadowRays;
    j["hits"] = size_t(hits);
    j["integratorRays"] = stats.count("rays") ? stats["rays"] : -1.0;
    j["pathTracer"] = {{"wallSeconds", pt.wall}, {"cpuSeconds", pt.cpu}};
    j["syncEstimate"] = {{"wallSeconds", syncWall}, {"cpuSeconds", syncCpu}};
    j["pathTracerNetOfSync"] = {{"wallSeconds", ptWall}, {"cpuSeconds", ptCpu}};
    j["recordingRender"] = {{"wallSeconds", recorded.wall}, {"cpuSeconds", recorded.cpu}};
    j["replay"] = {{"wallSeconds", replay.wall}, {"cpuSeconds", replay.cpu}};
    j["ratioWall"] = ptWall / replay.wall;
    j["ratioCpu"] = ptCpu / replay.cpu;
    j["replayMraysPerCpuSecond"] = double(total) * 1e-6 / replay.cpu;
    j["pathTracerMraysPerCpuSecond"] = double(total) * 1e-6 / ptCpu;
    std::string text = j.dump(2);
    std::printf("%s\n", text.c_str());
    if (!jsonPath.empty()) std::ofstream(jsonPath) << text << "\n";
    return 0;
}
