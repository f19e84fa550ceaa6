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

// Sobol points are XORs of direction numbers selected by the index bits, so each byte of the
// index contributes independently: four 256-entry tables per dimension replace the 32-step
// bit loop (scrambled indices use all 32 bits). 16 KiB in all.
struct ByteTables {
    std::array<std::array<std::array<uint32_t, 256>, 4>, 4> t{};
    ByteTables() {
        Directions d;
        for (int dim = 0; dim < 4; ++dim)
            for (int byte = 0; byte < 4; ++byte)
                for (uint32_t b = 0; b < 256; ++b) {
                    uint32_t x = 0;
                    for (int k = 0; k < 8; ++k)
                        if (b & (1u << k)) x ^= d.v[dim][byte * 8 + k];
                    t[dim][byte][b] = x;
                }
    }
};

const ByteTables kTables;  // built at load time: no guard on the hot path

}  // namespace

uint32_t sobol4(uint32_t index, int dimension) {
    const auto& t = kTables.t[dimension & 3];
    return t[0][index & 0xffu] ^ t[1][(index >> 8) & 0xffu] ^ t[2][(index >> 16) & 0xffu] ^
           t[3][index >> 24];
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
