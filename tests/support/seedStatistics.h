// SPDX-License-Identifier: Apache-2.0
// seedStatistics: how two estimators of the same image are compared in tests: render with
// several independent seeds, then the mean over seeds, its standard error, and the mean
// per-pixel variance across seeds (the noise each estimator leaves).
#pragma once

#include <cmath>
#include <functional>
#include <vector>

namespace principled::test {

struct SeedStats {
    double mean = 0.0;      ///< image mean, averaged over seeds
    double se = 0.0;        ///< standard error of that mean
    double pixelVar = 0.0;  ///< per-pixel variance across seeds, averaged over pixels
};

/// Renders `seeds` images with seeds firstSeed, firstSeed + 1, ... (each a channel's pixels).
inline SeedStats seedStatistics(const std::function<std::vector<float>(int seed)>& render, int firstSeed,
                                int seeds = 6) {
    std::vector<std::vector<float>> imgs;
    std::vector<double> means;
    for (int s = 0; s < seeds; ++s) {
        imgs.push_back(render(firstSeed + s));
        double m = 0.0;
        for (float v : imgs.back()) m += v;
        means.push_back(m / imgs.back().size());
    }
    SeedStats st;
    for (double m : means) st.mean += m / seeds;
    double v = 0.0;
    for (double m : means) v += (m - st.mean) * (m - st.mean) / (seeds - 1);
    st.se = std::sqrt(v / seeds);
    for (size_t i = 0; i < imgs[0].size(); ++i) {
        double mu = 0.0, q = 0.0;
        for (auto& im : imgs) mu += im[i] / seeds;
        for (auto& im : imgs) q += (im[i] - mu) * (im[i] - mu) / (seeds - 1);
        st.pixelVar += q / imgs[0].size();
    }
    return st;
}

}  // namespace principled::test
