// SPDX-License-Identifier: Apache-2.0
// Helpers shared by the bsdf tests: lobe-level chi-square, furnace integrals, random directions.
#pragma once

#include <gtest/gtest.h>

#include "bsdf/chi2.h"
#include "bsdf/diagnostics.h"
#include "bsdf/lobe.h"
#include "bsdf/rng.h"
#include "bsdf/warp.h"

namespace principled::bsdf::test {

/// Chi-square of one lobe's sample() against its pdf() at view angle thetaDeg.
template <typename L>
Chi2Result lobeChi2(const L& lobe, float thetaDeg, int testCount = 1, int samples = 400000,
                    float phiDeg = 30.0f) {
    Chi2Config cfg;
    cfg.samples = samples;
    cfg.testCount = testCount;
    cfg.cosBins = 60;
    cfg.phiBins = 60;
    glm::vec3 wo = directionFromAngles(thetaDeg, phiDeg);
    auto sampler = [&](float uLobe, glm::vec2 u) -> std::optional<glm::vec3> {
        auto s = lobe.sample(wo, u, uLobe);
        if (!s || s->delta) return std::nullopt;
        return s->wi;
    };
    auto pdf = [&](const glm::vec3& wi) { return lobe.pdf(wo, wi); };
    return chi2Test(sampler, pdf, cfg);
}

/// Directional albedo of a lobe by uniform-sphere quadrature (independent of its sampler).
template <typename L>
double lobeAlbedoUniform(const L& lobe, const glm::vec3& wo, int n = 400000, uint64_t seed = 3) {
    Pcg32 rng(seed);
    double sum = 0.0;
    for (int k = 0; k < n; ++k) {
        glm::vec3 wi = squareToUniformSphere({rng.uniform(), rng.uniform()});
        sum += double(lobe.eval(wo, wi).x) * 4.0 * kPi;
    }
    return sum / n;
}

/// Directional albedo of a lobe by its own importance sampling.
template <typename L>
double lobeAlbedoSampled(const L& lobe, const glm::vec3& wo, int n = 400000, uint64_t seed = 5) {
    Pcg32 rng(seed);
    double sum = 0.0;
    for (int k = 0; k < n; ++k) {
        auto s = lobe.sample(wo, {rng.uniform(), rng.uniform()}, rng.uniform());
        if (s && s->pdf > 0.0f) sum += double(s->f.x) / s->pdf;
    }
    return sum / n;
}

inline glm::vec3 muDirection(float mu, float phi = 0.0f) {
    float s = std::sqrt(std::max(0.0f, 1.0f - mu * mu));
    return {s * std::cos(phi), s * std::sin(phi), mu};
}

inline glm::vec3 randomUpper(Pcg32& rng) {
    glm::vec3 w = squareToUniformSphere({rng.uniform(), rng.uniform()});
    return {w.x, w.y, std::abs(w.z)};
}

inline float relErr(float a, float b) { return std::abs(a - b) / std::max(std::abs(b), 1e-6f); }

}  // namespace principled::bsdf::test
