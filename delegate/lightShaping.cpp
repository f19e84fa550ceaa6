// SPDX-License-Identifier: Apache-2.0
#include "delegate/lightShaping.h"

#include <algorithm>
#include <cmath>

namespace principled::embree {

float coneFalloff(float theta, float coneAngle, float softness) {
    float start = coneAngle * (1.0f - std::clamp(softness, 0.0f, 1.0f));
    if (theta <= start) return 1.0f;
    if (theta >= coneAngle) return 0.0f;
    // Hermite smoothstep(start, coneAngle, theta) (GLSL 4.60 §8.3), subtracted from 1.
    float t = (theta - start) / (coneAngle - start);
    return 1.0f - t * t * (3.0f - 2.0f * t);
}

glm::vec3 shapingFactor(const LightShaping& s, const glm::vec3& w) {
    if (!s.enabled) return glm::vec3(1.0f);
    float c = std::clamp(glm::dot(s.axis, w), -1.0f, 1.0f);
    float cone = coneFalloff(std::acos(c), s.coneAngle, s.softness);
    if (cone <= 0.0f) return glm::vec3(0.0f);
    glm::vec3 focus(1.0f);
    if (s.focus > 0.0f) {
        float f = std::pow(std::max(0.0f, c), s.focus);
        focus = s.focusTint + (glm::vec3(1.0f) - s.focusTint) * f;
    }
    if (s.ies) {
        constexpr float kPi = 3.14159265358979323846f;
        const float theta = (std::acos(c) - kPi) / (1.0f + s.iesAngleScale) + kPi;
        if (!(theta >= 0.0f)) return glm::vec3(0.0f);
        // Local +Y of the light: its -Z (the axis) crossed with +X is -Y, so +Y = tangent x axis.
        const glm::vec3 bitangent = glm::cross(s.tangent, s.axis);
        const float phi = std::atan2(glm::dot(w, bitangent), glm::dot(w, s.tangent)) * (180.0f / kPi);
        focus *= s.ies->evaluate(theta * (180.0f / kPi), phi) * s.iesScale;
    }
    return cone * focus;
}

}  // namespace principled::embree
