// SPDX-License-Identifier: Apache-2.0
// LightShaping: the UsdLux ShapingAPI emission profile of a light (cone cut-off with a soft edge,
// focus), evaluated per emission direction. Spot lights are sphere or disk lights with a cone.
#pragma once

#include <glm/glm.hpp>

namespace principled::embree {

struct LightShaping {
    bool enabled = false;
    glm::vec3 axis{0, 0, -1};   ///< world direction of the light's primary axis (its local -Z)
    float coneAngle = 3.14159265358979323846f;  ///< radians off the axis where emission ends
    float softness = 0.0f;      ///< [0, 1]: fraction of the cone angle the edge fades over
    float focus = 0.0f;         ///< off-axis cosine power
    glm::vec3 focusTint{0.0f};  ///< what the focus falloff fades to
};

/// Multiplier of the emitted radiance in unit direction w (from the emitting point toward the
/// receiver). UsdLux ShapingAPI (OpenUSD usdLux/schema.usda: shaping:cone:angle is the angular
/// limit off the primary axis, shaping:cone:softness the cut-off softness; the smoothstep over the
/// outer `softness` fraction of the angle is the falloff the OpenUSD 24 schema docs give, older
/// docs leave the curve to the renderer):
///   theta = acos(axis . w), theta_cut = coneAngle, theta_start = coneAngle * (1 - softness),
///   cone = 1 - smoothstep(theta_start, theta_cut, theta)   (a hard step when softness = 0),
///   focus: f = max(0, cos theta)^focus, tinted: focusTint + (1 - focusTint) f.
glm::vec3 shapingFactor(const LightShaping& s, const glm::vec3& w);

/// The cone part alone (theta in radians), for tests and hosts' documentation.
float coneFalloff(float theta, float coneAngle, float softness);

}  // namespace principled::embree
