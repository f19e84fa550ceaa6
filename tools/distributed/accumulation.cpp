// SPDX-License-Identifier: Apache-2.0
#include "tools/distributed/accumulation.h"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <unistd.h>

#include "delegate/imageio/imageIO.h"
#include "delegate/renderBuffer.h"
#include "delegate/renderPass.h"
#include "plugins/renderSession.h"

namespace principled::tools::distributed {

namespace {

template <class T>
void append(std::vector<char>& out, const std::vector<T>& v) {
    const char* p = reinterpret_cast<const char*>(v.data());
    out.insert(out.end(), p, p + v.size() * sizeof(T));
}

template <class T>
bool take(const std::vector<char>& in, size_t& at, std::vector<T>& v) {
    size_t n = v.size() * sizeof(T);
    if (at + n > in.size()) return false;
    if (n) std::memcpy(v.data(), in.data() + at, n);
    at += n;
    return true;
}

}  // namespace

Accumulation Accumulation::capture(const host::RenderSession& session) {
    Accumulation acc;
    acc.width = session.width();
    acc.height = session.height();
    size_t n = size_t(acc.width) * acc.height;
    acc.completedSamples = session.completedSamples();
    for (const auto& img : session.aovs()) {
        const auto* buf = session.buffer(img.name);
        AovAccumulation a;
        a.name = img.name;
        a.components = img.components;
        a.isInt = img.isInt;
        a.multiSampled = buf->isMultiSampled();
        a.sums = buf->sums();
        a.ints = buf->ints();
        a.counts = buf->counts();
        acc.aovs.push_back(std::move(a));
    }
    acc.stats = session.pass()->pixelStats();
    embree::PixelStats& st = acc.stats;
    if (st.lumSum.size() != n) st.lumSum.assign(n, 0.0);
    if (st.lumSqSum.size() != n) st.lumSqSum.assign(n, 0.0);
    if (st.samples.size() != n) st.samples.assign(n, 0);
    if (st.ltSum.size() != n || st.ltN1.size() != n || st.ltN2.size() != n) {
        st.ltSum.clear();  // no light paths
        st.ltN1.clear();
        st.ltN2.clear();
        st.ltPaths = st.ltSpread = 0.0;
        st.ltPasses = 0;
    }
    return acc;
}

bool Accumulation::applyTo(host::RenderSession& session) const {
    // Same shape as the session's buffers, checked without copying them.
    size_t n = size_t(width) * height;
    if (width != session.width() || height != session.height() || aovs.size() != session.aovs().size() ||
        stats.lumSum.size() != n || stats.lumSqSum.size() != n || stats.samples.size() != n)
        return false;
    for (const auto& a : aovs) {
        const auto* buf = session.buffer(a.name);
        if (!buf || buf->isMultiSampled() != a.multiSampled || buf->sums().size() != a.sums.size() ||
            buf->ints().size() != a.ints.size() || buf->counts().size() != a.counts.size())
            return false;
    }
    if (!session.pass()->setPixelStats(stats, completedSamples)) return false;
    for (const auto& a : aovs) {
        auto* buf = session.buffer(a.name);
        if (!buf->setAccumulation(a.sums, a.ints, a.counts)) return false;
        // Statistics AOVs are derived from the merged luminance statistics.
        if (a.name == "sampleCount" || a.name == "variance") {
            for (int y = 0; y < height; ++y)
                for (int x = 0; x < width; ++x) {
                    size_t p = size_t(y) * width + x;
                    float v = a.name == "variance" ? float(session.pass()->meanVariance(p))
                                                   : float(stats.samples[p]);
                    buf->setPixel(x, y, &v);
                }
        }
        buf->resolve();
    }
    return true;
}

bool Accumulation::sameShape(const Accumulation& o) const {
    if (width != o.width || height != o.height || aovs.size() != o.aovs.size() ||
        stats.lumSum.size() != o.stats.lumSum.size() || stats.lumSqSum.size() != o.stats.lumSqSum.size() ||
        stats.samples.size() != o.stats.samples.size())
        return false;
    for (size_t i = 0; i < aovs.size(); ++i) {
        const auto &a = aovs[i], &b = o.aovs[i];
        if (a.name != b.name || a.components != b.components || a.isInt != b.isInt ||
            a.multiSampled != b.multiSampled || a.sums.size() != b.sums.size() ||
            a.ints.size() != b.ints.size() || a.counts.size() != b.counts.size())
            return false;
    }
    return true;
}

bool Accumulation::merge(const Accumulation& next) {
    if (!sameShape(next)) return false;
    size_t n = size_t(width) * height;
    for (size_t i = 0; i < aovs.size(); ++i) {
        auto& a = aovs[i];
        const auto& b = next.aovs[i];
        int c = a.components;
        for (size_t p = 0; p < n; ++p) {
            if (a.isInt) {
                if (a.counts[p] == 0) a.ints[p] = b.ints[p];
            } else if (a.multiSampled) {
                for (int k = 0; k < c; ++k) a.sums[p * c + k] += b.sums[p * c + k];
            } else if (a.counts[p] == 0) {
                for (int k = 0; k < c; ++k) a.sums[p * c + k] = b.sums[p * c + k];
            }
            a.counts[p] += b.counts[p];
        }
    }
    for (size_t p = 0; p < stats.lumSum.size(); ++p) {
        stats.lumSum[p] += next.stats.lumSum[p];
        stats.lumSqSum[p] += next.stats.lumSqSum[p];
        stats.samples[p] += next.stats.samples[p];
    }
    if (!next.stats.ltSum.empty()) {
        if (stats.ltSum.empty()) {
            stats.ltSum.assign(n, 0.0);
            stats.ltN1.assign(n, 0.0);
            stats.ltN2.assign(n, 0.0);
        }
        for (size_t p = 0; p < n; ++p) {
            stats.ltSum[p] += next.stats.ltSum[p];
            stats.ltN1[p] += next.stats.ltN1[p];
            stats.ltN2[p] += next.stats.ltN2[p];
        }
        stats.ltPaths += next.stats.ltPaths;
        stats.ltSpread += next.stats.ltSpread;
        stats.ltPasses += next.stats.ltPasses;
    }
    completedSamples += next.completedSamples;
    return true;
}

size_t Accumulation::packedSize() const {
    size_t bytes = sizeof(int);
    for (const auto& a : aovs)
        bytes += a.sums.size() * 8 + a.ints.size() * 4 + a.counts.size() * 4;
    bytes += stats.lumSum.size() * 8 + stats.lumSqSum.size() * 8 + stats.samples.size() * sizeof(int);
    return bytes + 2 * sizeof(int) + 2 * 8 + (stats.ltSum.size() + stats.ltN1.size() + stats.ltN2.size()) * 8;
}

std::vector<char> Accumulation::pack() const {
    std::vector<char> out;
    out.reserve(packedSize());
    append(out, std::vector<int>{completedSamples});
    for (const auto& a : aovs) {
        append(out, a.sums);
        append(out, a.ints);
        append(out, a.counts);
    }
    append(out, stats.lumSum);
    append(out, stats.lumSqSum);
    append(out, stats.samples);
    append(out, std::vector<int>{stats.ltSum.empty() ? 0 : 1, stats.ltPasses});
    append(out, std::vector<double>{stats.ltPaths, stats.ltSpread});
    append(out, stats.ltSum);
    append(out, stats.ltN1);
    append(out, stats.ltN2);
    return out;
}

bool Accumulation::unpack(const std::vector<char>& in) {
    size_t at = 0;
    std::vector<int> completed(1);
    bool ok = take(in, at, completed);
    completedSamples = completed[0];
    for (auto& a : aovs) ok = ok && take(in, at, a.sums) && take(in, at, a.ints) && take(in, at, a.counts);
    ok = ok && take(in, at, stats.lumSum) && take(in, at, stats.lumSqSum) && take(in, at, stats.samples);
    std::vector<int> lt(2);
    std::vector<double> ltFrame(2);
    ok = ok && take(in, at, lt) && take(in, at, ltFrame);
    const size_t n = lt[0] ? stats.lumSum.size() : 0;
    stats.ltSum.assign(n, 0.0);
    stats.ltN1.assign(n, 0.0);
    stats.ltN2.assign(n, 0.0);
    stats.ltPasses = lt[1];
    stats.ltPaths = ltFrame[0];
    stats.ltSpread = ltFrame[1];
    ok = ok && take(in, at, stats.ltSum) && take(in, at, stats.ltN1) && take(in, at, stats.ltN2);
    return ok && at == in.size();
}

// ---- checkpoints ---------------------------------------------------------------------------

bool writeCheckpoint(const std::string& path, const Accumulation& acc, const CheckpointInfo& info,
                     std::string* error) {
    namespace fs = std::filesystem;
    size_t n = size_t(acc.width) * acc.height;
    std::vector<std::string> names;
    std::vector<std::vector<uint32_t>> planes;
    auto addDouble = [&](const std::string& name, const std::vector<double>& v, int stride, int k) {
        std::vector<uint32_t> lo(n), hi(n);
        for (size_t p = 0; p < n; ++p) {
            uint64_t bits;
            std::memcpy(&bits, &v[p * stride + k], 8);
            lo[p] = uint32_t(bits);
            hi[p] = uint32_t(bits >> 32);
        }
        names.push_back(name + ".lo");
        planes.push_back(std::move(lo));
        names.push_back(name + ".hi");
        planes.push_back(std::move(hi));
    };
    auto addInt = [&](const std::string& name, const std::vector<int32_t>& v) {
        std::vector<uint32_t> w(n);
        for (size_t p = 0; p < n; ++p) w[p] = uint32_t(v[p]);
        names.push_back(name);
        planes.push_back(std::move(w));
    };
    for (const auto& a : acc.aovs) {
        if (a.isInt) {
            addInt(a.name + ".id", a.ints);
        } else {
            for (int k = 0; k < a.components; ++k)
                addDouble(a.name + ".sum" + std::to_string(k), a.sums, a.components, k);
        }
        addInt(a.name + ".count", a.counts);
    }
    addDouble("stats.lumSum", acc.stats.lumSum, 1, 0);
    addDouble("stats.lumSqSum", acc.stats.lumSqSum, 1, 0);
    addInt("stats.samples", std::vector<int32_t>(acc.stats.samples.begin(), acc.stats.samples.end()));
    if (!acc.stats.ltSum.empty()) {
        addDouble("stats.ltSum", acc.stats.ltSum, 1, 0);
        addDouble("stats.ltN1", acc.stats.ltN1, 1, 0);
        addDouble("stats.ltN2", acc.stats.ltN2, 1, 0);
    }

    imageio::ImageSpec spec;
    spec.width = acc.width;
    spec.height = acc.height;
    spec.channels = int(names.size());
    spec.format = imageio::PixelType::UInt32;
    spec.channelNames = names;
    spec.strings["compression"] = "zip";
    spec.strings["principled:checkpoint"] = "1";
    spec.strings["principled:sceneHash"] = info.sceneHash;
    spec.strings["principled:settings"] = info.settings;
    spec.strings["principled:sceneFiles"] = info.sceneFiles;
    spec.strings["principled:sampleRange"] = std::to_string(info.rangeFirst) + ":" + std::to_string(info.rangeEnd);
    spec.numbers["principled:completedSamples"] = acc.completedSamples;
    spec.numbers["principled:passes"] = acc.stats.passes;
    if (!acc.stats.ltSum.empty()) {
        // Exact doubles as text (metadata numbers are read back as float).
        char frame[96];
        std::snprintf(frame, sizeof frame, "%.17g %.17g %d", acc.stats.ltPaths, acc.stats.ltSpread, acc.stats.ltPasses);
        spec.strings["principled:lightPathFrame"] = frame;
    }
    if (acc.stats.causticPaths > 0) {
        const embree::CausticBudget::State& b = acc.stats.budget;
        char state[256];
        std::snprintf(state, sizeof state, "%llu %llu %llu %llu %llu %llu %.17g %.17g",
                      (unsigned long long)acc.stats.causticPaths, (unsigned long long)b.paths,
                      (unsigned long long)b.lightRays, (unsigned long long)b.samples,
                      (unsigned long long)b.cameraRays, (unsigned long long)b.varianceCount, b.splatSquares,
                      b.varianceSum);
        spec.strings["principled:lightPaths"] = state;
    }
    std::string order;
    for (const auto& a : acc.aovs) order += (order.empty() ? "" : ",") + a.name;
    spec.strings["principled:aovs"] = order;
    for (const auto& a : acc.aovs)
        if (!a.isInt) spec.numbers["principled:multiSampled:" + a.name] = a.multiSampled ? 1 : 0;
    spec.strings["principled:rank"] = std::to_string(info.rank) + "/" + std::to_string(info.ranks);
    std::vector<uint32_t> pixels(n * names.size());
    for (size_t p = 0; p < n; ++p)
        for (size_t c = 0; c < names.size(); ++c) pixels[p * names.size() + c] = planes[c][p];

    fs::path final(path);
    std::error_code ec;
    if (!final.parent_path().empty()) fs::create_directories(final.parent_path(), ec);
    fs::path tmp = final.parent_path() / ("." + final.stem().string() + ".tmp" + std::to_string(getpid()) + ".exr");
    std::string reason;
    imageio::Backend* io = imageio::backend(&reason);
    if (!io || !io->write(tmp.string(), final.string(), spec, pixels.data(), &reason)) {
        *error = path + ": cannot write the checkpoint" + (reason.empty() ? "" : ": " + reason);
        fs::remove(tmp, ec);
        return false;
    }
    fs::rename(tmp, final, ec);
    if (ec) {
        *error = path + ": cannot rename the checkpoint into place: " + ec.message();
        fs::remove(tmp, ec);
        return false;
    }
    return true;
}

bool readCheckpoint(const std::string& path, Accumulation* acc, CheckpointInfo* info,
                    std::string* error) {
    std::string reason;
    imageio::Backend* io = imageio::backend(&reason);
    std::unique_ptr<imageio::ImageReader> in = io ? io->open(path, &reason) : nullptr;
    if (!in) {
        *error = path + ": cannot read the checkpoint: " + reason;
        return false;
    }
    const imageio::ImageSpec& spec = in->spec();
    if (spec.string("principled:checkpoint") != "1") {
        *error = path + ": not a principled checkpoint (no principled:checkpoint metadata)";
        return false;
    }
    info->sceneHash = spec.string("principled:sceneHash");
    info->settings = spec.string("principled:settings");
    info->sceneFiles = spec.string("principled:sceneFiles");
    std::string range = spec.string("principled:sampleRange");
    if (std::sscanf(range.c_str(), "%d:%d", &info->rangeFirst, &info->rangeEnd) != 2) {
        *error = path + ": checkpoint has no valid principled:sampleRange";
        return false;
    }
    int nch = spec.channels;
    size_t n = size_t(spec.width) * spec.height;
    std::vector<uint32_t> pixels(n * nch);
    if (!in->read(imageio::PixelType::UInt32, nch, pixels.data())) {
        *error = path + ": cannot read the checkpoint pixels: " + in->error();
        return false;
    }
    std::map<std::string, int> index;
    for (int c = 0; c < nch && c < int(spec.channelNames.size()); ++c) index[spec.channelNames[c]] = c;
    auto plane = [&](const std::string& name, bool* ok) {
        std::vector<uint32_t> v(n);
        auto it = index.find(name);
        if (it == index.end()) {
            *ok = false;
            return v;
        }
        for (size_t p = 0; p < n; ++p) v[p] = pixels[p * nch + it->second];
        return v;
    };
    bool ok = true;
    auto readDouble = [&](const std::string& name, std::vector<double>& v, int stride, int k) {
        auto lo = plane(name + ".lo", &ok), hi = plane(name + ".hi", &ok);
        for (size_t p = 0; p < n; ++p) {
            uint64_t bits = uint64_t(lo[p]) | (uint64_t(hi[p]) << 32);
            std::memcpy(&v[p * stride + k], &bits, 8);
        }
    };
    acc->width = spec.width;
    acc->height = spec.height;
    acc->completedSamples = int(spec.number("principled:completedSamples", 0));
    acc->stats.passes = int(spec.number("principled:passes", 0));
    // EXR sorts channels by name: the AOV order comes from principled:aovs.
    acc->aovs.clear();
    std::stringstream order(spec.string("principled:aovs"));
    for (std::string name; std::getline(order, name, ',');) {
        if (!index.count(name + ".count")) {
            ok = false;
            break;
        }
        const std::string ch = name + ".count";
        AovAccumulation a;
        a.name = name;
        a.isInt = index.count(a.name + ".id") > 0;
        a.counts.resize(n);
        auto counts = plane(ch, &ok);
        for (size_t p = 0; p < n; ++p) a.counts[p] = int32_t(counts[p]);
        if (a.isInt) {
            a.components = 1;
            auto ids = plane(a.name + ".id", &ok);
            a.ints.resize(n);
            for (size_t p = 0; p < n; ++p) a.ints[p] = int32_t(ids[p]);
            a.multiSampled = false;
        } else {
            while (index.count(a.name + ".sum" + std::to_string(a.components) + ".lo")) ++a.components;
            a.sums.resize(n * a.components);
            for (int k = 0; k < a.components; ++k)
                readDouble(a.name + ".sum" + std::to_string(k), a.sums, a.components, k);
            a.multiSampled = spec.number("principled:multiSampled:" + a.name, 1) != 0;
        }
        acc->aovs.push_back(std::move(a));
    }
    acc->stats.lumSum.resize(n);
    acc->stats.lumSqSum.resize(n);
    readDouble("stats.lumSum", acc->stats.lumSum, 1, 0);
    readDouble("stats.lumSqSum", acc->stats.lumSqSum, 1, 0);
    auto samples = plane("stats.samples", &ok);
    acc->stats.samples.assign(samples.begin(), samples.end());
    // The light-traced share's statistics (checkpoints of renders with light paths; older
    // checkpoints have none, and their caustic pixels' variance counts only the samples').
    acc->stats.ltSum.clear();
    acc->stats.ltN1.clear();
    acc->stats.ltN2.clear();
    acc->stats.ltPaths = acc->stats.ltSpread = 0.0;
    acc->stats.ltPasses = 0;
    const std::string frame = spec.string("principled:lightPathFrame");
    if (!frame.empty() && index.count("stats.ltSum.lo")) {
        if (std::sscanf(frame.c_str(), "%lf %lf %d", &acc->stats.ltPaths, &acc->stats.ltSpread, &acc->stats.ltPasses) != 3) {
            *error = path + ": checkpoint has an invalid principled:lightPathFrame";
            return false;
        }
        acc->stats.ltSum.resize(n);
        acc->stats.ltN1.resize(n);
        acc->stats.ltN2.resize(n);
        readDouble("stats.ltSum", acc->stats.ltSum, 1, 0);
        readDouble("stats.ltN1", acc->stats.ltN1, 1, 0);
        readDouble("stats.ltN2", acc->stats.ltN2, 1, 0);
    }
    acc->stats.causticPaths = 0;
    acc->stats.budget = {};
    const std::string lightPaths = spec.string("principled:lightPaths");
    if (!lightPaths.empty()) {
        unsigned long long v[6];
        embree::CausticBudget::State& b = acc->stats.budget;
        if (std::sscanf(lightPaths.c_str(), "%llu %llu %llu %llu %llu %llu %lf %lf", &v[0], &v[1], &v[2], &v[3],
                        &v[4], &v[5], &b.splatSquares, &b.varianceSum) != 8) {
            *error = path + ": checkpoint has an invalid principled:lightPaths";
            return false;
        }
        acc->stats.causticPaths = v[0];
        b.paths = v[1], b.lightRays = v[2], b.samples = v[3], b.cameraRays = v[4], b.varianceCount = v[5];
    }
    if (!ok) {
        *error = path + ": checkpoint is missing channels";
        return false;
    }
    return true;
}

std::string hashBytes(const std::string& bytes) {
    uint64_t h = 1469598103934665603ull;
    for (unsigned char c : bytes) {
        h ^= c;
        h *= 1099511628211ull;
    }
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    return buf;
}

}  // namespace principled::tools::distributed
