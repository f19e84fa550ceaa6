// SPDX-License-Identifier: Apache-2.0
// The caustic light-path budget (delegate/causticBudget.h): the count per camera sample that
// makes variance x cost least, checked against a direct scan of that product.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "delegate/causticBudget.h"

using principled::embree::CausticBudget;

namespace {

// Image variance x cost per camera sample with n light paths per camera sample: the model the
// budget minimises, written out independently of it.
double varianceTimesCost(double n, double A, double v, double c, double d, double P) {
    return (P * v + A / (n * P)) * (c + n * d);
}

}  // namespace

TEST(CausticBudget, UsesTheBaseCountUntilBothKindsOfPathsHaveBeenMeasured) {
    CausticBudget b;
    EXPECT_EQ(b.pathsPerSample(0.125, 100), 0.125);
    b.addLightPaths(100, 300, 5.0);
    EXPECT_EQ(b.pathsPerSample(0.125, 100), 0.125);
    b.addCameraSamples(200, 800, 0.0, 0);  // no pixel took two samples yet
    EXPECT_EQ(b.pathsPerSample(0.125, 100), 0.125);
    b.addCameraSamples(200, 800, 10.0, 100);
    EXPECT_NE(b.pathsPerSample(0.125, 100), 0.125);
    b.reset();
    EXPECT_EQ(b.pathsPerSample(0.125, 100), 0.125);
}

TEST(CausticBudget, PicksTheCountWithTheLeastVarianceTimesCost) {
    // A per light path, v per sample and pixel, c and d rays, P pixels; the scan's best n must be
    // the budget's, within the scan's step.
    const double P = 400.0;
    for (double A : {50.0, 400.0, 3000.0})
        for (double v : {0.02, 0.1}) {
            const double c = 4.0, d = 3.0;
            CausticBudget b;
            b.addLightPaths(1000, uint64_t(1000 * d), A * 1000);  // d rays a path, each kLightRayCost
            b.addCameraSamples(2000, uint64_t(2000 * c), v * P, uint64_t(P));
            const double picked = b.pathsPerSample(1.0, uint64_t(P));
            double best = 0.0, bestCost = INFINITY;
            for (double n = 1.0 / 16; n <= 4.0; n *= 1.001) {
                const double cost = varianceTimesCost(n, A, v, c, d * CausticBudget::kLightRayCost, P);
                if (cost < bestCost) {
                    bestCost = cost;
                    best = n;
                }
            }
            EXPECT_NEAR(picked / best, 1.0, 2e-3) << "A " << A << " v " << v;
            EXPECT_LE(varianceTimesCost(picked, A, v, c, d * CausticBudget::kLightRayCost, P), bestCost * (1.0 + 1e-6));
        }
}

TEST(CausticBudget, StaysWithinItsRangeAndHandlesDegenerateStatistics) {
    const double base = 0.125, P = 100.0;
    CausticBudget noisyRest;  // the rest of the image is far noisier: as few paths as allowed
    noisyRest.addLightPaths(1000, 3000, 1e-3);
    noisyRest.addCameraSamples(1000, 4000, 1e6, 100);
    EXPECT_DOUBLE_EQ(noisyRest.pathsPerSample(base, uint64_t(P)), base * CausticBudget::kMinFactor);
    CausticBudget quietRest;  // only the caustic is noisy: as many as allowed
    quietRest.addLightPaths(1000, 3000, 1e6);
    quietRest.addCameraSamples(1000, 4000, 1e-9, 100);
    EXPECT_DOUBLE_EQ(quietRest.pathsPerSample(base, uint64_t(P)), base * CausticBudget::kMaxFactor);
    CausticBudget silent;  // the light paths reached no pixel
    silent.addLightPaths(1000, 3000, 0.0);
    silent.addCameraSamples(1000, 4000, 5.0, 100);
    EXPECT_DOUBLE_EQ(silent.pathsPerSample(base, uint64_t(P)), base * CausticBudget::kMinFactor);
    CausticBudget noiseless;  // nothing else varies
    noiseless.addLightPaths(1000, 3000, 2.0);
    noiseless.addCameraSamples(1000, 4000, 0.0, 100);
    EXPECT_DOUBLE_EQ(noiseless.pathsPerSample(base, uint64_t(P)), base * CausticBudget::kMaxFactor);
    CausticBudget broken;  // a NaN or negative statistic is not taken
    broken.addLightPaths(1000, 3000, NAN);
    broken.addLightPaths(1000, 3000, -1.0);
    broken.addCameraSamples(1000, 4000, INFINITY, 100);
    EXPECT_DOUBLE_EQ(broken.pathsPerSample(base, uint64_t(P)), base);
}

TEST(CausticBudget, DisplayWeightIsTheToneCurvesSlopeSquared) {
    // Var T(X) ~ T'(mean)^2 Var X for T(l) = l / (1 + l): the slope by central differences.
    auto tone = [](double l) { return l / (1.0 + l); };
    for (double mean : {0.0, 0.1, 1.0, 3.0, 300.0}) {
        const double h = 1e-4 * (1.0 + mean);
        const double slope = (tone(mean + h) - tone(std::max(0.0, mean - h))) / (mean + h - std::max(0.0, mean - h));
        EXPECT_NEAR(CausticBudget::displayWeight(mean) / (slope * slope), 1.0, 1e-3) << mean;
    }
    EXPECT_EQ(CausticBudget::displayWeight(-1.0), 1.0);  // a negative mean (noise) counts as black
}

TEST(CausticBudget, ADisplaySeesNoMoreThanAQuarterOfVariance) {
    // A pixel's first glint hit (mean 0 before it) must not claim millions.
    EXPECT_EQ(CausticBudget::displayVariance(3e6), 0.25);
    EXPECT_EQ(CausticBudget::displayVariance(0.01), 0.01);
}
