// SPDX-License-Identifier: Apache-2.0
// A scene-wide budget of refined triangles: the subdivision levels of all meshes lowered
// together until the scene fits.
#pragma once

#include <cstddef>
#include <vector>

namespace principled::subdiv {

/// What one subdivision mesh asks for. Its level at step k of the budget is
/// levelFromLog2Ratio(log2Ratio - k / 2, maxLevel) (delegate/subdiv/adaptiveLevel.h): each step
/// doubles the adaptive target edge length by sqrt(2), i.e. every two steps take one level off
/// every mesh. A fixed level L is the plan {L, L}: it loses one level every two steps too.
struct LevelPlan {
    float log2Ratio = 0.0f;  ///< adaptiveLog2Ratio() (or the fixed level), +inf allowed
    int maxLevel = 0;        ///< highest level the settings allow
    int faceCapLevel = 64;   ///< levels above are built at this one (the per-mesh face cap)
    /// Triangles at level L: cageTriangles at 0; else trianglesPerLevel1 * 4^(L-1).
    size_t cageTriangles = 0;
    double trianglesAtLevel1 = 0.0;

    int levelAt(int step) const;
    double trianglesAt(int level) const;
};

struct LevelBudgetFit {
    std::vector<int> levels;  ///< one per plan
    int steps = 0;            ///< half-level steps taken (0: every plan as asked)
    double requested = 0.0;   ///< triangles at step 0
    double triangles = 0.0;   ///< triangles at the levels chosen
    bool fits = true;         ///< false: even the lowest levels exceed the budget
};

/// The smallest step k at which the plans' triangles sum to at most `budget`, or the step at
/// which every plan is at its lowest level when none does (fits = false). Deterministic and
/// independent of the order of the plans; budget 0 means no limit (step 0).
LevelBudgetFit fitLevelBudget(const std::vector<LevelPlan>& plans, double budget);

}  // namespace principled::subdiv
