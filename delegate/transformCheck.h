// SPDX-License-Identifier: Apache-2.0
// Whether a matrix can place geometry: rays reach an object through the inverse of its
// transform, so a singular, non-finite or projective matrix would hand Embree invalid rays (or
// degenerate instance bounds) instead of an image.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

namespace principled::embree {

/// Null when m is finite, affine (last row (0, 0, 0, 1)) and invertible; else why not.
inline const char* unusableTransform(const glm::mat4& m) {
    bool finite = true;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) finite = finite && std::isfinite(m[c][r]);
    if (!finite) return "not finite";
    const bool affine = std::abs(m[0][3]) + std::abs(m[1][3]) + std::abs(m[2][3]) < 1e-6f && std::abs(m[3][3] - 1.0f) < 1e-6f;
    if (!affine) return "projective (last column is not (0,0,0,1))";
    const float det = glm::determinant(glm::mat3(m));
    if (!std::isfinite(det) || !(std::abs(det) > 1e-30f)) return "singular";
    return nullptr;
}

}  // namespace principled::embree
