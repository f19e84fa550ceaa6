// SPDX-License-Identifier: Apache-2.0
// Sample warps from the unit square to disks and hemispheres, each with its density.
#pragma once

#include "bsdf/frame.h"

namespace principled::bsdf {

/// Shirley & Chiu 1997, "A Low Distortion Map Between Disk and Square", concentric map.
inline glm::vec2 squareToConcentricDisk(const glm::vec2& u) {
    glm::vec2 p = 2.0f * u - glm::vec2(1.0f);
    if (p.x == 0.0f && p.y == 0.0f) return {0.0f, 0.0f};
    float r, phi;
    if (std::abs(p.x) > std::abs(p.y)) {
        r = p.x;
        phi = (kPi / 4.0f) * (p.y / p.x);
    } else {
        r = p.y;
        phi = (kPi / 2.0f) - (kPi / 4.0f) * (p.x / p.y);
    }
    return {r * std::cos(phi), r * std::sin(phi)};
}

/// Malley's method: cosine-weighted upper hemisphere. pdf = cos(theta) / pi.
inline glm::vec3 squareToCosineHemisphere(const glm::vec2& u) {
    glm::vec2 d = squareToConcentricDisk(u);
    return {d.x, d.y, safeSqrt(1.0f - d.x * d.x - d.y * d.y)};
}
inline float cosineHemispherePdf(const glm::vec3& w) { return std::max(w.z, 0.0f) * kInvPi; }

/// Uniform direction on the unit sphere. pdf = 1 / (4 pi).
inline glm::vec3 squareToUniformSphere(const glm::vec2& u) {
    float z = 1.0f - 2.0f * u.x;
    float r = safeSqrt(1.0f - z * z), phi = kTwoPi * u.y;
    return {r * std::cos(phi), r * std::sin(phi), z};
}

}  // namespace principled::bsdf
