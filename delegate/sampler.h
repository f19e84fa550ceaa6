// SPDX-License-Identifier: Apache-2.0
// Sampler: deterministic sample values addressed by (seed, pixel, sample index, dimension), so
// an image does not depend on thread count, tile order or how sample ranges are split across
// processes. Two kinds: Owen-scrambled Sobol (default) and independent random (baseline).
#pragma once

#include <array>
#include <cstdint>

#include <glm/glm.hpp>

namespace principled::embree {

enum class SamplerKind : uint8_t { Sobol, Independent };

/// Stateless hash mixing (Wellons 2018, "Prospecting for Hash Functions", lowbias32).
inline uint32_t hashMix(uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}
inline uint32_t hashCombine(uint32_t a, uint32_t b) { return hashMix(a ^ (b + 0x9e3779b9u + (a << 6) + (a >> 2))); }

namespace detail {
/// Sobol dimensions 1-4 as XORs of direction numbers, one 256-entry table per index byte
/// (built at compile time in sampler.cpp).
using SobolByteTables = std::array<std::array<std::array<uint32_t, 256>, 4>, 4>;
extern const SobolByteTables kSobolByteTables;

/// Bit reversal: a byte swap, then the bits of each byte reversed.
inline uint32_t reverseBits(uint32_t x) {
    x = __builtin_bswap32(x);
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    return ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
}
}  // namespace detail

/// The first four Sobol dimensions at index i, as 32-bit fractions (Joe & Kuo 2008 direction
/// numbers for dimensions 2-4; dimension 1 is the van der Corput sequence).
inline uint32_t sobol4(uint32_t index, int dimension) {
    const auto& t = detail::kSobolByteTables[dimension & 3];
    return t[0][index & 0xffu] ^ t[1][(index >> 8) & 0xffu] ^ t[2][(index >> 16) & 0xffu] ^
           t[3][index >> 24];
}

/// Nested uniform (Owen) scrambling of a 32-bit fraction with a hash-based permutation:
/// Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4), section 3 (Laine-Karras
/// style hash applied to the bit-reversed value).
inline uint32_t owenScramble(uint32_t x, uint32_t seed) {
    // Burley 2020, JCGT 9(4), listing 3 constants for the Laine-Karras permutation.
    x = detail::reverseBits(x);
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return detail::reverseBits(x);
}

class Sampler {
public:
    Sampler(SamplerKind kind, uint32_t seed, uint32_t pixel, uint32_t sampleIndex)
        : _kind(kind), _pixelKey(hashCombine(hashMix(seed ^ 0x5bd1e995u), pixel)), _index(sampleIndex) {}

    /// Uniform in [0, 1).
    float next1D() { return toUnit(value(_dimension++)); }
    glm::vec2 next2D() {
        float a = next1D();
        return {a, next1D()};
    }
    uint32_t dimension() const { return _dimension; }

private:
    uint32_t value(uint32_t d) {
        if (_kind == SamplerKind::Independent)
            return hashCombine(hashCombine(_pixelKey, _index), d * 0x85ebca6bu + 1u);
        // Burley 2020 section 4: dimensions come in groups of four Owen-scrambled Sobol
        // dimensions; each group shuffles the sample order per pixel (scrambling the index)
        // with its own seed, which decorrelates the groups ("padding").
        uint32_t group = d >> 2;
        if (group != _group) {
            _group = group;
            _groupSeed = hashCombine(_pixelKey, group);
            _shuffled = owenScramble(_index, _groupSeed);
        }
        return owenScramble(sobol4(_shuffled, int(d & 3u)), hashCombine(_groupSeed, (d & 3u) + 1u));
    }
    static float toUnit(uint32_t x) { return static_cast<float>(x >> 8) * 0x1p-24f; }

    SamplerKind _kind;
    uint32_t _pixelKey;
    uint32_t _index;
    uint32_t _dimension = 0;
    // Dimensions are drawn in order, four per Sobol group: the group's seed and scrambled
    // index are computed once per group, not once per dimension (same values).
    uint32_t _group = ~0u;
    uint32_t _groupSeed = 0;
    uint32_t _shuffled = 0;
};

}  // namespace principled::embree
