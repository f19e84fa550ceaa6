// SPDX-License-Identifier: Apache-2.0
// SphericalRectangle: the solid angle a planar rectangle subtends from a point, and points on
// the rectangle drawn uniformly in that solid angle (Urena, Fajardo & King 2013, "An
// Area-Preserving Parametrization for Spherical Rectangles", EGSR, section 3, Algorithm 1).
// Arithmetic in double: the arc cosines of the setup lose float precision for small angles.
#pragma once

#include <glm/glm.hpp>

namespace principled::embree {

class SphericalRectangle {
public:
    SphericalRectangle() = default;  ///< not valid()
    /// The rectangle corner + a ex + b ey (a, b in [0, 1]; ex and ey perpendicular) seen from p.
    SphericalRectangle(const glm::vec3& p, const glm::vec3& corner, const glm::vec3& ex, const glm::vec3& ey);

    /// False when p lies in the rectangle's plane or the rectangle is degenerate.
    bool valid() const { return _valid; }
    /// Steradians.
    double solidAngle() const { return _solidAngle; }
    /// The point of the rectangle at (u, v) in [0, 1)^2 of the area-preserving map: uniform in
    /// solid angle as seen from p.
    glm::vec3 sample(float u, float v) const;

private:
    bool _valid = false;
    glm::dvec3 _p{0.0}, _x{0.0}, _y{0.0}, _z{0.0};
    double _z0 = 0.0, _x0 = 0.0, _y0 = 0.0, _x1 = 0.0, _y1 = 0.0;
    double _b0 = 0.0, _b1 = 0.0, _k = 0.0, _solidAngle = 0.0;
};

}  // namespace principled::embree
