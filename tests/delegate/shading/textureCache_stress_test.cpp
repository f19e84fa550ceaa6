// SPDX-License-Identifier: Apache-2.0
// The long run of TextureCacheResident.InvalidateDuringLookups (label "stress": not in the
// default run). PRINCIPLED_STRESS_SECONDS overrides its length.
#include <cstdlib>

#include "textureCacheStress.h"

TEST(TextureCacheStress, InvalidateDuringLookups) {
    const char* env = std::getenv("PRINCIPLED_STRESS_SECONDS");
    const double seconds = env ? std::atof(env) : 20.0;
    principled::shading::test::invalidateWhileLooking(seconds > 0.0 ? seconds : 20.0, 4);
}
