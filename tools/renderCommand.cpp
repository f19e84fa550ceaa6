// SPDX-License-Identifier: Apache-2.0
#include "tools/renderCommand.h"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <limits>
#include <new>
#include <regex>

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>
#include <unistd.h>

#include "delegate/imageWriter.h"
#include "delegate/renderDelegate.h"
#include "delegate/renderPass.h"
#include "plugins/renderSession.h"
#include "scene_adapter/usda/error.h"
#include "tools/defaultScene.h"
#include "tools/distributed/distributedRender.h"
#include "tools/outputs.h"
#include "tools/processClock.h"
#include "tools/progressBar.h"

namespace principled::tools {

namespace {

struct RenderArgs {
    std::string scene;
    std::vector<std::string> outputs;
    int spp = 64;
    bool sppGiven = false;  ///< --spp on the command line
    std::string res;  ///< "" : the stage's RenderSettings resolution, else 640x360
    int seed = 0;
    int threads = 0;
    int maxDepth = 8;
    std::string camera;
    std::string model = "disney";
    std::string statsPath;
    std::vector<std::string> aovs;
    std::string sampler = "sobol";
    int refineLevel = -1;
    float noiseThreshold = 0.0f;
    double timeLimit = 0.0;
    std::vector<std::string> settings;
    double time = std::numeric_limits<double>::quiet_NaN();
    bool split = false;
    bool quiet = false;
    distributed::Options distributed;  // mpirun, --frames, checkpoints: tools/distributed/
};

/// SIGINT / SIGTERM during the render: the first stops it after the current pass (the image so
/// far is written), a second exits at once.
volatile std::sig_atomic_t gStopSignal = 0;

extern "C" void onStopSignal(int sig) {
    if (gStopSignal != 0) _exit(128 + sig);
    gStopSignal = sig;
}

/// Installs onStopSignal for SIGINT and SIGTERM while it lives; the previous handlers after.
class StopSignals {
public:
    StopSignals() {
        struct sigaction sa {};
        sa.sa_handler = onStopSignal;
        sigemptyset(&sa.sa_mask);
        sigaction(SIGINT, &sa, &_int);
        sigaction(SIGTERM, &sa, &_term);
        // A signal the parent ignores on purpose (a shell script's background job and SIGINT) stays ignored.
        if (_int.sa_handler == SIG_IGN) sigaction(SIGINT, &_int, nullptr);
        if (_term.sa_handler == SIG_IGN) sigaction(SIGTERM, &_term, nullptr);
    }
    ~StopSignals() {
        sigaction(SIGINT, &_int, nullptr);
        sigaction(SIGTERM, &_term, nullptr);
    }
    StopSignals(const StopSignals&) = delete;
    StopSignals& operator=(const StopSignals&) = delete;

private:
    struct sigaction _int {}, _term {};
};

int fail(const std::string& message) {
    std::fprintf(stderr, "principled: error: %s\n", message.c_str());
    return 1;
}

int runRender(const RenderArgs& a) {
    host::SessionOptions o;
    std::smatch m;
    static const std::regex resPattern(R"(^(\d+)x(\d+)$)");
    if (a.res.empty()) {
        o.width = o.height = 0;  // the stage's RenderSettings, else 640x360
    } else {
        if (!std::regex_match(a.res, m, resPattern))
            return fail("--res must look like WIDTHxHEIGHT (e.g. 640x360), not '" + a.res + "'");
        if (m[1].length() > 5 || m[2].length() > 5 || std::stoi(m[1]) > 32768 || std::stoi(m[2]) > 32768)
            return fail("--res " + a.res + " is too large: at most 32768x32768");
        o.width = std::stoi(m[1]);
        o.height = std::stoi(m[2]);
        if (o.width == 0 || o.height == 0) return fail("--res must be at least 1x1, not '" + a.res + "'");
    }
    o.samplesPerPixel = a.spp;
    o.seed = a.seed;
    o.maxDepth = a.maxDepth;
    o.camera = a.camera;
    o.shadingModel = a.model;
    o.sampler = a.sampler;
    o.refineLevel = a.refineLevel;
    o.noiseThreshold = a.noiseThreshold;
    o.time = a.time;
    for (const auto& kv : a.settings) {
        auto eq = kv.find('=');
        if (eq == std::string::npos || eq == 0)
            return fail("--set expects KEY=VALUE, not '" + kv + "'");
        o.settings[kv.substr(0, eq)] = kv.substr(eq + 1);
    }
    // --set KEY=VALUE is applied after the options it overlaps (--seed, --max-depth...) and wins;
    // the sample count is given once, as it also cuts MPI ranks' sample ranges.
    if (auto it = o.settings.find("convergedSamplesPerPixel"); it != o.settings.end()) {
        if (a.sppGiven)
            return fail("--spp " + std::to_string(a.spp) + " and --set convergedSamplesPerPixel=" + it->second +
                        " both give the samples per pixel; give one");
        char* end = nullptr;
        long n = std::strtol(it->second.c_str(), &end, 10);
        if (!it->second.empty() && *end == '\0' && n >= 1 && n <= (1 << 20)) o.samplesPerPixel = int(n);
        // (anything else: the session's error names the setting and its range)
    }
    o.aovs = a.aovs;
    if (!outputFormat(a.scene).empty())
        return fail("'" + a.scene + "' is an image, not a scene: -o takes one output; give each its own -o "
                    "(-o a.exr -o a.png)");
    // Every output (and the stats file) can be written, before the scene is loaded.
    for (const auto& out : a.outputs)
        if (std::string problem = checkWritable(out, true); !problem.empty()) return fail(problem);
    if (!a.statsPath.empty())
        if (std::string problem = checkWritable(a.statsPath, false); !problem.empty()) return fail(problem);
    std::unique_ptr<tbb::global_control> threadLimit;
    if (a.threads > 0)
        threadLimit = std::make_unique<tbb::global_control>(
            tbb::global_control::max_allowed_parallelism, size_t(a.threads));

    if (distributed::wanted(a.distributed)) {
        // Passes are checkpointed and merged whole: a deadline would end ranks at different samples.
        if (a.timeLimit > 0.0)
            return fail("--time-limit cannot be combined with MPI ranks, --frames, --checkpoint-every or --resume "
                        "(checkpoint with --checkpoint-every and stop the job instead)");
        distributed::Options d = a.distributed;
        d.statsPath = a.statsPath;
        return distributed::run(o, a.scene, a.outputs, a.split, a.quiet, d);
    }

    auto t0 = std::chrono::steady_clock::now();
    std::unique_ptr<host::RenderSession> session;
    try {
        session = a.scene.empty()
                      ? host::RenderSession::openString(kDefaultSceneUsda, "<default scene>", o)
                      : host::RenderSession::openFile(a.scene, o);
    } catch (const usd::Error& e) {
        return fail(e.what());
    } catch (const host::UserError& e) {
        return fail(e.what());
    }
    double loadSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    auto report = [&] {
        for (const auto& w : session->takeWarnings())
            if (!a.quiet) std::fprintf(stderr, "principled: warning: %s\n", w.c_str());
    };
    report();
    if (!a.quiet && session->stats()["defaultLight"] > 0.0)
        std::fprintf(stderr, "principled: note: the scene has no lights; lighting it with a white dome (radiance 1)\n");

    ProgressBar bar("render", !a.quiet);
    auto t1 = std::chrono::steady_clock::now();
    const std::clock_t c1 = std::clock();  // process CPU time, all threads (Linux)
    bool timedOut = false;
    // The first pass: the first progressive image is in memory (issue #7: under 100 ms from exec).
    double processToFirstImage = -1.0, firstImageUnix = 0.0, cpuToFirstImage = 0.0;
    auto firstImage = [&] {
        if (processToFirstImage >= 0.0) return;
        processToFirstImage = secondsSinceProcessStart();
        firstImageUnix = unixSeconds();
        cpuToFirstImage = processCpuSeconds();
    };
    StopSignals stopSignals;  // until the outputs are written
    // --time-limit: a pass cannot stop midway, so each is sized to the time left from the
    // seconds per sample per pixel of the one before (the first, 1 spp, includes the scene's
    // build): the limit is overshot by at most about one 1-spp pass.
    double secondsPerSample = 0.0;
    for (;;) {
        if (a.timeLimit > 0.0 && secondsPerSample > 0.0) {
            double left = a.timeLimit - std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
            double fit = left / secondsPerSample;
            if (fit < 0.5) {  // even one sample would end further past the limit than stopping now is before it
                timedOut = true;
                break;
            }
            session->pass()->setPassSampleLimit(int(std::clamp(fit, 1.0, 1024.0)));
        }
        const auto passStart = std::chrono::steady_clock::now();
        const int before = session->completedSamples();
        const bool converged = session->step();
        const int taken = session->completedSamples() - before;
        if (taken > 0)
            secondsPerSample = std::chrono::duration<double>(std::chrono::steady_clock::now() - passStart).count() / taken;
        if (converged) break;
        firstImage();
        double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
        if (a.timeLimit > 0.0 && elapsed >= a.timeLimit) {
            timedOut = true;
            break;
        }
        if (gStopSignal != 0) break;
        bar.update(session->completedSamples(), session->targetSamples(),
                   std::to_string(session->completedSamples()) + "/" +
                       std::to_string(session->targetSamples()) + " spp");
    }
    firstImage();
    bar.update(1, 1, std::to_string(session->completedSamples()) + "/" +
                         std::to_string(session->targetSamples()) + " spp");
    bar.finish();
    double renderSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    double renderCpuSeconds = double(std::clock() - c1) / CLOCKS_PER_SEC;
    report();
    const int stopSignal = gStopSignal;
    if (stopSignal != 0 && !a.quiet)
        std::fprintf(stderr, "principled: %s: stopped after the pass in progress; writing the image so far (%d of %d spp; "
                             "press Ctrl-C again to exit without writing)\n",
                     stopSignal == SIGINT ? "interrupted (SIGINT)" : "terminated (SIGTERM)",
                     session->completedSamples(), session->targetSamples());

    // Under adaptive sampling pixels stop early: the samples actually taken, per pixel.
    const bool adaptive = session->delegate()->noiseThreshold() > 0.0f;
    const double meanSamples =
        session->stats()["samples"] / std::max(1.0, double(session->width()) * double(session->height()));

    // Each output through a temporary file renamed into place; one that fails does not stop
    // the others (nor the stats).
    const std::vector<std::string> writeErrors = writeOutputs(*session, a.outputs, a.split);
    for (const auto& e : writeErrors) std::fprintf(stderr, "principled: error: %s\n", e.c_str());
    if (!a.statsPath.empty()) {
        nlohmann::json j;
        j["scene"] = a.scene.empty() ? "<default scene>" : a.scene;
        j["width"] = session->width();
        j["height"] = session->height();
        j["samplesPerPixel"] = session->completedSamples();  // the most a pixel took
        j["meanSamplesPerPixel"] = meanSamples;                // less under adaptive sampling
        j["camera"] = session->cameraPath();
        j["timedOut"] = timedOut;
        j["interrupted"] = stopSignal != 0;
        j["loadSeconds"] = loadSeconds;
        j["renderWallSeconds"] = renderSeconds;
        j["renderCpuSeconds"] = renderCpuSeconds;  // equal-CPU-time comparisons on a shared machine
        // Startup (docs/performance.md): process start (/proc/self/stat, 10 ms steps) to main's
        // static initialisation (the dynamic loader) and to the first completed pass, the CPU
        // spent until then, and the wall clock at that pass for harnesses that time the exec.
        j["processToInitSeconds"] = processStartToInitSeconds();
        j["processToFirstImageSeconds"] = processToFirstImage;
        j["processCpuToFirstImageSeconds"] = cpuToFirstImage;  // all threads, from exec
        j["firstImageUnixSeconds"] = firstImageUnix;
        for (const auto& [k, v] : session->stats()) j["delegate"][k] = v;
        std::ofstream f(a.statsPath);
        if (!f) return fail(a.statsPath + ": cannot write the stats file");
        f << j.dump(2) << "\n";
    }
    if (!writeErrors.empty()) return 1;
    if (stopSignal != 0) return 128 + stopSignal;  // 130 (SIGINT), 143 (SIGTERM), as the shell reports a kill
    if (!a.quiet && adaptive)
        std::fprintf(stderr, "principled: rendered %dx%d at %.1f spp on average (adaptive sampling; at most %d) in %.2fs (%.1f Mrays/s)\n",
                     session->width(), session->height(), meanSamples, session->targetSamples(),
                     renderSeconds, session->stats()["mraysPerSecond"]);
    else if (!a.quiet)
        std::fprintf(stderr, "principled: rendered %dx%d at %d spp in %.2fs (%.1f Mrays/s)\n",
                     session->width(), session->height(), session->completedSamples(),
                     renderSeconds, session->stats()["mraysPerSecond"]);
    if (!a.quiet) std::fprintf(stderr, "principled: scene: %s\n", session->delegate()->sceneSummary().c_str());
    return 0;
}

}  // namespace

void addRenderCommand(CLI::App& app, int* exitCode) {
    auto args = std::make_shared<RenderArgs>();
    auto* cmd = app.add_subcommand("render", "Render a .usda stage (default: the built-in scene)");
    cmd->add_option("scene", args->scene, "USDA file; omitted: the built-in default scene");
    // -o, --aov and --set take one value each time (repeat them): `-o out.exr scene.usda` keeps
    // the scene a positional instead of a second output.
    cmd->add_option("-o,--output", args->outputs, "Output image: .exr (linear float) or .png (sRGB); repeat for more (-o a.exr -o a.png)")
        ->required()
        ->allow_extra_args(false);
    cmd->add_option("--spp", args->spp, "Samples per pixel")->check(CLI::Range(1, 1 << 20));
    cmd->add_option("--res", args->res, "Resolution WIDTHxHEIGHT (default: the stage's RenderSettings, else 640x360)");
    cmd->add_option("--seed", args->seed, "Random seed (same seed, same image)");
    cmd->add_option("--threads", args->threads, "Worker threads (0 = all cores)")->check(CLI::Range(0, 1024));
    cmd->add_option("--max-depth", args->maxDepth, "Bounces after the camera hit")->check(CLI::Range(0, 1024));
    cmd->add_option("--camera", args->camera, "Camera prim path (default: the stage's RenderSettings camera, else the first camera)");
    cmd->add_option("--model", args->model, "Shading model: disney or ue4");
    cmd->add_option("--stats", args->statsPath, "Write render statistics as JSON");
    cmd->add_option("--aov", args->aovs, "AOVs to write besides color, comma-separated, or 'all'")
        ->delimiter(',')
        ->allow_extra_args(false);
    cmd->add_flag("--split", args->split, "Write one EXR per AOV (NAME.AOV.exr; ':' in AOV names becomes '_': NAME.primvars_st.exr) instead of one multi-layer EXR");
    cmd->add_option("--sampler", args->sampler, "sobol (Owen-scrambled, default) or independent");
    cmd->add_option("--noise-threshold", args->noiseThreshold,
                    "Adaptive sampling: stop a pixel when the relative standard error of its mean is below this (e.g. 0.01); 0 = off")
        ->check(CLI::Range(0.0, 10.0));
    cmd->add_option("--time-limit", args->timeLimit,
                    "Stop after this many seconds of rendering (the image so far is written; passes are sized to the time "
                    "left, so the limit is overshot by about one sample per pixel's time). Ctrl-C / SIGTERM also "
                    "stop after the pass in progress, write the image and exit 130 / 143; a second Ctrl-C exits at once")
        ->check(CLI::Range(0.0, 1e9));
    cmd->add_option("--time", args->time, "Time code to render the stage at (default: startTimeCode, else the default values)");
    cmd->add_option("--set", args->settings,
                    "Render setting KEY=VALUE (repeatable), e.g. --set mis=0 --set maxDepth=3; applied after the "
                    "options (it wins over --seed, --max-depth...); convergedSamplesPerPixel beside --spp is refused")
        ->allow_extra_args(false);
    cmd->add_option("--refine-level", args->refineLevel,
                    "Subdivision level for every mesh (0-8); -1 = adaptive from the projected size")
        ->check(CLI::Range(-1, 8));
    cmd->add_flag("-q,--quiet", args->quiet, "No progress bar, warnings or summary");
    distributed::addOptions(cmd, &args->distributed);
    cmd->callback([args, exitCode, cmd] {
        args->sppGiven = cmd->count("--spp") > 0;
        try {
            *exitCode = runRender(*args);
        } catch (const std::bad_alloc&) {
            std::string aovs;
            for (const auto& aov : args->aovs) aovs += (aovs.empty() ? "" : ",") + aov;
            *exitCode = fail("ran out of memory rendering " +
                             (args->res.empty() ? std::string("at the stage's resolution") : args->res) +
                             (aovs.empty() ? "" : " with --aov " + aovs) +
                             ": reduce --res, the AOVs (--aov) or the scene's subdivision (--refine-level, "
                             "--set subdivisionBudget=...), or render on a machine with more memory");
        }
    });
}

}  // namespace principled::tools
