// SPDX-License-Identifier: Apache-2.0
#include "delegate/shadingNormal.h"

#include <algorithm>
#include <cmath>

namespace principled::embree {

glm::vec3 bendToValidReflection(const glm::vec3& ng, const glm::vec3& wo, const glm::vec3& n) {
    const float iz = glm::dot(wo, ng);
    const float threshold = std::min(0.9f * iz, 0.01f);
    const glm::vec3 r = 2.0f * glm::dot(n, wo) * n - wo;  // mirror direction of wo about n
    if (glm::dot(r, ng) >= threshold) return n;
    // Candidates n' = cos(a) ng + sin(a) x, x the unit tangent toward which n leans. With
    // wo = iz ng + ix x + (a part orthogonal to both), the mirror direction's height is
    //   reflect(wo, n') . ng = 2 (n' . wo) cos(a) - iz = iz cos(2a) + ix sin(2a)
    //                        = len cos(2a - psi),  len = |(iz, ix)|, psi = atan2(ix, iz).
    // It equals iz >= threshold at a = 0 and falls for 2a beyond psi, so the largest valid tilt
    // is 2a = psi + acos(threshold / len).
    glm::vec3 x = n - glm::dot(n, ng) * ng;
    const float lx = glm::length(x);
    if (!(lx > 1e-7f)) return ng;
    x /= lx;
    const float ix = glm::dot(wo, x);
    const float len = std::sqrt(iz * iz + ix * ix);
    if (!(len > 0.0f)) return ng;
    const float psi = std::atan2(ix, iz);
    const float twoA = psi + std::acos(std::clamp(threshold / len, -1.0f, 1.0f));
    const float a = std::clamp(0.5f * twoA, 0.0f, 1.5707963f);
    const glm::vec3 bent = std::cos(a) * ng + std::sin(a) * x;
    return glm::normalize(bent);
}

}  // namespace principled::embree
