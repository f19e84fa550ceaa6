// SPDX-License-Identifier: Apache-2.0
#include "delegate/subdiv/levelBudget.h"

#include <algorithm>
#include <cmath>

#include "delegate/subdiv/adaptiveLevel.h"

namespace principled::subdiv {

namespace {

// Every level drops to 0 by this step: plans ask for at most 64 (log2Ratio is capped there,
// +inf included) and lose one level per two steps.
constexpr int kLastStep = 2 * 64 + 2;

float cappedLog2Ratio(float x) { return std::isnan(x) ? -INFINITY : std::min(x, 64.0f); }

}  // namespace

int LevelPlan::levelAt(int step) const {
    return levelFromLog2Ratio(cappedLog2Ratio(log2Ratio) - 0.5f * float(step), maxLevel);
}

double LevelPlan::trianglesAt(int level) const {
    level = std::min(level, faceCapLevel);
    return level <= 0 ? double(cageTriangles) : trianglesAtLevel1 * std::pow(4.0, level - 1);
}

LevelBudgetFit fitLevelBudget(const std::vector<LevelPlan>& plans, double budget) {
    auto total = [&](int step) {
        double sum = 0.0;
        for (const LevelPlan& p : plans) sum += p.trianglesAt(p.levelAt(step));
        return sum;
    };
    LevelBudgetFit fit;
    fit.requested = total(0);
    int step = 0;
    if (budget > 0.0 && fit.requested > budget) {
        // The total never grows with the step: bisect for the first step that fits.
        int lo = 0, hi = kLastStep;
        if (total(hi) > budget) {
            step = hi;
            fit.fits = false;
        } else {
            while (hi - lo > 1) {
                const int mid = (lo + hi) / 2;
                (total(mid) <= budget ? hi : lo) = mid;
            }
            step = hi;
        }
    }
    fit.steps = step;
    fit.levels.reserve(plans.size());
    for (const LevelPlan& p : plans) {
        fit.levels.push_back(p.levelAt(step));
        fit.triangles += p.trianglesAt(fit.levels.back());
    }
    return fit;
}

}  // namespace principled::subdiv
