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
/// The same points in the bit-reversed domain: entry [d][k][b] is reverseBits of the point at
/// index reverseBits(b << 8k), so reversed points come from reversed indices directly.
extern const SobolByteTables kSobolReversedByteTables;

/// Each byte with its bits in reverse order (built at compile time in sampler.cpp).
extern const std::array<uint8_t, 256> kReversedBytes;

/// reverseBits(x) >> 8, the 24 bits a float in [0, 1) keeps: the low three bytes of x, each
/// reversed, in swapped order.
inline uint32_t reverseBitsTop24(uint32_t x) {
    return uint32_t(kReversedBytes[x & 0xffu]) << 16 | uint32_t(kReversedBytes[(x >> 8) & 0xffu]) << 8 |
           uint32_t(kReversedBytes[(x >> 16) & 0xffu]);
}

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

/// reverseBits(sobol4(reverseBits(reversedIndex), dimension)): a Sobol point in the
/// bit-reversed domain, where Owen scrambling works, without reversing twice.
inline uint32_t sobol4Reversed(uint32_t reversedIndex, int dimension) {
    const auto& t = detail::kSobolReversedByteTables[dimension & 3];
    return t[0][reversedIndex & 0xffu] ^ t[1][(reversedIndex >> 8) & 0xffu] ^
           t[2][(reversedIndex >> 16) & 0xffu] ^ t[3][reversedIndex >> 24];
}

/// The Laine-Karras style permutation of a bit-reversed value: it flips each bit depending on
/// the bits below it only, which in the reversed domain is nested uniform scrambling.
/// Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4), listing 3 constants.
inline uint32_t laineKarrasPermutation(uint32_t x, uint32_t seed) {
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

/// Nested uniform (Owen) scrambling of a 32-bit fraction with a hash-based permutation:
/// Burley 2020, "Practical Hash-based Owen Scrambling", JCGT 9(4), section 3 (Laine-Karras
/// style hash applied to the bit-reversed value).
inline uint32_t owenScramble(uint32_t x, uint32_t seed) {
    return detail::reverseBits(laineKarrasPermutation(detail::reverseBits(x), seed));
}

class Sampler {
public:
    Sampler(SamplerKind kind, uint32_t seed, uint32_t pixel, uint32_t sampleIndex)
        : _kind(kind), _pixelKey(hashCombine(hashMix(seed ^ 0x5bd1e995u), pixel)), _index(sampleIndex),
          _reversedIndex(detail::reverseBits(sampleIndex)) {}

    /// Uniform in [0, 1).
    float next1D() { return toUnit24(value24(_dimension++)); }
    /// A 2-D decision starts a fresh group of four, so it always gets dimensions (0, 1) of an
    /// Owen-scrambled Sobol sequence of its own: a (0,2)-sequence, stratified in 2-D. 1-D
    /// decisions take the dimensions left over in the group (2 and 3), which keeps a light
    /// pick or lobe choice stratified jointly with the 2-D sample before it. Burley 2020,
    /// "Practical Hash-based Owen Scrambling", JCGT 9(4), section 4 (padding by shuffling).
    glm::vec2 next2D() {
        _dimension = (_dimension + 3u) & ~3u;
        float a = next1D();
        return {a, next1D()};
    }
    uint32_t dimension() const { return _dimension; }

private:
    /// The top 24 bits of dimension d's 32-bit value (all that toUnit24 keeps).
    uint32_t value24(uint32_t d) {
        if (_kind == SamplerKind::Independent)
            return hashCombine(hashCombine(_pixelKey, _index), d * 0x85ebca6bu + 1u) >> 8;
        // Burley 2020 section 4: dimensions come in groups of four Owen-scrambled Sobol
        // dimensions; each group shuffles the sample order per pixel (scrambling the index)
        // with its own seed, which decorrelates the groups ("padding").
        // Everything stays bit-reversed until the end: the value equals
        // owenScramble(sobol4(owenScramble(index, groupSeed), d), dimensionSeed) with one
        // reversal per value instead of four.
        uint32_t group = d >> 2;
        if (group != _group) {
            _group = group;
            _groupSeed = hashCombine(_pixelKey, group);
            _shuffledReversed = laineKarrasPermutation(_reversedIndex, _groupSeed);
        }
        return detail::reverseBitsTop24(laineKarrasPermutation(sobol4Reversed(_shuffledReversed, int(d & 3u)),
                                                               hashCombine(_groupSeed, (d & 3u) + 1u)));
    }
    static float toUnit24(uint32_t x) { return static_cast<float>(x) * 0x1p-24f; }

    SamplerKind _kind;
    uint32_t _pixelKey;
    uint32_t _index;
    uint32_t _reversedIndex;
    uint32_t _dimension = 0;
    // Dimensions are drawn in order, four per Sobol group: the group's seed and scrambled
    // index are computed once per group, not once per dimension (same values).
    uint32_t _group = ~0u;
    uint32_t _groupSeed = 0;
    uint32_t _shuffledReversed = 0;  ///< reverseBits of the group's scrambled index
};

}  // namespace principled::embree
