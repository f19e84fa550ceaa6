// SPDX-License-Identifier: Apache-2.0
// How far a ray's origin leaves the surface it starts on.
#pragma once

#include <algorithm>

#include <glm/glm.hpp>

namespace principled::embree {

/// About 16 float ulps of the position's magnitude (2^-23 relative each), with a floor for
/// positions near the origin: large enough for a reconstructed hit point's error, small enough
/// that contact shadows survive far from the origin.
inline float offsetScale(const glm::vec3& p) {
    const glm::vec3 a = glm::abs(p);
    return std::max(1e-5f, 2e-6f * std::max({a.x, a.y, a.z}));
}

}  // namespace principled::embree
