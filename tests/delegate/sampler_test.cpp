#include "delegate/sampler.h"

#include <gtest/gtest.h>

#include <set>

using namespace principled::embree;

TEST(Sampler, SobolFirstTwoDimensionsAreAZeroMTwoNet) {
    // Any 2^m consecutive-from-zero Sobol points in dimensions (0,1) put exactly one point in
    // each elementary interval of area 2^-m; Owen scrambling preserves this (Owen 1995).
    for (uint32_t seed : {0u, 1u, 12345u}) {
        const int m = 8, n = 1 << m;
        for (int split = 0; split <= m; ++split) {
            int nx = 1 << split, ny = 1 << (m - split);
            std::set<int> cells;
            for (int i = 0; i < n; ++i) {
                Sampler s(SamplerKind::Sobol, seed, 77, uint32_t(i));
                glm::vec2 u = s.next2D();
                ASSERT_GE(u.x, 0.0f);
                ASSERT_LT(u.x, 1.0f);
                cells.insert(int(u.x * nx) * ny + int(u.y * ny));
            }
            EXPECT_EQ(int(cells.size()), n) << "seed " << seed << " split " << split;
        }
    }
}

TEST(Sampler, ValuesDependOnlyOnTheirAddress) {
    Sampler a(SamplerKind::Sobol, 3, 10, 5), b(SamplerKind::Sobol, 3, 10, 5), c(SamplerKind::Sobol, 4, 10, 5);
    for (int d = 0; d < 40; ++d) {
        float va = a.next1D(), vb = b.next1D(), vc = c.next1D();
        EXPECT_EQ(va, vb);
        if (d < 4) {
            EXPECT_NE(va, vc);
        }
    }
}

TEST(Sampler, IndependentAndHigherDimensionsAreUniform) {
    // Mean and variance of 4096 samples in dimensions 0, 5 and 37 for both kinds.
    for (SamplerKind k : {SamplerKind::Sobol, SamplerKind::Independent})
        for (int dim : {0, 5, 37}) {
            double sum = 0.0, sq = 0.0;
            const int n = 4096;
            for (int i = 0; i < n; ++i) {
                Sampler s(k, 9, 1234, uint32_t(i));
                float v = 0.0f;
                for (int d = 0; d <= dim; ++d) v = s.next1D();
                sum += v;
                sq += double(v) * v;
            }
            double mean = sum / n, var = sq / n - mean * mean;
            EXPECT_NEAR(mean, 0.5, 0.02) << int(k) << " dim " << dim;
            EXPECT_NEAR(var, 1.0 / 12.0, 0.01);
        }
}
