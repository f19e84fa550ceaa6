// SPDX-License-Identifier: Apache-2.0
// Shadowing of the diffuse lobes by a shading normal that leans away from the surface's own
// normal (a normal map, or a normal bent at a grazing view): without it, a normal tilted toward
// a light collects more light than the surface it sits on receives, and the light falls off
// with a harsh edge where it reaches the surface's horizon (the "shadow terminator").
#pragma once

#include <glm/glm.hpp>

namespace principled::bsdf {

/// The factor on the diffuse and sheen lobes for light from wi, in the shading frame (shading
/// normal = +z), where n0 is the surface's own (interpolated) unit normal.
/// Chiang, Li & Burley 2019, "Taming the Shadow Terminator" (SIGGRAPH Talks, art. 71): the
/// shadowing G = min(1, (n0.wi) / ((n.wi)(n0.n))), smoothed to -G^3 + G^2 + G (1 with zero slope
/// at G = 1, 0 at G = 0). Cycles 3.4 applies the same term (bump_shadowing_term) to its diffuse
/// closures whenever the closure normal differs from the smooth normal.
inline float bumpShadowing(const glm::vec3& n0, const glm::vec3& wi) {
    const float denom = wi.z * n0.z;
    if (!(denom > 0.0f)) return 0.0f;  // light below the shading or the surface hemisphere
    const float g = glm::dot(n0, wi) / denom;
    if (g >= 1.0f) return 1.0f;
    if (!(g > 0.0f)) return 0.0f;
    const float g2 = g * g;
    return -g2 * g + g2 + g;
}

}  // namespace principled::bsdf
