// SPDX-License-Identifier: Apache-2.0
// A small deterministic generator for tests, tools and benchmarks (never seeded from the clock).
#pragma once

#include <cstdint>

namespace principled::bsdf {

/// O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient Statistically Good Algorithms for
/// Random Number Generation", PCG32 (XSH RR output, 64-bit LCG state).
class Pcg32 {
public:
    explicit Pcg32(uint64_t seed = 0x853c49e6748fea9bULL, uint64_t stream = 0xda3e39cb94b95bdbULL) {
        _inc = (stream << 1u) | 1u;
        next();
        _state += seed;
        next();
    }
    uint32_t next() {
        uint64_t old = _state;
        _state = old * 6364136223846793005ULL + _inc;  // Knuth's MMIX LCG multiplier
        auto xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
        auto rot = static_cast<uint32_t>(old >> 59u);
        return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
    }
    /// Uniform in [0, 1): 24 random mantissa bits.
    float uniform() { return static_cast<float>(next() >> 8) * 0x1p-24f; }

private:
    uint64_t _state = 0, _inc = 0;
};

}  // namespace principled::bsdf
