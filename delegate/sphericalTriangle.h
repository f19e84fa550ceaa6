// SPDX-License-Identifier: Apache-2.0
// Uniform sampling of the solid angle a triangle subtends from a point (a spherical triangle).
// Used by mesh lights: a point near a small emitter gets directions spread evenly over what it
// sees of the emitter instead of a 1/r^2-weighted area sample.
#pragma once

#include <glm/glm.hpp>

namespace principled::embree {

/// Solid angle of triangle (a, b, c) seen from p (unsigned, steradians).
/// Van Oosterom & Strackee 1983, "The Solid Angle of a Plane Triangle", IEEE TBME 30(2), eq. 8:
/// tan(Omega / 2) = |A . (B x C)| / (|A||B||C| + (A.B)|C| + (A.C)|B| + (B.C)|A|).
float triangleSolidAngle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c);

/// A unit direction from p, uniform over the spherical triangle the triangle (a, b, c)
/// subtends (pdf 1 / triangleSolidAngle). Arvo 1995, "Stratified Sampling of Spherical
/// Triangles", SIGGRAPH, figure 2 (u.x chooses the sub-triangle area, u.y the point on the arc).
/// Returns false for a degenerate (zero-area or edge-on) spherical triangle.
bool sampleSphericalTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                             const glm::vec2& u, glm::vec3* dir);

}  // namespace principled::embree
