// SPDX-License-Identifier: Apache-2.0
// PixelStats: a progressive render's per-pixel statistics and pass state, everything a render
// of a sample range leaves behind besides its AOV sums (for merging ranges and for --resume).
#pragma once

#include <cstdint>
#include <vector>

#include "delegate/causticBudget.h"

namespace principled::embree {

struct PixelStats {
    /// Per-pixel luminance sum, sum of squares and sample count, behind the variance AOV and
    /// adaptive sampling.
    std::vector<double> lumSum, lumSqSum;
    std::vector<int> samples;
    /// The light-traced share's statistics (EmbreeRenderPass::_ltSum...); empty without light
    /// paths. All sums: ranges merge by adding them.
    std::vector<double> ltSum, ltN1, ltN2;
    double ltPaths = 0.0, ltSpread = 0.0;
    int ltPasses = 0;
    /// Where the light paths' sequence and budget stand (a resumed render continues them; a
    /// merge of ranges keeps the first's).
    uint64_t causticPaths = 0;
    CausticBudget::State budget;
    /// Passes run (their batch sizes follow it; light paths and photons go per pass); 0: unknown.
    int passes = 0;
};

}  // namespace principled::embree
