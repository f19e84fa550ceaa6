// SPDX-License-Identifier: Apache-2.0
// Measurements on a material used by the tests, the `principled bsdf` command and benchmarks:
// directional albedo, the NaN/Inf/negative stress sweep, and parameter parsing by name.
#pragma once

#include <cstdint>
#include <string>

#include "bsdf/bsdf.h"

namespace principled::bsdf {

struct AlbedoResult {
    glm::vec3 albedo{0.0f};   ///< estimate of the integral of f |cos| over the sphere
    glm::vec3 stdError{0.0f};
};

/// Directional albedo at cos theta_o = mu by importance sampling sample() (delta lobes included).
AlbedoResult directionalAlbedo(const Bsdf& bsdf, float mu, int samples, uint64_t seed = 7);

struct StressResult {
    uint64_t evaluations = 0;
    uint64_t bad = 0;
    std::string firstBad;  ///< description of the first failure
};

/// Random parameters in [0,1] (edge values 0, 1, 1e-8 favoured) and random or degenerate
/// directions; every eval, pdf and sample must be finite and non-negative.
StressResult stressTest(uint64_t evaluations, uint64_t seed, Model model);
/// Same, with the model drawn at random for every material.
StressResult stressTest(uint64_t evaluations, uint64_t seed);

/// Sets the parameter called name (Disney naming, as in MaterialParams) from text. Colours take
/// one value or three joined by ':'. Returns an empty string on success, else a one-line error.
std::string setParameter(MaterialParams& p, const std::string& name, const std::string& value);

/// The defaults of `principled bsdf`: the Disney notes' defaults with a white baseColor.
MaterialParams cliDefaults();

}  // namespace principled::bsdf
