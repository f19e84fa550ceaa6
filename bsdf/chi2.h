// SPDX-License-Identifier: Apache-2.0
// Chi-square goodness-of-fit of a direction sampler against its pdf (the standard BSDF sampling
// test of pbrt-v3/v4 and Mitsuba; reference/bsdf.md §3), shared by the tests and the CLI.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "bsdf/bsdf.h"

namespace principled::bsdf {

struct Chi2Config {
    int cosBins = 100;          ///< cos theta bins over [-1, 1] (equal solid angle)
    int phiBins = 100;          ///< phi bins over [-pi, pi)
    int samples = 1000000;
    double significance = 0.01;
    int testCount = 1;          ///< Sidak correction over this many tests
    uint64_t seed = 1;
    double minExpected = 5.0;   ///< pool cells with fewer expected counts
};

struct Chi2Result {
    bool passed = false;
    double pValue = 0.0;
    double statistic = 0.0;
    int dof = 0;
    double pdfIntegral = 0.0;   ///< integral of the pdf over the sphere
    double histogramSum = 0.0;  ///< fraction of samples that produced a non-delta direction
    std::string message;
};

/// Samples a direction (nullopt or delta: the sample is counted but not binned).
using DirectionSampler = std::function<std::optional<glm::vec3>(float uLobe, glm::vec2 u)>;
using DirectionPdf = std::function<float(const glm::vec3& wi)>;

Chi2Result chi2Test(const DirectionSampler& sample, const DirectionPdf& pdf, const Chi2Config& cfg);

/// The test applied to a whole material at the view direction with polar angle thetaDeg
/// (azimuth phiDeg, default off-axis so anisotropy is exercised).
Chi2Result chi2TestBsdf(const Bsdf& bsdf, float thetaDeg, const Chi2Config& cfg,
                        float phiDeg = 30.0f);

/// Integral of pdf over the sphere (adaptive per cell, same integrator as the test).
double integratePdf(const DirectionPdf& pdf, int cosBins = 100, int phiBins = 100);

/// Regularised upper incomplete gamma Q(a, x) = 1 - P(a, x); chi-square tail = Q(dof/2, x/2).
double gammaQ(double a, double x);

/// Local direction with polar angle theta (degrees) and azimuth phi (degrees).
glm::vec3 directionFromAngles(float thetaDeg, float phiDeg);

}  // namespace principled::bsdf
