// SPDX-License-Identifier: Apache-2.0
#include "tools/distributed/distributedRender.h"

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <new>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "delegate/imageWriter.h"
#include "plugins/renderSession.h"
#include "scene_adapter/usda/error.h"
#include "scene_adapter/usda/prim.h"
#include "scene_adapter/usda/stage.h"
#include "tools/defaultScene.h"
#include "tools/distributed/accumulation.h"
#include "tools/distributed/comm.h"
#include "tools/outputs.h"
#include "tools/progressBar.h"

namespace principled::tools::distributed {

namespace fs = std::filesystem;

namespace {

/// Anything that stops this rank; the job ends with it, naming the rank.
struct RankError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

std::vector<double> parseFrames(const std::string& text) {
    if (text.empty()) return {std::numeric_limits<double>::quiet_NaN()};
    double a = 0, b = 0, step = 1;
    char tail = 0;
    int n = std::sscanf(text.c_str(), "%lf:%lf:%lf%c", &a, &b, &step, &tail);
    if (n == 1 && text.find(':') == std::string::npos) b = a;
    if ((n != 1 && n != 2 && n != 3) || (n == 1 && text.find(':') != std::string::npos) ||
        !(step > 0) || b < a || (b - a) / step > 1e6)
        throw RankError("--frames expects A:B or A:B:STEP time codes with A <= B and STEP > 0, not '" + text + "'");
    std::vector<double> frames;
    for (long i = 0; a + i * step <= b + 1e-9; ++i) frames.push_back(a + i * step);
    return frames;
}

/// The fewest decimals (0-6) that write every frame of the sequence exactly, so that all of
/// its names have the same form and sort in time order.
int frameDecimals(const std::vector<double>& frames) {
    for (int d = 0; d < 6; ++d) {
        const double k = std::pow(10.0, d);
        bool exact = true;
        for (double t : frames) exact = exact && std::abs(t * k - std::round(t * k)) <= 1e-6 * std::max(1.0, std::abs(t * k));
        if (exact) return d;
    }
    return 6;
}

/// 7 -> "0007", -1 -> "-0001"; with 3 decimals, 2.5 -> "0002.500".
std::string frameTag(double t, int decimals) {
    char buf[64];
    const double a = std::abs(t);
    if (decimals == 0) std::snprintf(buf, sizeof buf, "%s%04lld", t < 0 ? "-" : "", static_cast<long long>(std::llround(a)));
    else std::snprintf(buf, sizeof buf, "%s%0*.*f", t < 0 ? "-" : "", 5 + decimals, decimals, a);
    return buf;
}

/// OUT.exr -> OUT.0007.exr, or "####" in the name replaced by the frame.
std::string framePath(const std::string& out, double t, int decimals, bool animated) {
    if (!animated) return out;
    std::string tag = frameTag(t, decimals);
    auto hashes = out.find("####");
    if (hashes != std::string::npos) return out.substr(0, hashes) + tag + out.substr(hashes + 4);
    fs::path p(out);
    return (p.parent_path() / (p.stem().string() + "." + tag + p.extension().string())).string();
}

/// Everything that changes the accumulated samples, in a fixed order.
std::string canonicalSettings(const host::SessionOptions& o) {
    std::ostringstream s;
    s.precision(17);
    s << "res=" << o.width << 'x' << o.height << ";spp=" << o.samplesPerPixel << ";seed=" << o.seed
      << ";maxDepth=" << o.maxDepth << ";camera=" << o.camera << ";model=" << o.shadingModel
      << ";sampler=" << o.sampler << ";refineLevel=" << o.refineLevel << ";aovs=";
    for (size_t i = 0; i < o.aovs.size(); ++i) s << (i ? "," : "") << o.aovs[i];
    for (const auto& [k, v] : o.settings) s << ";set:" << k << '=' << v;
    s << ";time=";
    if (std::isnan(o.time)) s << "default";
    else s << o.time;
    return s.str();
}

/// "seed: 1 in the checkpoint, 2 now; ..." for the keys that differ.
std::string settingsDiff(const std::string& was, const std::string& now) {
    auto parse = [](const std::string& text) {
        std::map<std::string, std::string> m;
        std::stringstream ss(text);
        std::string item;
        while (std::getline(ss, item, ';')) {
            auto eq = item.find('=');
            m[item.substr(0, eq)] = eq == std::string::npos ? "" : item.substr(eq + 1);
        }
        return m;
    };
    auto a = parse(was), b = parse(now);
    std::map<std::string, int> keys;
    for (const auto& [k, v] : a) keys[k];
    for (const auto& [k, v] : b) keys[k];
    std::string out;
    for (const auto& [k, unused] : keys) {
        std::string va = a.count(k) ? a[k] : "(unset)", vb = b.count(k) ? b[k] : "(unset)";
        if (va != vb) out += (out.empty() ? "" : "; ") + k + ": " + va + " there, " + vb + " here";
    }
    return out;
}

std::string readFile(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw RankError(path + ": cannot read the scene file");
    std::ostringstream s;
    s << f.rdbuf();
    return s.str();
}

/// "SIZE:MTIME" of a file (modification time in nanoseconds), "missing" when it is not a file.
std::string fileStamp(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return "missing";
    return std::to_string(st.st_size) + ":" +
           std::to_string(int64_t(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec);
}

/// Every file the stage's attributes name (textures, IES profiles...), resolved.
std::set<std::string> assetFiles(const usd::Stage& stage) {
    std::set<std::string> files;
    auto add = [&](const usd::Value& v) {
        if (auto a = v.getAsset(); a && !a->resolved.empty()) files.insert(a->resolved);
        if (const auto* list = v.assets())
            for (const auto& a : *list)
                if (!a.resolved.empty()) files.insert(a.resolved);
    };
    for (const usd::Prim* p : stage.traverse())
        for (const usd::Attribute* attr : p->attributes()) {
            if (const usd::Value* v = attr->defaultValue()) add(*v);
            for (const auto& [t, v] : attr->timeSamples()) add(v);
        }
    return files;
}

/// The file whose entry differs between two CheckpointInfo::sceneFiles ("" when none does),
/// with what differs.
std::string changedSceneFile(const std::string& was, const std::string& now) {
    auto parse = [](const std::string& text) {
        std::map<std::string, std::string> m;  // path -> "layer HASH" / "file STAMP"
        std::stringstream ss(text);
        std::string line;
        while (std::getline(ss, line)) {
            auto a = line.find(' '), b = a == std::string::npos ? a : line.find(' ', a + 1);
            if (b != std::string::npos) m[line.substr(b + 1)] = line.substr(0, b);
        }
        return m;
    };
    auto a = parse(was), b = parse(now);
    for (const auto& [path, entry] : a) {
        auto it = b.find(path);
        if (it != b.end() && it->second != entry)
            return path + " changed since the checkpoint was written";
    }
    for (const auto& [path, entry] : b)
        if (!a.count(path) && entry.rfind("layer ", 0) == 0) return path + " is not a layer of the checkpoint's scene";
    for (const auto& [path, entry] : a)
        if (!b.count(path) && entry.rfind("layer ", 0) == 0) return path + " is no longer a layer of the scene";
    return "";
}

/// Writes the session's AOVs like `principled render` does (tools/outputs.h): every output,
/// each complete or absent; then fails naming every file that could not be written.
void writeOutputs(host::RenderSession& session, const std::vector<std::string>& outputs, bool split) {
    std::vector<std::string> errors = tools::writeOutputs(session, outputs, split);
    std::string all;
    for (const auto& e : errors) all += (all.empty() ? "" : "; ") + e;
    if (!errors.empty()) throw RankError(all);
}

/// Under mpirun a rank's stderr is a pipe to the launcher; rank 0 usually runs on the node
/// mpirun was started on, as its child: draw the bar when mpirun's own stderr is a terminal.
bool launcherOnTerminal() {
    std::error_code ec;
    std::string target = fs::read_symlink("/proc/" + std::to_string(getppid()) + "/fd/2", ec).string();
    return !ec && (target.rfind("/dev/pts/", 0) == 0 || target.rfind("/dev/tty", 0) == 0);
}

/// CPU time of the calling thread: the reduction's cost without other processes' load.
double threadCpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

class Job {
public:
    Job(Comm& comm, const host::SessionOptions& base, std::string scene, std::vector<std::string> outputs,
        bool split, bool quiet, Options options)
        : _comm(comm), _base(base), _scene(std::move(scene)), _outputs(std::move(outputs)),
          _split(split), _quiet(quiet), _opt(std::move(options)),
          _bar("render", !quiet && comm.rank() == 0 && (!comm.distributed() || launcherOnTerminal()),
               !comm.distributed()) {}

    void run();

private:
    std::unique_ptr<host::RenderSession> open(double time, int first, int end);
    /// _hash and _sceneFiles from the first session's stage: every layer it read and every
    /// file its attributes name.
    void describeScene(const usd::Stage& stage);
    void checkSameEverywhere(const std::string& settings);
    /// Renders [first, end) into the session, resuming from / writing checkpoints.
    void render(host::RenderSession& session, int first, int end, const std::string& checkpoint,
                const std::string& settings);
    void progress(long long localDone);
    void serveProgress();
    void waitFor(int src, int tag);
    std::string checkpointPath(double time, bool wholeFrame) const;
    void note(const std::string& text) const {
        if (!_quiet) std::fprintf(stderr, "principled: %s\n", text.c_str());
    }

    Comm& _comm;
    host::SessionOptions _base;
    int _width = 0, _height = 0;  ///< the image size the sessions resolved
    std::string _scene, _sceneText, _hash;
    std::string _sceneFiles;  ///< CheckpointInfo::sceneFiles of this scene
    std::vector<std::string> _outputs;
    bool _split, _quiet;
    std::set<std::string> _reportedWarnings;  ///< printed already (later frames repeat the stage's)
    Options _opt;
    ProgressBar _bar;
    bool _checked = false;
    long long _doneBefore = 0, _totalWork = 0, _shown = -1;
    std::vector<long long> _done;  // rank 0: samples per pixel finished by each rank
    std::vector<std::string> _written;  // checkpoints this rank wrote (removed at the end)
    int _checkpointsWritten = 0;
    long long _resumedSamples = 0;  ///< samples per pixel this rank took from checkpoints
    std::string _cameraPath;        ///< the camera the sessions resolved
    int _frameDecimals = 0;  ///< of the frame numbers in file names (frameDecimals)
};

std::unique_ptr<host::RenderSession> Job::open(double time, int first, int end) {
    host::SessionOptions o = _base;
    o.time = time;
    o.sampleRangeFirst = first;
    o.sampleRangeEnd = end;
    try {
        auto session = _scene.empty() ? host::RenderSession::openString(_sceneText, "<default scene>", o)
                                      : host::RenderSession::openFile(_scene, o);
        _width = session->width(), _height = session->height();  // resolved (RenderSettings)
        _cameraPath = session->cameraPath();
        if (_hash.empty()) describeScene(session->stage());
        return session;
    } catch (const usd::Error& e) {
        throw RankError(e.what());
    } catch (const host::UserError& e) {
        throw RankError(e.what());
    }
}

void Job::describeScene(const usd::Stage& stage) {
    if (_scene.empty()) {
        _hash = hashBytes(_sceneText);
        return;
    }
    // The composed stage is the scene: a shot's root layer rarely changes, its sublayers,
    // references and payloads do. One layer hashes as its bytes alone.
    std::string all;
    for (const auto& layer : stage.layerFiles()) {
        std::string text = readFile(layer);
        _sceneFiles += "layer " + hashBytes(text) + " " + layer + "\n";
        all += text;
    }
    _hash = hashBytes(all);
    for (const auto& file : assetFiles(stage)) _sceneFiles += "file " + fileStamp(file) + " " + file + "\n";
}

void Job::checkSameEverywhere(const std::string& settings) {
    if (_checked) return;
    _checked = true;
    std::string mine = _hash + "|" + settings, root = mine;
    _comm.broadcast(root);
    if (root != mine) {
        if (root.substr(0, 16) != _hash)
            throw RankError("the scene differs from rank 0's (hash " + _hash + " here, " + root.substr(0, 16) +
                            " on rank 0): every rank must read the same scene, e.g. from a shared filesystem");
        throw RankError("the render settings differ from rank 0's: " + settingsDiff(root.substr(17), settings));
    }
}

std::string Job::checkpointPath(double time, bool wholeFrame) const {
    fs::path dir = _opt.checkpointDir.empty() ? fs::path(_outputs.front() + ".ckpt") : fs::path(_opt.checkpointDir);
    // Whole frames of an animation are independent of the rank layout; sample ranges are not.
    std::string name = _opt.frames.empty() ? "" : "frame" + frameTag(time, _frameDecimals) + ".";
    name += wholeFrame && !_opt.frames.empty() ? "whole" : "rank" + std::to_string(_comm.rank());
    return (dir / (name + ".exr")).string();
}

void Job::serveProgress() {
    for (int src; (src = _comm.probe(-1, Comm::kProgress)) >= 0;)
        _done[size_t(src)] = _comm.recvInt64(src, Comm::kProgress);
    long long sum = 0;
    for (long long d : _done) sum += d;
    if (sum == _shown) return;
    _shown = sum;
    _bar.update(double(sum), double(_totalWork),
                std::to_string(sum) + "/" + std::to_string(_totalWork) + " spp" +
                    (_comm.distributed() ? " over " + std::to_string(_comm.size()) + " ranks" : ""));
}

void Job::progress(long long localDone) {
    if (_comm.rank() == 0) {
        _done[0] = localDone;
        serveProgress();
    } else {
        _comm.sendInt64(0, Comm::kProgress, localDone);
    }
}

void Job::waitFor(int src, int tag) {
    while (_comm.probe(src, tag) < 0) {
        serveProgress();
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    serveProgress();
}

void Job::render(host::RenderSession& session, int first, int end, const std::string& checkpoint,
                 const std::string& settings) {
    if (end <= first) return;  // more ranks than samples: nothing to do here
    int lastCheckpoint = 0;
    if (_opt.resume && fs::exists(checkpoint)) {
        Accumulation acc;
        CheckpointInfo info;
        std::string error;
        if (!readCheckpoint(checkpoint, &acc, &info, &error)) throw RankError(error);
        const std::string changed = changedSceneFile(info.sceneFiles, _sceneFiles);
        if (info.sceneHash != _hash)
            throw RankError("refusing to resume from " + checkpoint + ": it was rendered from another scene (hash " +
                            info.sceneHash + ", this scene " + _hash + (changed.empty() ? "" : "; " + changed) +
                            "); delete it or render without --resume");
        if (!changed.empty())
            throw RankError("refusing to resume from " + checkpoint + ": " + changed +
                            " (size or modification time); delete it or render without --resume");
        if (info.settings != settings)
            throw RankError("refusing to resume from " + checkpoint + ": it was rendered with other settings (" +
                            settingsDiff(info.settings, settings) + "); delete it or render without --resume");
        if (info.rangeFirst != first || info.rangeEnd != end)
            throw RankError("refusing to resume from " + checkpoint + ": it holds sample range " +
                            std::to_string(info.rangeFirst) + ":" + std::to_string(info.rangeEnd) + " but this rank renders " +
                            std::to_string(first) + ":" + std::to_string(end) +
                            " (another number of ranks); resume with the same -np or delete it");
        session.step();  // sizes the accumulation; the checkpoint replaces what it rendered
        if (!acc.applyTo(session))
            throw RankError("refusing to resume from " + checkpoint + ": its AOVs or resolution differ");
        lastCheckpoint = acc.completedSamples;
        _resumedSamples += acc.completedSamples;
        note((_comm.distributed() ? "rank " + std::to_string(_comm.rank()) + ": " : std::string()) + "resumed " +
             std::to_string(acc.completedSamples) + " of samples " + std::to_string(first) + ":" +
             std::to_string(end) + " from " + checkpoint);
    }
    progress(_doneBefore + session.completedSamples());
    while (!session.converged()) {
        session.step();
        int done = session.completedSamples();
        progress(_doneBefore + done);
        // Every checkpointEvery samples, and once the range is done (a later failure elsewhere
        // then costs this rank nothing on --resume).
        if (_opt.checkpointEvery > 0 &&
            (done - lastCheckpoint >= _opt.checkpointEvery || (session.converged() && done > lastCheckpoint))) {
            CheckpointInfo info{_hash, _sceneFiles, settings, first, end, _comm.rank(), _comm.size()};
            std::string error;
            if (!writeCheckpoint(checkpoint, Accumulation::capture(session), info, &error)) throw RankError(error);
            if (_written.empty() || _written.back() != checkpoint) _written.push_back(checkpoint);
            lastCheckpoint = done;
            ++_checkpointsWritten;
            // Test hook: die like a killed node right after the Nth checkpoint.
            if (const char* k = std::getenv("PRINCIPLED_TEST_KILL_AFTER_CHECKPOINT"))
                if (std::atoi(k) == _checkpointsWritten) std::raise(SIGKILL);
        }
    }
    _doneBefore += end - first;
}

void Job::run() {
    // The effective setting: --set noiseThreshold=... is applied after --noise-threshold.
    float noiseThreshold = _base.noiseThreshold;
    if (auto it = _base.settings.find("noiseThreshold"); it != _base.settings.end())
        noiseThreshold = std::strtof(it->second.c_str(), nullptr);
    if (noiseThreshold > 0.0f || std::isnan(noiseThreshold))
        throw RankError("--noise-threshold / --set noiseThreshold (adaptive sampling) cannot be combined with MPI "
                        "ranks, --frames or checkpoints: which pixels stopped is not part of the merged accumulation");
    if (_opt.checkpointEvery < 0) throw RankError("--checkpoint-every must be at least 0");
    std::vector<double> frames = parseFrames(_opt.frames);
    bool animated = !_opt.frames.empty();
    if (animated && !std::isnan(_base.time))
        throw RankError("--time and --frames cannot be combined: --frames gives each frame its time");
    _frameDecimals = frameDecimals(frames);
    for (size_t f = 1; f < frames.size(); ++f)
        if (frameTag(frames[f], _frameDecimals) == frameTag(frames[f - 1], _frameDecimals))
            throw RankError("--frames " + _opt.frames + ": frames " + std::to_string(frames[f - 1]) + " and " +
                            std::to_string(frames[f]) + " would write the same file (frame numbers keep 6 decimals)");
    if (_scene.empty()) _sceneText = kDefaultSceneUsda;
    else if (!std::ifstream(_scene)) throw RankError(_scene + ": cannot read the scene file");
    int spp = _base.samplesPerPixel;
    int ranks = _comm.size(), rank = _comm.rank();
    _totalWork = (long long)frames.size() * spp;
    _done.assign(size_t(ranks), 0);
    auto t0 = std::chrono::steady_clock::now();

    // More frames than ranks: each rank renders whole frames (round robin) and writes them.
    // Otherwise every frame's samples are split into one contiguous range per rank.
    bool wholeFrames = ranks == 1 || frames.size() >= size_t(ranks);
    size_t reducedBytes = 0;
    double reduceSeconds = 0.0, reduceCpuSeconds = 0.0;
    for (size_t f = 0; f < frames.size(); ++f) {
        if (wholeFrames && int(f % size_t(ranks)) != rank) continue;
        double time = frames[f];
        int chunk = (spp + ranks - 1) / ranks;
        int first = wholeFrames ? 0 : std::min(spp, rank * chunk);
        int end = wholeFrames ? spp : std::min(spp, (rank + 1) * chunk);
        auto session = open(time, first, end);
        host::SessionOptions o = _base;
        o.time = time;
        std::string settings = canonicalSettings(o);
        checkSameEverywhere(canonicalSettings(_base));
        // Each frame's warnings, once: a later frame (its own session) repeats the stage's, and
        // adds its own (animated topology, say), tagged with its time. A frame split across
        // ranks reports from rank 0 only.
        if (wholeFrames || rank == 0) {
            for (const auto& w : session->takeWarnings()) {
                if (!_reportedWarnings.insert(w).second || _quiet) continue;
                if (animated)
                    std::fprintf(stderr, "principled: warning: %s (time %g)\n", w.c_str(), time);
                else
                    std::fprintf(stderr, "principled: warning: %s\n", w.c_str());
            }
        }
        render(*session, first, end, checkpointPath(time, wholeFrames), settings);
        if (wholeFrames) {
            writeOutputs(*session, [&] {
                std::vector<std::string> outs;
                for (const auto& out : _outputs) outs.push_back(framePath(out, time, _frameDecimals, animated));
                return outs;
            }(), _split);
            continue;
        }
        // Fixed-order reduction: rank 0 adds rank 1's range, then rank 2's... so the sums are
        // the same whatever order the ranks finish in.
        Accumulation acc = Accumulation::capture(*session);
        if (rank != 0) {
            _comm.send(0, Comm::kData, acc.pack());
            continue;
        }
        for (int r = 1; r < ranks; ++r) {
            waitFor(r, Comm::kData);
            auto tr = std::chrono::steady_clock::now();
            double cr = threadCpuSeconds();
            std::vector<char> bytes(acc.packedSize());
            _comm.recv(r, Comm::kData, bytes);
            Accumulation part = acc;
            if (!part.unpack(bytes) || !acc.merge(part))
                throw RankError("rank " + std::to_string(r) + " sent an accumulation of another shape");
            reducedBytes += bytes.size();
            reduceSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - tr).count();
            reduceCpuSeconds += threadCpuSeconds() - cr;
        }
        if (!acc.applyTo(*session)) throw RankError("cannot apply the merged accumulation");
        std::vector<std::string> outs;
        for (const auto& out : _outputs) outs.push_back(framePath(out, time, _frameDecimals, animated));
        writeOutputs(*session, outs, _split);
    }
    // Everyone is done (and every output is written) before checkpoints are removed.
    if (rank != 0) {
        _comm.sendInt64(0, Comm::kDone, 1);
    } else {
        for (int r = 1; r < ranks; ++r) {
            waitFor(r, Comm::kDone);
            _comm.recvInt64(r, Comm::kDone);
        }
        serveProgress();
        _bar.finish();
    }
    _comm.barrier();
    std::error_code ec;
    for (const auto& c : _written) fs::remove(c, ec);
    _comm.barrier();
    if (rank == 0) {
        fs::path dir = _opt.checkpointDir.empty() ? fs::path(_outputs.front() + ".ckpt") : fs::path(_opt.checkpointDir);
        if (fs::is_directory(dir, ec) && fs::is_empty(dir, ec)) fs::remove(dir, ec);
        double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::string how = ranks > 1 ? (wholeFrames ? " (whole frames per rank)" : " (sample ranges per rank)") : "";
        note("rendered " + std::to_string(_width) + "x" + std::to_string(_height) + " at " +
             std::to_string(spp) + " spp, " + std::to_string(frames.size()) + " frame(s) on " + std::to_string(ranks) +
             " rank(s)" + how + " in " + std::to_string(seconds).substr(0, 6) + "s");
        if (!_opt.statsPath.empty()) {
            // The job's figures (a plain render's --stats also has the delegate's and startup's).
            nlohmann::json j;
            j["scene"] = _scene.empty() ? "<default scene>" : _scene;
            j["width"] = _width;
            j["height"] = _height;
            j["samplesPerPixel"] = spp;
            j["camera"] = _cameraPath;
            j["timedOut"] = false;
            j["frames"] = frames.size();
            j["ranks"] = ranks;
            j["renderWallSeconds"] = seconds;
            j["checkpointsWritten"] = _checkpointsWritten;  // rank 0's
            j["resumedSamplesPerPixel"] = _resumedSamples;  // rank 0's, over its frames
            std::ofstream f(_opt.statsPath);
            if (!(f << j.dump(2) << "\n")) throw RankError(_opt.statsPath + ": cannot write the stats file");
        }
        if (std::getenv("PRINCIPLED_MPI_TIMING"))
            std::fprintf(stderr, "principled: timing: total %.4f s, reduce %.4f s (cpu %.4f s), %zu bytes received\n",
                         seconds, reduceSeconds, reduceCpuSeconds, reducedBytes);
    }
}

}  // namespace

void addOptions(CLI::App* render, Options* o) {
    render->add_option("--frames", o->frames,
                       "Render time codes A:B (or A:B:STEP), one image per frame: OUT.0001.exr or #### in the name");
    render->add_option("--checkpoint-every", o->checkpointEvery,
                       "Write a resumable checkpoint every N samples per pixel (0 = never)")
        ->check(CLI::Range(0, 1 << 20));
    render->add_option("--checkpoint-dir", o->checkpointDir, "Where checkpoints go (default: OUTPUT.ckpt/)");
    render->add_flag("--resume", o->resume, "Continue from the checkpoints of an interrupted render of the same scene and settings");
}

bool wanted(const Options& o) {
    return Comm::launcherSize() > 0 || !o.frames.empty() || o.checkpointEvery > 0 || o.resume;
}

int run(const host::SessionOptions& session, const std::string& scene, const std::vector<std::string>& outputs,
        bool split, bool quiet, const Options& options) {
    Comm comm;
    if (comm.launchedWithoutSupport()) {
        std::fprintf(stderr, "principled: error: started by an MPI launcher with several ranks, but this principled "
                             "was built without MPI (install libopenmpi-dev and rebuild)\n");
        return 1;
    }
    if (!comm.loadError().empty()) {
        std::fprintf(stderr, "principled: error: %s\n", comm.loadError().c_str());
        return 1;
    }
    try {
        Job(comm, session, scene, outputs, split, quiet, options).run();
    } catch (const std::exception& e) {
        const std::string what = dynamic_cast<const std::bad_alloc*>(&e)
                                     ? "ran out of memory: reduce --res, the AOVs (--aov) or the scene's subdivision "
                                       "(--refine-level, --set subdivisionBudget=...)"
                                     : e.what();
        if (!comm.distributed()) {
            std::fprintf(stderr, "principled: error: %s\n", what.c_str());
            return 1;
        }
        std::fprintf(stderr, "principled: error: rank %d of %d (%s): %s\n", comm.rank(), comm.size(),
                     comm.host().c_str(), what.c_str());
        comm.abort(1);
    }
    return 0;
}

}  // namespace principled::tools::distributed
