#include "delegate/sampler.h"

#include <gtest/gtest.h>

#include <set>
#include <vector>

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

TEST(Sampler, EveryTwoDimensionalDecisionIsAZeroMTwoNet) {
    // The integrator's pattern: camera jitter (2-D), then per bounce a light sample (2-D + pick)
    // and a BSDF sample (2-D + lobe + roulette). Every 2-D pair, at any bounce, must be a
    // (0,m,2)-net: a pair that straddled two Sobol groups (before the acc branch) loses the 2-D
    // stratification and fails this.
    const int m = 6, n = 1 << m;
    const int kPairs = 7;  // camera + 3 bounces x (light, BSDF)
    for (uint32_t seed : {0u, 5u}) {
        std::vector<std::vector<glm::vec2>> pairs(kPairs);
        for (int i = 0; i < n; ++i) {
            Sampler s(SamplerKind::Sobol, seed, 123, uint32_t(i));
            pairs[0].push_back(s.next2D());
            for (int b = 0; b < 3; ++b) {
                pairs[1 + 2 * b].push_back(s.next2D());
                s.next1D();  // light pick
                pairs[2 + 2 * b].push_back(s.next2D());
                s.next1D();  // lobe
                s.next1D();  // roulette
            }
        }
        for (int k = 0; k < kPairs; ++k)
            for (int split = 0; split <= m; ++split) {
                int nx = 1 << split, ny = 1 << (m - split);
                std::set<int> cells;
                for (const glm::vec2& u : pairs[k]) cells.insert(int(u.x * nx) * ny + int(u.y * ny));
                EXPECT_EQ(int(cells.size()), n) << "pair " << k << " split " << split << " seed " << seed;
            }
    }
}

TEST(Sampler, ReversedDomainTablesMatchTheSobolPoints) {
    // sobol4Reversed works on reversed indices and returns reversed points: it must agree with
    // the plain tables bit for bit (every byte of the index matters once it is scrambled).
    uint32_t x = 0x12345678u;
    for (int i = 0; i < 20000; ++i) {
        x = hashMix(x + uint32_t(i));
        for (int d = 0; d < 4; ++d)
            ASSERT_EQ(sobol4Reversed(detail::reverseBits(x), d), detail::reverseBits(sobol4(x, d)))
                << "index " << x << " dimension " << d;
    }
}

TEST(Sampler, ValuesFollowTheScrambledSobolDefinition) {
    // The sampler computes in the bit-reversed domain; its values must equal the definition:
    // group g of four dimensions shuffles the index with owenScramble(index, seed_g) and
    // scrambles dimension d of that point with its own seed (Burley 2020, sections 3-4).
    for (uint32_t seed : {0u, 9u}) {
        for (uint32_t pixel : {0u, 1234u}) {
            for (uint32_t index : {0u, 1u, 7u, 1000u, 65537u}) {
                Sampler s(SamplerKind::Sobol, seed, pixel, index);
                uint32_t pixelKey = hashCombine(hashMix(seed ^ 0x5bd1e995u), pixel);
                for (uint32_t d = 0; d < 12; ++d) {
                    uint32_t groupSeed = hashCombine(pixelKey, d >> 2);
                    uint32_t shuffled = owenScramble(index, groupSeed);
                    uint32_t v = owenScramble(sobol4(shuffled, int(d & 3u)), hashCombine(groupSeed, (d & 3u) + 1u));
                    float expected = float(v >> 8) * 0x1p-24f;
                    ASSERT_EQ(s.next1D(), expected) << "dimension " << d;
                }
            }
        }
    }
}

TEST(Sampler, TopBitsOfTheReversalComeFromTheLowBytes) {
    // reverseBitsTop24 (three byte-table lookups) is the 24 bits reverseBits keeps for a float.
    uint32_t x = 0x9e3779b9u;
    for (int i = 0; i < 100000; ++i) {
        x = hashMix(x + uint32_t(i));
        ASSERT_EQ(detail::reverseBitsTop24(x), detail::reverseBits(x) >> 8) << x;
    }
    for (uint32_t b : {0u, 1u, 0x80u, 0xffu, 0xffffffu, 0x1000000u, 0xffffffffu})
        ASSERT_EQ(detail::reverseBitsTop24(b), detail::reverseBits(b) >> 8) << b;
}
