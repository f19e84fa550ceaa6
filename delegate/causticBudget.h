// SPDX-License-Identifier: Apache-2.0
// How many caustic light paths a pass traces per camera sample: the count that makes the
// image's variance times its cost least, from what the passes before it measured.
#pragma once

#include <algorithm>
#include <cstdint>

namespace principled::embree {

/// The light-traced share of a pixel is a mean over N light paths (variance A/N summed over the
/// image, A = a path's squared splats); the rest is a mean over S camera samples (variance
/// P v / S, v = the per-sample variance averaged over the P pixels). Both are weighted per
/// pixel by how much of its variance a display shows (displayWeight). With n light paths per
/// camera sample, N = n S P and the cost per camera sample is c + n d (c, d: rays per camera
/// sample and per light path), so variance x cost ~ (P v + A / (n P)) (c + n d), least at
/// n = sqrt(A c / (P^2 v d)) (the efficiency of an estimator sum, as in Grittmann et al. 2022,
/// "Efficiency-aware multiple importance sampling for bidirectional rendering algorithms",
/// section 4). Rays, not seconds, measure cost, so the choice and the image are the same on any
/// machine and thread count; a light path's ray costs kLightRayCost camera rays (its vertices
/// also connect to the camera and evaluate the BSDF from both sides).
class CausticBudget {
public:
    /// Forgets every statistic (a restart).
    void reset() { *this = CausticBudget(); }

    /// Every statistic, to save with a checkpoint and restore on resume.
    struct State {
        uint64_t paths = 0, lightRays = 0, samples = 0, cameraRays = 0, varianceCount = 0;
        double splatSquares = 0.0, varianceSum = 0.0;
    };
    State state() const { return {_paths, _lightRays, _samples, _cameraRays, _varianceCount, _splatSquares, _varianceSum}; }
    void restore(const State& s) {
        _paths = s.paths, _lightRays = s.lightRays, _samples = s.samples, _cameraRays = s.cameraRays;
        _varianceCount = s.varianceCount, _splatSquares = s.splatSquares, _varianceSum = s.varianceSum;
    }

    /// A pass's light paths: how many, the rays they cast, and the sum over paths of the
    /// squared luminance of each splat (in pixel units: a pixel's share is the mean of its
    /// splats over the paths), each times its pixel's displayWeight.
    void addLightPaths(uint64_t paths, uint64_t rays, double splatSquares);
    /// A pass's camera samples: how many and their rays; and the per-sample luminance variance
    /// times displayWeight summed over the pixels that took two or more samples in the pass,
    /// with their count.
    void addCameraSamples(uint64_t samples, uint64_t rays, double varianceSum, uint64_t varianceCount);

    /// Light paths per camera sample for the next pass: `base` until both kinds of statistics
    /// exist, then the optimum above kept within [base / 16, base * 4].
    double pathsPerSample(double base, uint64_t pixels) const;

    /// The weight of a pixel's variance: the error a display sees, through the tone curve
    /// T(l) = l / (1 + l) (Reinhard et al. 2002, "Photographic Tone Reproduction for Digital
    /// Images", eq. 3), by the delta method Var T(X) ~ T'(mean)^2 Var X, T'(l) = 1 / (1 + l)^2.
    /// A sun glint of mean radiance 300 in one pixel (3e4 on 1 % of it) then weighs 1e-3 instead
    /// of 1e7 mid-grey pixels' worth.
    static double displayWeight(double mean) {
        const double m = mean > 0.0 ? mean : 0.0;
        const double slope = 1.0 / ((1.0 + m) * (1.0 + m));
        return slope * slope;
    }

    /// A weighted per-sample variance as a display sees it: no more than 1/4, the most any
    /// quantity within [0, 1) (the tone curve's range) can vary. The delta method above holds
    /// once a pixel's mean is known; before that (a glint's first hit on a pixel that had been
    /// black) it can claim millions.
    static double displayVariance(double weighted) { return std::min(weighted, 0.25); }

    static constexpr double kMinFactor = 1.0 / 16.0, kMaxFactor = 4.0;
    /// CPU per light-path ray over CPU per camera-path ray, measured (1 thread, 96x96, 32 spp,
    /// causticPaths 4 against caustics 0): fig_specular0 297/182 ns, fig_metallic1 291/168,
    /// the default scene 336/168, a glass ball 248/188.
    static constexpr double kLightRayCost = 1.6;

private:
    uint64_t _paths = 0, _lightRays = 0, _samples = 0, _cameraRays = 0, _varianceCount = 0;
    double _splatSquares = 0.0, _varianceSum = 0.0;
};

}  // namespace principled::embree
