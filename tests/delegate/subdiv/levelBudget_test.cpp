// SPDX-License-Identifier: Apache-2.0
#include "delegate/subdiv/levelBudget.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "delegate/subdiv/adaptiveLevel.h"

using namespace principled::subdiv;

namespace {

// A quad cage of `quads` faces asking for log2Ratio (adaptive, up to maxLevel).
LevelPlan quadPlan(size_t quads, float log2Ratio, int maxLevel = 6) {
    LevelPlan p;
    p.log2Ratio = log2Ratio;
    p.maxLevel = maxLevel;
    p.cageTriangles = 2 * quads;
    p.trianglesAtLevel1 = 8.0 * double(quads);
    return p;
}

double total(const std::vector<LevelPlan>& plans, const std::vector<int>& levels) {
    double t = 0.0;
    for (size_t i = 0; i < plans.size(); ++i) t += plans[i].trianglesAt(levels[i]);
    return t;
}

}  // namespace

TEST(LevelBudget, StepZeroIsTheAdaptiveLevel) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-3.0f, 3.0f);
    for (int i = 0; i < 2000; ++i) {
        const glm::vec3 lo(u(rng), u(rng), u(rng));
        const glm::vec3 hi = lo + glm::vec3(std::abs(u(rng)), std::abs(u(rng)), std::abs(u(rng)));
        ScreenMetric view;
        view.cameraPosition = glm::vec3(u(rng), u(rng), 4.0f * u(rng));
        view.imageHeight = 100 + i;
        view.maxLevel = i % 9;
        const size_t faces = size_t(1 + i % 300);
        LevelPlan p = quadPlan(faces, adaptiveLog2Ratio(lo, hi, faces, view), view.maxLevel);
        EXPECT_EQ(p.levelAt(0), adaptiveLevel(lo, hi, faces, view)) << i;
    }
}

TEST(LevelBudget, UnderTheBudgetNothingChanges) {
    const std::vector<LevelPlan> plans{quadPlan(100, 3.2f), quadPlan(10, 5.9f), quadPlan(1000, -INFINITY)};
    const LevelBudgetFit fit = fitLevelBudget(plans, 1e9);
    EXPECT_EQ(fit.steps, 0);
    EXPECT_TRUE(fit.fits);
    EXPECT_EQ(fit.levels, (std::vector<int>{4, 6, 0}));
    EXPECT_DOUBLE_EQ(fit.triangles, fit.requested);
    EXPECT_EQ(fitLevelBudget(plans, 0.0).levels, fit.levels);  // 0: no limit
}

TEST(LevelBudget, OverTheBudgetTakesTheFewestHalfStepsThatFit) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> ratio(-1.0f, 9.0f);
    std::uniform_int_distribution<int> faces(1, 5000);
    for (int trial = 0; trial < 50; ++trial) {
        std::vector<LevelPlan> plans;
        for (int i = 0; i < 20; ++i) plans.push_back(quadPlan(size_t(faces(rng)), ratio(rng)));
        const double requested = fitLevelBudget(plans, 0.0).triangles;
        const double budget = requested * std::pow(0.5, 1 + trial % 8);
        const LevelBudgetFit fit = fitLevelBudget(plans, budget);
        ASSERT_GT(fit.steps, 0);
        EXPECT_DOUBLE_EQ(fit.requested, requested);
        if (!fit.fits) continue;
        EXPECT_LE(fit.triangles, budget);
        EXPECT_DOUBLE_EQ(total(plans, fit.levels), fit.triangles);
        // One half step fewer would not fit: the fewest steps.
        std::vector<int> previous;
        for (const LevelPlan& p : plans) previous.push_back(p.levelAt(fit.steps - 1));
        EXPECT_GT(total(plans, previous), budget);
        // Every mesh is lowered alike, never raised, and the order of the plans does not matter.
        for (size_t i = 0; i < plans.size(); ++i) EXPECT_LE(fit.levels[i], plans[i].levelAt(0));
        std::vector<LevelPlan> reversed(plans.rbegin(), plans.rend());
        std::vector<int> levels = fitLevelBudget(reversed, budget).levels;
        std::reverse(levels.begin(), levels.end());
        EXPECT_EQ(levels, fit.levels);
    }
}

TEST(LevelBudget, FixedLevelsLoseOneLevelEveryTwoSteps) {
    LevelPlan fixed = quadPlan(10, 5.0f, 5);
    for (int step = 0; step < 14; ++step) EXPECT_EQ(fixed.levelAt(step), std::max(0, 5 - step / 2)) << step;
    // An overflowed ratio (+inf) asks for maxLevel and still comes down.
    LevelPlan huge = quadPlan(10, INFINITY, 6);
    EXPECT_EQ(huge.levelAt(0), 6);
    EXPECT_EQ(huge.levelAt(200), 0);
}

TEST(LevelBudget, CountsThePerMeshCapAndSaysWhenNothingFits) {
    LevelPlan capped = quadPlan(1000, 6.0f);
    capped.faceCapLevel = 3;
    EXPECT_DOUBLE_EQ(capped.trianglesAt(6), capped.trianglesAt(3));
    // Cages alone over the budget: every mesh at level 0, reported as not fitting.
    const std::vector<LevelPlan> plans{capped, quadPlan(5000, 4.0f)};
    const LevelBudgetFit fit = fitLevelBudget(plans, 100.0);
    EXPECT_FALSE(fit.fits);
    EXPECT_EQ(fit.levels, (std::vector<int>{0, 0}));
    EXPECT_DOUBLE_EQ(fit.triangles, 2.0 * 6000.0);
}
