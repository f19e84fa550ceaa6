// SPDX-License-Identifier: Apache-2.0
// parallelRange: TBB parallel loop over [0, n) in fixed chunks, serial for small n.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstddef>

namespace principled::subdiv {

/// Calls f(begin, end) over chunks of [0, n). 8192 elements per task: large enough that
/// scheduling is noise next to the per-element work, small enough to balance 2+ cores.
template <typename F>
void parallelRange(size_t n, F&& f) {
    constexpr size_t kChunk = 8192;
    if (n <= kChunk) {
        f(size_t(0), n);
        return;
    }
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, kChunk),
                      [&](const tbb::blocked_range<size_t>& r) { f(r.begin(), r.end()); });
}

}  // namespace principled::subdiv
