// SPDX-License-Identifier: Apache-2.0
// LightShaping: the UsdLux ShapingAPI emission profile of a light (cone cut-off with a soft edge,
// focus, IES profile), evaluated per emission direction. Spot lights are sphere or disk lights
// with a cone.
#pragma once

#include <memory>

#include <glm/glm.hpp>

#include "delegate/iesProfile.h"

namespace principled::embree {

struct LightShaping {
    bool enabled = false;
    glm::vec3 axis{0, 0, -1};   ///< world direction of the light's primary axis (its local -Z)
    float coneAngle = 3.14159265358979323846f;  ///< radians off the axis where emission ends
    float softness = 0.0f;      ///< [0, 1]: fraction of the cone angle the edge fades over
    float focus = 0.0f;         ///< off-axis cosine power
    glm::vec3 focusTint{0.0f};  ///< what the focus falloff fades to
    /// shaping:ies:file: the profile's vertical angle 0 on the axis, horizontal angle 0 along
    /// `tangent` (the light's local +X) and 90 along its local +Y (see shapingFactor()).
    std::shared_ptr<const IesProfile> ies;
    glm::vec3 tangent{1, 0, 0};
    float iesScale = 1.0f;       ///< 1 / the profile's peak, or 1 / its mean (ies:normalize)
    float iesAngleScale = 0.0f;  ///< shaping:ies:angleScale (> -1)
};

/// Multiplier of the emitted radiance in unit direction w (from the emitting point toward the
/// receiver). UsdLux ShapingAPI (OpenUSD usdLux/schema.usda: shaping:cone:angle is the angular
/// limit off the primary axis, shaping:cone:softness the cut-off softness; the smoothstep over the
/// outer `softness` fraction of the angle is the falloff the OpenUSD 24 schema docs give, older
/// docs leave the curve to the renderer):
///   theta = acos(axis . w), theta_cut = coneAngle, theta_start = coneAngle * (1 - softness),
///   cone = 1 - smoothstep(theta_start, theta_cut, theta)   (a hard step when softness = 0),
///   focus: f = max(0, cos theta)^focus, tinted: focusTint + (1 - focusTint) f;
///   IES: I(theta_ies, phi) * iesScale, with theta_ies = (theta - pi) / (1 + angleScale) + pi
///   (the shaping:ies:angleScale remap of the OpenUSD 24.11 schema text, RenderMan's profile
///   scale) and phi the azimuth from the light's +X toward its +Y; 0 where theta_ies < 0.
glm::vec3 shapingFactor(const LightShaping& s, const glm::vec3& w);

/// The cone part alone (theta in radians), for tests and hosts' documentation.
float coneFalloff(float theta, float coneAngle, float softness);

}  // namespace principled::embree
