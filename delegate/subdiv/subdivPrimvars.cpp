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
    // coarse values -> last-level values -> limit values, then gathered per triangle corner.
    // Per-thread scratch: repeated calls reuse the pages (the gather below reads it through a
    // plain pointer, so TBB workers never name the thread_local).
    thread_local std::vector<float> limitValues;
    if (!refineFaceVaryingValues(channel, values, count, components, &limitValues, error))
        return false;
    const size_t n = size_t(components);
    const std::vector<int>& cornerList = *_fvar[size_t(channel)].corners;
    out->resize(cornerList.size() * n);
    float* dst = out->data();
    const float* src = limitValues.data();
    const int* corners = cornerList.data();
    parallelRange(cornerList.size(), [=](size_t begin, size_t end) {
        for (size_t k = begin; k < end; ++k)
            std::copy_n(src + size_t(corners[k]) * n, n, dst + k * n);
    });
    return true;
}

bool SubdivTopology::refineFaceVaryingValues(int channel, const float* values, size_t count,
                                             int components, std::vector<float>* out,
                                             std::string* error) const {
    if (!faceVaryingAvailable(channel))
        return fail(error, "face-varying channel " + std::to_string(channel) + " is not available");
    const FaceVaryingTables& fv = _fvar[size_t(channel)];
    if (!checkInput(values, count, fv.coarseValues, components, "face-varying primvar", error))
        return false;
    const size_t n = size_t(components);
    // coarse values -> last-level values -> limit values (either step may be the identity).
    if (fv.toLevel.empty() && fv.limit.empty()) {
        out->assign(values, values + count * n);
        return true;
    }
    if (fv.limit.empty()) {
        out->resize(chainRows(fv.toLevel, count) * n);
        applyChain(fv.toLevel, values, count, components, out->data());
        return true;
    }
    const float* src = values;
    thread_local std::vector<float> level;  // per-thread scratch, as in refine()
    if (!fv.toLevel.empty()) {
        level.resize(chainRows(fv.toLevel, count) * n);
        applyChain(fv.toLevel, values, count, components, level.data());
        src = level.data();
    }
    out->resize(fv.limit.rows() * n);
    fv.limit.apply(src, components, out->data());
    return true;
}

std::shared_ptr<const std::vector<int>> SubdivTopology::faceVaryingCorners(int channel) const {
    if (!faceVaryingAvailable(channel)) return nullptr;
    return _fvar[size_t(channel)].corners;
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
