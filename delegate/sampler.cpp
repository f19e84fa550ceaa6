// SPDX-License-Identifier: Apache-2.0
#include "delegate/sampler.h"

#include <array>

namespace principled::embree {
namespace {

// Direction numbers v[k] (left-aligned in 32 bits) for Sobol dimensions 2..4 from primitive
// polynomials x+1, x^2+x+1, x^3+x+1 with initial m = {1}, {1,3}, {1,3,1} (Joe & Kuo 2008,
// new-joe-kuo-6.21201, first lines); v[k] = m[k] / 2^(k+1) and the recurrence of Bratley & Fox 1988.
using Directions = std::array<std::array<uint32_t, 32>, 4>;

constexpr Directions directions() {
    Directions v{};
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
    return v;
}

// Sobol points are XORs of direction numbers selected by the index bits, so each byte of the
// index contributes independently: four 256-entry tables per dimension replace the 32-step
// bit loop (scrambled indices use all 32 bits). 16 KiB per set, computed by the compiler (no
// start-up cost, no guard on the hot path). contribution(v, bit) is what index bit `bit`
// adds, given the dimension's direction numbers v.
template <typename Contribution>
constexpr detail::SobolByteTables byteTables(Contribution contribution) {
    const Directions d = directions();
    detail::SobolByteTables out{};
    for (int dim = 0; dim < 4; ++dim)
        for (int byte = 0; byte < 4; ++byte)
            for (uint32_t b = 0; b < 256; ++b) {
                uint32_t x = 0;
                for (int k = 0; k < 8; ++k)
                    if (b & (1u << k)) x ^= contribution(d[dim], byte * 8 + k);
                out[dim][byte][b] = x;
            }
    return out;
}

constexpr uint32_t reverse(uint32_t x) {
    uint32_t r = 0;
    for (int k = 0; k < 32; ++k) r |= ((x >> k) & 1u) << (31 - k);
    return r;
}

}  // namespace

// Bit m of a reversed index stands for bit 31 - m of the index, which selects direction number
// 31 - m; reversing that direction number gives the reversed point's contribution.
constexpr detail::SobolByteTables detail::kSobolReversedByteTables =
    byteTables([](const std::array<uint32_t, 32>& v, int bit) { return reverse(v[31 - bit]); });

constexpr std::array<uint8_t, 256> detail::kReversedBytes = [] {
    std::array<uint8_t, 256> t{};
    for (uint32_t b = 0; b < 256; ++b) t[b] = uint8_t(reverse(b) >> 24);
    return t;
}();

// External linkage from the declaration in sampler.h.
constexpr detail::SobolByteTables detail::kSobolByteTables =
    byteTables([](const std::array<uint32_t, 32>& v, int bit) { return v[bit]; });

}  // namespace principled::embree
