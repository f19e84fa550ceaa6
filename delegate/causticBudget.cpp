// SPDX-License-Identifier: Apache-2.0
#include "delegate/causticBudget.h"

#include <algorithm>
#include <cmath>

namespace principled::embree {

void CausticBudget::addLightPaths(uint64_t paths, uint64_t rays, double splatSquares) {
    if (!std::isfinite(splatSquares) || splatSquares < 0.0) return;
    _paths += paths;
    _lightRays += rays;
    _splatSquares += splatSquares;
}

void CausticBudget::addCameraSamples(uint64_t samples, uint64_t rays, double varianceSum, uint64_t varianceCount) {
    _samples += samples;
    _cameraRays += rays;
    if (std::isfinite(varianceSum) && varianceSum >= 0.0) {
        _varianceSum += varianceSum;
        _varianceCount += varianceCount;
    }
}

double CausticBudget::pathsPerSample(double base, uint64_t pixels) const {
    if (_paths == 0 || _samples == 0 || _varianceCount == 0 || _lightRays == 0 || pixels == 0) return base;
    const double lo = base * kMinFactor, hi = base * kMaxFactor;
    const double A = _splatSquares / double(_paths);                 // per light path
    const double v = _varianceSum / double(_varianceCount);          // per camera sample and pixel
    const double c = double(_cameraRays) / double(_samples);         // rays per camera sample
    const double d = kLightRayCost * double(_lightRays) / double(_paths);  // per light path, in camera rays
    const double P = double(pixels);
    if (!(A > 0.0)) return lo;   // the light paths reached no pixel: keep them few
    if (!(v > 0.0)) return hi;   // nothing else is noisy
    const double n = std::sqrt(A * c / (P * P * v * d));
    return std::isfinite(n) ? std::clamp(n, lo, hi) : base;
}

}  // namespace principled::embree
