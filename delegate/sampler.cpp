// SPDX-License-Identifier: Apache-2.0
#include "delegate/sampler.h"

#include <array>

namespace principled::embree {
namespace {

uint32_t reverseBits(uint32_t x) {
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
    x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
    return (x >> 16) | (x << 16);
}

// Direction numbers v[k] (left-aligned in 32 bits) for Sobol dimensions 2..4 from primitive
// polynomials x+1, x^2+x+1, x^3+x+1 with initial m = {1}, {1,3}, {1,3,1} (Joe & Kuo 2008,
// new-joe-kuo-6.21201, first lines); v[k] = m[k] / 2^(k+1) and the recurrence of Bratley & Fox 1988.
struct Directions {
    std::array<std::array<uint32_t, 32>, 4> v{};
    Directions() {
        for (int k = 0; k < 32; ++k) v[0][k] = 1u << (31 - k);
        struct Poly {
            int degree;
            uint32_t a;  // inner coefficients, highest first
            std::array<uint32_t, 3> m;
        };
        const Poly polys[3] = {{1, 0, {1, 0, 0}}, {2, 1, {1, 3, 0}}, {3, 1, {1, 3, 1}}};
        for (int d = 1; d < 4; ++d) {
            const Poly& p = polys[d - 1];
            int s = p.degree;
            for (int k = 0; k < s; ++k) v[d][k] = p.m[k] << (31 - k);
            for (int k = s; k < 32; ++k) {
                uint32_t x = v[d][k - s] ^ (v[d][k - s] >> s);
                for (int j = 1; j < s; ++j)
                    if ((p.a >> (s - 1 - j)) & 1u) x ^= v[d][k - j];
                v[d][k] = x;
            }
        }
    }
};

const Directions& directions() {
    static const Directions d;
    return d;
}

}  // namespace

uint32_t sobol4(uint32_t index, int dimension) {
    const auto& v = directions().v[dimension & 3];
    uint32_t x = 0;
    for (int k = 0; index; index >>= 1, ++k)
        if (index & 1u) x ^= v[k];
    return x;
}

uint32_t owenScramble(uint32_t x, uint32_t seed) {
    // Burley 2020, JCGT 9(4), listing 3 constants for the Laine-Karras permutation.
    x = reverseBits(x);
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return reverseBits(x);
}

uint32_t Sampler::value(uint32_t d) const {
    if (_kind == SamplerKind::Independent)
        return hashCombine(hashCombine(_pixelKey, _index), d * 0x85ebca6bu + 1u);
    // Burley 2020 section 4: dimensions come in groups of four Owen-scrambled Sobol dimensions;
    // each group shuffles the sample order per pixel (scrambling the index) with its own seed,
    // which decorrelates the groups ("padding").
    uint32_t group = d >> 2;
    uint32_t groupSeed = hashCombine(_pixelKey, group);
    uint32_t shuffled = owenScramble(_index, groupSeed);
    return owenScramble(sobol4(shuffled, int(d & 3u)), hashCombine(groupSeed, (d & 3u) + 1u));
}

}  // namespace principled::embree
