// SPDX-License-Identifier: Apache-2.0
#include "delegate/subdiv/stencils.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <utility>

namespace principled::subdiv {

namespace {

// 4096 rows per task: large enough that scheduling is noise, small enough to balance 2+ cores.
constexpr size_t kRowsPerTask = 4096;

template <int N>
void applyFixed(const Stencils& s, const float* src, float* dst, size_t begin, size_t end) {
    for (size_t r = begin; r < end; ++r) {
        float acc[N] = {};
        for (int k = s.offsets[r]; k < s.offsets[r + 1]; ++k) {
            const float w = s.weights[k];
            const float* v = src + static_cast<size_t>(s.indices[k]) * N;
            for (int c = 0; c < N; ++c) acc[c] += w * v[c];
        }
        for (int c = 0; c < N; ++c) dst[r * N + c] = acc[c];
    }
}

void applyAny(const Stencils& s, const float* src, int n, float* dst, size_t begin, size_t end) {
    for (size_t r = begin; r < end; ++r) {
        float* out = dst + r * static_cast<size_t>(n);
        std::fill(out, out + n, 0.0f);
        for (int k = s.offsets[r]; k < s.offsets[r + 1]; ++k) {
            const float w = s.weights[k];
            const float* v = src + static_cast<size_t>(s.indices[k]) * static_cast<size_t>(n);
            for (int c = 0; c < n; ++c) out[c] += w * v[c];
        }
    }
}

}  // namespace

size_t Stencils::bytes() const {
    return offsets.size() * sizeof(int) + indices.size() * sizeof(int) +
           weights.size() * sizeof(float);
}

size_t Stencils::sourceCount() const {
    int maxIndex = -1;
    for (int i : indices) maxIndex = std::max(maxIndex, i);
    return static_cast<size_t>(maxIndex + 1);
}

void Stencils::apply(const float* src, int components, float* dst) const {
    auto range = [&](size_t begin, size_t end) {
        switch (components) {
            case 1:
                applyFixed<1>(*this, src, dst, begin, end);
                break;
            case 2:
                applyFixed<2>(*this, src, dst, begin, end);
                break;
            case 3:
                applyFixed<3>(*this, src, dst, begin, end);
                break;
            case 4:
                applyFixed<4>(*this, src, dst, begin, end);
                break;
            default:
                applyAny(*this, src, components, dst, begin, end);
                break;
        }
    };
    const size_t n = rows();
    if (n <= kRowsPerTask) {
        range(0, n);
        return;
    }
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, kRowsPerTask),
                      [&](const tbb::blocked_range<size_t>& r) { range(r.begin(), r.end()); });
}

void applyChain(const std::vector<Stencils>& chain, const float* src, size_t count, int components,
                float* dst) {
    const size_t n = size_t(components);
    if (chain.empty()) {
        std::copy(src, src + count * n, dst);
        return;
    }
    // Ping-pong between two per-thread buffers; the last table writes into dst.
    thread_local std::vector<float> scratch[2];
    const float* in = src;
    for (size_t k = 0; k < chain.size(); ++k) {
        float* out = dst;
        if (k + 1 < chain.size()) {
            std::vector<float>& buffer = scratch[k % 2];
            buffer.resize(chain[k].rows() * n);
            out = buffer.data();
        }
        chain[k].apply(in, components, out);
        in = out;
    }
}

void StencilsBuilder::add(int index, float weight) {
    _table.indices.push_back(index);
    _table.weights.push_back(weight);
}

void StencilsBuilder::endRow() {
    const size_t begin = static_cast<size_t>(_table.offsets.back());
    const size_t end = _table.indices.size();
    int* idx = _table.indices.data();
    float* wgt = _table.weights.data();
    // Sort the row by index so duplicates (a vertex reached through two mask slots) merge.
    // Rows hold a few dozen weights at most: insertion sort in place.
    for (size_t i = begin + 1; i < end; ++i) {
        const int key = idx[i];
        const float w = wgt[i];
        size_t j = i;
        for (; j > begin && idx[j - 1] > key; --j) {
            idx[j] = idx[j - 1];
            wgt[j] = wgt[j - 1];
        }
        idx[j] = key;
        wgt[j] = w;
    }
    // Merge duplicates, then drop weights that are exactly zero (tangent masks pad with zeros).
    size_t out = begin;
    for (size_t k = begin; k < end;) {
        const int key = idx[k];
        float w = 0.0f;
        for (; k < end && idx[k] == key; ++k) w += wgt[k];
        if (w == 0.0f) continue;
        idx[out] = key;
        wgt[out] = w;
        ++out;
    }
    _table.indices.resize(out);
    _table.weights.resize(out);
    _table.offsets.push_back(static_cast<int>(out));
    _open = false;
}

Stencils StencilsBuilder::finish() {
    if (_open) endRow();
    Stencils out = std::move(_table);
    _table = Stencils();
    return out;
}

}  // namespace principled::subdiv
