// SPDX-License-Identifier: Apache-2.0
// SubdivTopology primvar refinement: vertex, varying, face-varying and uniform interpolation.
#include <algorithm>

#include "delegate/subdiv/parallelRange.h"
#include "delegate/subdiv/subdivTopology.h"

namespace principled::subdiv {

namespace {

bool fail(std::string* error, std::string message) {
    if (error) *error = std::move(message);
    return false;
}

bool checkInput(const float* values, size_t count, size_t expected, int components,
                const char* what, std::string* error) {
    if (components < 1) return fail(error, std::string(what) + ": components must be >= 1");
    if (count != expected)
        return fail(error, std::string(what) + ": " + std::to_string(count) +
                               " elements given, expected " + std::to_string(expected));
    if (count > 0 && !values) return fail(error, std::string(what) + ": no values");
    return true;
}

}  // namespace

bool SubdivTopology::refineVertex(const float* values, size_t count, int components,
                                  std::vector<float>* out, std::string* error) const {
    if (!checkInput(values, count, _pointCount, components, "vertex primvar", error)) return false;
    const size_t n = size_t(components);
    if (!subdivided()) {
        out->assign(values, values + count * n);
        return true;
    }
    // Same stencils as the points, so the primvar sits at the limit like its point.
    std::vector<float> level(_refinedPoints * n);
    applyChain(_vertex, values, count, components, level.data());
    if (_limitP.empty()) {
        *out = std::move(level);
    } else {
        out->resize(_refinedPoints * n);
        _limitP.apply(level.data(), components, out->data());
    }
    return true;
}

bool SubdivTopology::refineVarying(const float* values, size_t count, int components,
                                   std::vector<float>* out, std::string* error) const {
    if (!checkInput(values, count, _pointCount, components, "varying primvar", error)) return false;
    const size_t n = size_t(components);
    if (!subdivided()) {
        out->assign(values, values + count * n);
        return true;
    }
    if (_varying.empty())
        return fail(error, "varying primvar: stencils not built (BuildOptions::varying)");
    out->resize(_refinedPoints * n);
    applyChain(_varying, values, count, components, out->data());
    return true;
}

bool SubdivTopology::refineFaceVarying(int channel, const float* values, size_t count,
                                       int components, std::vector<float>* out,
                                       std::string* error) const {
    if (!faceVaryingAvailable(channel))
        return fail(error, "face-varying channel " + std::to_string(channel) + " is not available");
    const FaceVaryingTables& fv = _fvar[size_t(channel)];
    if (!checkInput(values, count, fv.coarseValues, components, "face-varying primvar", error))
        return false;
    const size_t n = size_t(components);
    // coarse values -> last-level values -> limit values, then gathered per triangle corner.
    // Per-thread scratch: repeated calls reuse the pages (the gather below reads them through
    // plain pointers, so TBB workers never name these thread_locals).
    thread_local std::vector<float> level, limit;
    const float* src = values;
    if (!fv.toLevel.empty()) {
        level.resize(chainRows(fv.toLevel, count) * n);
        applyChain(fv.toLevel, values, count, components, level.data());
        src = level.data();
    }
    if (!fv.limit.empty()) {
        limit.resize(fv.limit.rows() * n);
        fv.limit.apply(src, components, limit.data());
        src = limit.data();
    }
    out->resize(fv.corners.size() * n);
    float* dst = out->data();
    const int* corners = fv.corners.data();
    parallelRange(fv.corners.size(), [=](size_t begin, size_t end) {
        for (size_t k = begin; k < end; ++k)
            std::copy_n(src + size_t(corners[k]) * n, n, dst + k * n);
    });
    return true;
}

bool SubdivTopology::refineUniform(const float* values, size_t count, int components,
                                   std::vector<float>* out, std::string* error) const {
    if (!checkInput(values, count, coarseFaceCount(), components, "uniform primvar", error))
        return false;
    const size_t n = size_t(components);
    out->resize(_triangleFace.size() * n);
    float* dst = out->data();
    const int* faces = _triangleFace.data();
    parallelRange(_triangleFace.size(), [=](size_t begin, size_t end) {
        for (size_t k = begin; k < end; ++k)
            std::copy_n(values + size_t(faces[k]) * n, n, dst + k * n);
    });
    return true;
}

}  // namespace principled::subdiv
