// SPDX-License-Identifier: Apache-2.0
// Building a SubdivTopology (OpenSubdiv Far) and re-posing it. Primvars: subdivPrimvars.cpp.
#include "delegate/subdiv/subdivTopology.h"

#include <opensubdiv/far/error.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <functional>
#include <mutex>
#include <numeric>

#include "delegate/subdiv/cageMesh.h"
#include "delegate/subdiv/osdStencils.h"
#include "delegate/subdiv/parallelRange.h"
#include "delegate/subdiv/sharpnessTags.h"
#include "delegate/subdiv/usdSdc.h"

namespace principled::subdiv {

static_assert(sizeof(glm::vec3) == 3 * sizeof(float), "points are read as packed float arrays");

namespace {

// 8: a quad becomes 4^8 = 65536 faces. Far's own limit is 15 (a 4-bit field); anything finer
// than 8 should come from adaptive tessellation rather than uniform refinement.
constexpr int kMaxLevel = 8;

std::atomic<uint64_t> gRefinerBuilds{0};
std::atomic<uint64_t> gNextId{1};

// OpenSubdiv reports through process-wide callbacks; messages land in the calling thread's
// buffer so concurrent builds do not mix them up.
thread_local std::string tOsdMessage;

void onOsdError(Far::ErrorType, const char* message) {
    if (tOsdMessage.empty()) tOsdMessage = message;
}
void onOsdWarning(const char* message) {
    if (tOsdMessage.empty()) tOsdMessage = message;
}

void installOsdCallbacks() {
    static std::once_flag once;
    std::call_once(once, [] {
        Far::SetErrorCallback(onOsdError);
        Far::SetWarningCallback(onOsdWarning);
    });
}

Scheme toScheme(Sdc::SchemeType s) {
    switch (s) {
        case Sdc::SCHEME_LOOP:
            return Scheme::Loop;
        case Sdc::SCHEME_BILINEAR:
            return Scheme::Bilinear;
        default:
            return Scheme::CatmullClark;
    }
}

}  // namespace

size_t refinedFaceEstimate(const hd::MeshTopology& t, bool loop, int level) {
    const double grow = std::pow(4.0, level - 1);
    double faces = 0.0;
    for (int n : t.faceVertexCounts) faces += loop ? 4.0 * grow : (n == 4 ? 4.0 : double(n)) * grow;
    return faces > 1e18 ? size_t(-1) : size_t(faces);
}

namespace {

/// True when row r of s is exactly "1 x element r" for every row: the table is a no-op.
bool isIdentity(const Stencils& s) {
    for (size_t r = 0; r < s.rows(); ++r) {
        if (s.offsets[r + 1] - s.offsets[r] != 1) return false;
        if (s.indices[s.offsets[r]] != int(r) || s.weights[s.offsets[r]] != 1.0f) return false;
    }
    return true;
}

/// PRINCIPLED_MEM_TRACE=1: resident memory after each build phase, on stderr (the refiner is
/// the largest transient: docs/geometry.md, subdivision memory).
void memTrace(const char* phase) {
    static const bool on = std::getenv("PRINCIPLED_MEM_TRACE") != nullptr;
    if (!on) return;
    long pages = 0, rss = 0;
    if (FILE* f = std::fopen("/proc/self/statm", "r")) {
        if (std::fscanf(f, "%ld %ld", &pages, &rss) != 2) rss = 0;
        std::fclose(f);
    }
    std::fprintf(stderr, "[mem]   subdiv build, %-14s rss %7.1f MB\n", phase, rss * 4096.0 / 1e6);
}

double secondsSince(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

uint64_t SubdivTopology::refinerBuildCount() {
    return gRefinerBuilds.load();
}

std::unique_ptr<SubdivTopology> SubdivTopology::create(const hd::MeshTopology& topology,
                                                       const hd::SubdivTags& tags,
                                                       size_t pointCount,
                                                       const BuildOptions& options,
                                                       std::string* error) {
    const auto start = std::chrono::steady_clock::now();
    std::string scratch;
    if (!error) error = &scratch;
    error->clear();
    if (!checkCage(topology, pointCount, error)) return nullptr;

    std::unique_ptr<SubdivTopology> t(new SubdivTopology());
    t->_topology = topology;
    t->_tags = tags;
    t->_pointCount = pointCount;
    t->_options = options;
    t->_id = gNextId.fetch_add(1);
    t->_level = std::clamp(options.level, 0, kMaxLevel);
    if (t->_level != options.level)
        t->_warnings.push_back("refine level " + std::to_string(options.level) + " clamped to " +
                               std::to_string(t->_level));

    // Face-varying channels: a bad one is dropped (the geometry is still fine).
    t->_fvar.resize(options.faceVarying.size());
    for (size_t c = 0; c < options.faceVarying.size(); ++c) {
        const auto& ch = options.faceVarying[c];
        bool ok = ch.indices.size() == topology.faceVertexIndices.size();
        for (size_t k = 0; ok && k < ch.indices.size(); ++k)
            ok = ch.indices[k] >= 0 && size_t(ch.indices[k]) < ch.valueCount;
        t->_fvar[c].available = ok;
        t->_fvar[c].coarseValues = ch.valueCount;
        if (!ok)
            t->_warnings.push_back("face-varying channel " + std::to_string(c) +
                                   " has a wrong index count or an index out of range; ignored");
    }

    if (topology.scheme == hd::Token("none") || t->_level == 0) {
        t->buildCage();
    } else if (!t->build(error)) {
        return nullptr;
    }
    t->_timings.total = secondsSince(start);
    return t;
}

void SubdivTopology::buildCage() {
    _scheme = Scheme::None;
    if (_topology.scheme != hd::Token("none")) {
        std::vector<std::string> ignored;
        _scheme = toScheme(sdcSetup(_topology, _tags, &ignored).scheme);
    }
    _level = 0;
    CageTriangles cage = triangulateCage(_topology, holeFlags(_topology, &_warnings));
    _triangles = std::move(cage.triangles);
    _triangleFace = std::move(cage.triangleFace);
    _refinedPoints = _pointCount;
    for (size_t c = 0; c < _fvar.size(); ++c) {
        if (!_fvar[c].available) continue;
        const auto& idx = _options.faceVarying[c].indices;
        auto& corners = *_fvar[c].corners;
        corners.reserve(cage.corners.size() * 3);
        for (const glm::uvec3& tri : cage.corners)
            for (int k = 0; k < 3; ++k) corners.push_back(idx[tri[k]]);
    }
}

bool SubdivTopology::build(std::string* error) {
    installOsdCallbacks();
    SdcSetup setup = sdcSetup(_topology, _tags, &_warnings);
    _scheme = toScheme(setup.scheme);
    // Lower the level until the refinement fits the face budget (checked before allocating).
    const int requested = _level;
    size_t estimate = refinedFaceEstimate(_topology, _scheme == Scheme::Loop, _level);
    while (_level > 0 && estimate > _options.maxRefinedFaces)
        estimate = refinedFaceEstimate(_topology, _scheme == Scheme::Loop, --_level);
    if (_level != requested)
        _warnings.push_back("level " + std::to_string(requested) + " would exceed the limit of " +
                            std::to_string(_options.maxRefinedFaces) +
                            " refined faces; using level " + std::to_string(_level));
    if (_level == 0) {
        buildCage();
        return true;
    }

    const std::vector<char> holes = holeFlags(_topology, &_warnings);
    std::vector<int> holeList;
    for (size_t f = 0; f < holes.size(); ++f)
        if (holes[f]) holeList.push_back(int(f));
    const SharpnessTags sharp = sharpnessTags(_tags, _pointCount, &_warnings);

    Far::TopologyDescriptor desc;
    desc.numVertices = int(_pointCount);
    desc.numFaces = int(_topology.faceVertexCounts.size());
    desc.numVertsPerFace = _topology.faceVertexCounts.data();
    desc.vertIndicesPerFace = _topology.faceVertexIndices.data();
    desc.numCreases = int(sharp.edgeSharpness.size());
    desc.creaseVertexIndexPairs = sharp.edgeVertices.data();
    desc.creaseWeights = sharp.edgeSharpness.data();
    desc.numCorners = int(sharp.cornerSharpness.size());
    desc.cornerVertexIndices = sharp.cornerVertices.data();
    desc.cornerWeights = sharp.cornerSharpness.data();
    desc.numHoles = int(holeList.size());
    desc.holeIndices = holeList.data();
    // OpenSubdiv reverses leftHanded faces itself, so refined faces come out right-handed.
    desc.isLeftHanded = _topology.orientation == hd::Token("leftHanded");

    std::vector<Far::TopologyDescriptor::FVarChannel> channels;
    std::vector<int> osdChannel(_fvar.size(), -1);
    for (size_t c = 0; c < _fvar.size(); ++c) {
        if (!_fvar[c].available) continue;
        osdChannel[c] = int(channels.size());
        Far::TopologyDescriptor::FVarChannel ch;
        ch.numValues = int(_options.faceVarying[c].valueCount);
        ch.valueIndices = _options.faceVarying[c].indices.data();
        channels.push_back(ch);
    }
    desc.numFVarChannels = int(channels.size());
    desc.fvarChannels = channels.data();

    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    auto clock = std::chrono::steady_clock::now();
    auto lap = [&clock](double* slot) {
        *slot = secondsSince(clock);
        clock = std::chrono::steady_clock::now();
    };
    tOsdMessage.clear();
    std::unique_ptr<Far::TopologyRefiner> refiner(
        Factory::Create(desc, Factory::Options(setup.scheme, setup.options)));
    gRefinerBuilds.fetch_add(1);
    if (!refiner) {
        *error = "OpenSubdiv rejected the topology" +
                 (tOsdMessage.empty() ? std::string() : ": " + tOsdMessage);
        return false;
    }
    if (!tOsdMessage.empty()) _warnings.push_back("OpenSubdiv: " + tOsdMessage);

    Far::TopologyRefiner::UniformOptions uniform(_level);
    uniform.fullTopologyInLastLevel = true;  // PrimvarRefiner::Limit needs vertex neighbourhoods
    memTrace("factory");
    refiner->RefineUniform(uniform);
    memTrace("refiner");
    lap(&_timings.refiner);

    // The tables only read the refiner, so they are built concurrently (TBB). Each task
    // records its own duration; a failure is caught inside its task (no exception crosses TBB).
    auto chain = [&](Interpolation mode, int channel) {
        // Per-level local tables by default; one flattened Far table as the reference path.
        if (_options.flatStencils) return StencilChain{refinementStencils(*refiner, mode, channel)};
        return levelStencils(*refiner, mode, channel);
    };
    std::mutex failureMutex;
    std::string failure;
    std::vector<double> fvarSeconds(_fvar.size(), 0.0);
    std::vector<std::function<void()>> tasks;
    auto task = [&](double* seconds, std::function<void()> work) {
        tasks.push_back([&failureMutex, &failure, seconds, work = std::move(work)] {
            const auto t0 = std::chrono::steady_clock::now();
            try {
                work();
            } catch (const std::exception& e) {
                std::lock_guard<std::mutex> lock(failureMutex);
                if (failure.empty()) failure = e.what();
            }
            *seconds = secondsSince(t0);
        });
    };
    task(&_timings.vertexStencils, [&] { _vertex = chain(Interpolation::Vertex, 0); });
    if (_options.varying)
        task(&_timings.varyingStencils, [&] { _varying = chain(Interpolation::Varying, 0); });
    if (_scheme != Scheme::Bilinear) {
        // Bilinear limit points are the refined points and its tangent masks are arbitrary
        // (Sdc calls them ambiguous), so bilinear normals come from the triangles.
        task(&_timings.limitMasks, [&] {
            LimitMasks masks = vertexLimitMasks(*refiner);
            _limitP = std::move(masks.position);
            _limitDu = std::move(masks.tangentU);
            _limitDv = std::move(masks.tangentV);
        });
    }
    for (size_t c = 0; c < _fvar.size(); ++c) {
        if (osdChannel[c] < 0) continue;
        task(&fvarSeconds[c], [&, c] {
            _fvar[c].toLevel = chain(Interpolation::FaceVarying, osdChannel[c]);
            _fvar[c].limit = faceVaryingLimitMasks(*refiner, osdChannel[c]);
            if (isIdentity(_fvar[c].limit)) _fvar[c].limit = Stencils();
        });
    }
    tbb::parallel_for(size_t(0), tasks.size(), [&tasks](size_t i) { tasks[i](); });
    memTrace("stencils");
    for (double t : fvarSeconds) _timings.faceVarying += t;
    clock = std::chrono::steady_clock::now();
    if (!failure.empty()) {
        *error = "building stencils failed: " + failure;
        return false;
    }
    if (_vertex.empty() ||
        _vertex.back().rows() != size_t(refiner->GetLevel(_level).GetNumVertices())) {
        *error = "OpenSubdiv produced no stencils" +
                 (tOsdMessage.empty() ? std::string() : ": " + tOsdMessage);
        return false;
    }

    // Coarse face of every refined face, level by level.
    std::vector<int> coarse(size_t(refiner->GetLevel(0).GetNumFaces()));
    std::iota(coarse.begin(), coarse.end(), 0);
    for (int l = 1; l <= _level; ++l) {
        const Far::TopologyLevel& lev = refiner->GetLevel(l);
        std::vector<int> next(size_t(lev.GetNumFaces()));
        for (int f = 0; f < lev.GetNumFaces(); ++f) next[f] = coarse[lev.GetFaceParentFace(f)];
        coarse.swap(next);
    }

    // Triangles: refined quads split along their 0-2 diagonal, loop triangles as they are.
    // Base-level hole tags include the faces OpenSubdiv itself turns into holes
    // (interpolateBoundary "none" makes boundary faces holes).
    const Far::TopologyLevel& base = refiner->GetLevel(0);
    const Far::TopologyLevel& last = refiner->GetLevel(_level);
    _refinedPoints = size_t(last.GetNumVertices());
    // Exact sizes first: growing by push_back would copy (and fault in) these arrays several
    // times and leave up to half of each allocation unused.
    size_t triangleCount = 0;
    for (int f = 0; f < last.GetNumFaces(); ++f)
        if (!base.IsFaceHole(coarse[f])) triangleCount += size_t(last.GetFaceVertices(f).size() - 2);
    _triangles.reserve(triangleCount);
    _triangleFace.reserve(triangleCount);
    for (size_t c = 0; c < _fvar.size(); ++c)
        if (osdChannel[c] >= 0) _fvar[c].corners->reserve(3 * triangleCount);
    for (int f = 0; f < last.GetNumFaces(); ++f) {
        if (base.IsFaceHole(coarse[f])) continue;
        Far::ConstIndexArray fv = last.GetFaceVertices(f);
        for (int k = 1; k + 1 < fv.size(); ++k) {
            _triangles.emplace_back(fv[0], fv[k], fv[k + 1]);
            _triangleFace.push_back(coarse[f]);
        }
        for (size_t c = 0; c < _fvar.size(); ++c) {
            if (osdChannel[c] < 0) continue;
            Far::ConstIndexArray vals = last.GetFaceFVarValues(f, osdChannel[c]);
            for (int k = 1; k + 1 < vals.size(); ++k) {
                _fvar[c].corners->push_back(vals[0]);
                _fvar[c].corners->push_back(vals[k]);
                _fvar[c].corners->push_back(vals[k + 1]);
            }
        }
    }
    if (_limitP.rows() && isIdentity(_limitP)) _limitP = Stencils();
    lap(&_timings.triangles);
    memTrace("triangles");
    return true;  // the refiner is released here: only stencils are kept
}

bool SubdivTopology::matches(const hd::MeshTopology& t, const hd::SubdivTags& g, size_t pointCount,
                             const BuildOptions& options) const {
    const auto& a = _topology;
    const auto& b = _tags;
    return pointCount == _pointCount && options == _options && t.scheme == a.scheme &&
           t.orientation == a.orientation && t.faceVertexCounts == a.faceVertexCounts &&
           t.faceVertexIndices == a.faceVertexIndices && t.holeIndices == a.holeIndices &&
           g.interpolateBoundary == b.interpolateBoundary &&
           g.faceVaryingLinearInterpolation == b.faceVaryingLinearInterpolation &&
           g.triangleSubdivisionRule == b.triangleSubdivisionRule &&
           g.creaseIndices == b.creaseIndices && g.creaseLengths == b.creaseLengths &&
           g.creaseSharpnesses == b.creaseSharpnesses && g.cornerIndices == b.cornerIndices &&
           g.cornerSharpnesses == b.cornerSharpnesses;
}

bool SubdivTopology::faceVaryingAvailable(int channel) const {
    return channel >= 0 && size_t(channel) < _fvar.size() && _fvar[channel].available;
}

size_t SubdivTopology::memoryBytes() const {
    auto chainBytes = [](const StencilChain& c) {
        size_t b = 0;
        for (const Stencils& s : c) b += s.bytes();
        return b;
    };
    size_t bytes = chainBytes(_vertex) + chainBytes(_varying) + _limitP.bytes() + _limitDu.bytes() +
                   _limitDv.bytes() + _triangles.size() * sizeof(glm::uvec3) +
                   _triangleFace.size() * sizeof(int);
    for (const auto& f : _fvar)
        bytes += chainBytes(f.toLevel) + f.limit.bytes() + f.corners->size() * sizeof(int);
    return bytes;
}

std::string SubdivTopology::describe() const {
    static const char* kNames[] = {"none", "catmullClark", "loop", "bilinear"};
    auto table = [](const char* name, const Stencils& st) {
        if (st.empty()) return std::string();
        char buf[96];
        std::snprintf(buf, sizeof buf, " %s %zux%.1f", name, st.rows(),
                      double(st.entries()) / double(st.rows()));
        return std::string(buf);
    };
    // A chain prints as its last table's rows x (all entries / those rows), then its length.
    auto chain = [](const char* name, const StencilChain& c) {
        if (c.empty()) return std::string();
        size_t entries = 0;
        for (const Stencils& st : c) entries += st.entries();
        char buf[96];
        std::snprintf(buf, sizeof buf, " %s %zux%.1f(%zu tables)", name, c.back().rows(),
                      double(entries) / double(c.back().rows()), c.size());
        return std::string(buf);
    };
    std::string s = std::string(kNames[int(_scheme)]) + " level " + std::to_string(_level) + ": " +
                    std::to_string(_triangles.size()) + " triangles, " +
                    std::to_string(_refinedPoints) +
                    " points; stencils (rows x entries/row):" + chain("vertex", _vertex) +
                    chain("varying", _varying) + table("limitP", _limitP) +
                    table("limitDu", _limitDu) + table("limitDv", _limitDv);
    for (size_t c = 0; c < _fvar.size(); ++c)
        s += chain(("fvar" + std::to_string(c)).c_str(), _fvar[c].toLevel) +
             table(("fvarLimit" + std::to_string(c)).c_str(), _fvar[c].limit);
    return s;
}

bool SubdivTopology::refine(const std::vector<glm::vec3>& coarsePoints, RefinedMesh* out,
                            std::string* error) const {
    if (coarsePoints.size() != _pointCount) {
        if (error)
            *error = "refine: " + std::to_string(coarsePoints.size()) +
                     " points given, topology has " + std::to_string(_pointCount);
        return false;
    }
    if (out->topologyId != _id) {
        out->triangles = _triangles;
        out->triangleFace = _triangleFace;
        out->topologyId = _id;
    }
    if (!subdivided()) {
        out->points = coarsePoints;
        out->normals.clear();
        return true;
    }
    // Last-level points in a per-thread scratch buffer: re-posing reuses its pages instead of
    // faulting in a fresh allocation every frame.
    thread_local std::vector<glm::vec3> levelPoints;
    levelPoints.resize(_refinedPoints);
    applyChain(_vertex, reinterpret_cast<const float*>(coarsePoints.data()), _pointCount, 3,
               reinterpret_cast<float*>(levelPoints.data()));
    out->points.resize(_refinedPoints);
    out->normals.resize(_refinedPoints);
    if (_limitP.empty()) std::copy(levelPoints.begin(), levelPoints.end(), out->points.begin());
    computeLimit(levelPoints, out);
    return true;
}

void SubdivTopology::computeLimit(const std::vector<glm::vec3>& levelPoints,
                                  RefinedMesh* out) const {
    const size_t n = _refinedPoints;
    // Per-thread scratch; the lambdas below run on TBB workers, so they must use this
    // reference and never name the thread_local itself.
    thread_local std::vector<char> fallbackScratch;
    std::vector<char>& fallback = fallbackScratch;
    fallback.assign(n, 1);
    auto row = [&levelPoints](const Stencils& s, size_t r) {
        glm::vec3 acc(0.0f);
        for (int k = s.offsets[r]; k < s.offsets[r + 1]; ++k)
            acc += s.weights[k] * levelPoints[size_t(s.indices[k])];
        return acc;
    };
    const bool tangents = !_limitDu.empty();
    const bool limit = !_limitP.empty();
    if (tangents || limit) {
        // One pass per point: limit position and both tangents.
        parallelRange(n, [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) {
                if (limit) out->points[i] = row(_limitP, i);
                if (!tangents) continue;
                const glm::vec3 du = row(_limitDu, i), dv = row(_limitDv, i);
                // Normal from limit tangents: N = normalize(dP/du x dP/dv) (Far tutorial 2_3).
                const glm::vec3 c = glm::cross(du, dv);
                const float len2 = glm::dot(c, c);
                // 1e-12: relative to |du|^2 |dv|^2, i.e. tangents within ~1e-6 rad of parallel
                // (or vanishing) give no usable normal.
                const float ref = glm::dot(du, du) * glm::dot(dv, dv);
                if (len2 > 1e-12f * ref && len2 > 0.0f) {
                    out->normals[i] = c / std::sqrt(len2);
                    fallback[i] = 0;
                }
            }
        });
    }
    if (std::find(fallback.begin(), fallback.end(), 1) == fallback.end()) return;
    // Area-weighted face normals for points without usable tangents (bilinear, degenerate).
    std::vector<glm::vec3> acc(n, glm::vec3(0.0f));
    const auto& p = out->points;
    for (const glm::uvec3& t : _triangles) {
        if (!fallback[t.x] && !fallback[t.y] && !fallback[t.z]) continue;
        glm::vec3 fn = glm::cross(p[t.y] - p[t.x], p[t.z] - p[t.x]);
        for (int k = 0; k < 3; ++k)
            if (fallback[t[k]]) acc[t[k]] += fn;
    }
    for (size_t i = 0; i < n; ++i) {
        if (!fallback[i]) continue;
        float len = glm::length(acc[i]);
        out->normals[i] = len > 0.0f ? acc[i] / len : glm::vec3(0.0f, 0.0f, 1.0f);
    }
}

}  // namespace principled::subdiv
