// SPDX-License-Identifier: Apache-2.0
// Sampler: deterministic random numbers addressed by (seed, pixel, sample index, dimension),
// so an image does not depend on thread count or tile order. This is the independent-random
// baseline; low-discrepancy sequences plug in behind the same interface.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

namespace principled::embree {

/// A stateless hash per draw: the value of dimension d depends only on (seed, pixel, sample, d).
class Sampler {
public:
    Sampler(uint32_t seed, uint32_t pixel, uint32_t sampleIndex)
        : _key(mix(mix(mix(0x9e3779b9u ^ seed) ^ pixel) ^ sampleIndex)) {}

    /// Uniform in [0, 1).
    float next1D() { return toUnit(mix(_key ^ mix(_dimension++ * 0x85ebca6bu + 0x68e31da4u))); }
    glm::vec2 next2D() {
        float a = next1D();
        return {a, next1D()};
    }

private:
    // Wellons 2018 "Prospecting for Hash Functions", lowbias32 (bias 0.17).
    static uint32_t mix(uint32_t x) {
        x ^= x >> 16;
        x *= 0x7feb352du;
        x ^= x >> 15;
        x *= 0x846ca68bu;
        x ^= x >> 16;
        return x;
    }
    static float toUnit(uint32_t x) { return static_cast<float>(x >> 8) * 0x1p-24f; }

    uint32_t _key;
    uint32_t _dimension = 0;
};

}  // namespace principled::embree
