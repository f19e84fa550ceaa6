// SPDX-License-Identifier: Apache-2.0
// Uniform sampling of the solid angle a triangle subtends from a point (a spherical triangle).
// Used by mesh lights: a point near a small emitter gets directions spread evenly over what it
// sees of the emitter instead of a 1/r^2-weighted area sample.
#pragma once

#include <glm/glm.hpp>

namespace principled::embree {

/// A triangle seen from a point: unit directions to its vertices and the solid angle they span.
/// Built once per triangle and shaded point; the solid angle (for picking a triangle of a mesh
/// light) and the sampler share it, so the sampler needs no inverse trigonometric function.
struct SphericalTriangle {
    // No default member initialisers: mesh lights keep arrays of these on the stack per sample
    // and makeSphericalTriangle() writes every field.
    glm::vec3 A, B, C;    ///< unit vectors from the point to the vertices
    float tripleProduct;  ///< |A . (B x C)|
    float solidAngle;     ///< steradians, 0 when degenerate
};

/// The spherical triangle (a, b, c) subtends from p. Returns false (solid angle 0) when it is
/// degenerate: p on a vertex, or the triangle zero-area or edge-on from p.
/// Van Oosterom & Strackee 1983, "The Solid Angle of a Plane Triangle", IEEE TBME 30(2), eq. 8,
/// divided through by |a-p||b-p||c-p| (unit vectors):
/// tan(Omega / 2) = |A . (B x C)| / (1 + A.B + A.C + B.C).
bool makeSphericalTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                           SphericalTriangle* out);

/// Solid angle of triangle (a, b, c) seen from p (unsigned, steradians; 0 when degenerate).
float triangleSolidAngle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c);

/// A unit direction uniform over spherical triangle t (pdf 1 / t.solidAngle).
/// Arvo 1995, "Stratified Sampling of Spherical Triangles", SIGGRAPH, figure 2 (u.x chooses the
/// sub-triangle area, u.y the point on the arc), with the area taken from t.solidAngle and the
/// angle at A from its sine and cosine (no acos). Returns false for a degenerate triangle.
bool sampleSphericalTriangle(const SphericalTriangle& t, const glm::vec2& u, glm::vec3* dir);

/// The same from the triangle's vertices (builds the SphericalTriangle first).
bool sampleSphericalTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                             const glm::vec2& u, glm::vec3* dir);

}  // namespace principled::embree
