// SPDX-License-Identifier: Apache-2.0
#include "delegate/sphericalRectangle.h"

#include <algorithm>
#include <cmath>

namespace principled::embree {

SphericalRectangle::SphericalRectangle(const glm::vec3& p, const glm::vec3& corner, const glm::vec3& ex,
                                       const glm::vec3& ey) {
    constexpr double kTwoPi = 6.283185307179586476925;
    const double exl = glm::length(glm::dvec3(ex)), eyl = glm::length(glm::dvec3(ey));
    if (!(exl > 0.0) || !(eyl > 0.0) || !std::isfinite(exl) || !std::isfinite(eyl)) return;
    _p = glm::dvec3(p);
    // Local frame (section 3.1): x, y along the edges, z their normal turned away from p.
    _x = glm::dvec3(ex) / exl;
    _y = glm::dvec3(ey) / eyl;
    _z = glm::cross(_x, _y);
    const glm::dvec3 d = glm::dvec3(corner) - _p;
    _z0 = glm::dot(d, _z);
    if (_z0 > 0.0) {
        _z = -_z;
        _z0 = -_z0;
    }
    if (!(std::abs(_z0) > 1e-9 * (exl + eyl))) return;  // p in the plane
    _x0 = glm::dot(d, _x);
    _y0 = glm::dot(d, _y);
    _x1 = _x0 + exl;
    _y1 = _y0 + eyl;
    // The four corners and the normals of the planes through p and each edge.
    const glm::dvec3 v00(_x0, _y0, _z0), v01(_x0, _y1, _z0), v10(_x1, _y0, _z0), v11(_x1, _y1, _z0);
    const glm::dvec3 n0 = glm::normalize(glm::cross(v00, v10)), n1 = glm::normalize(glm::cross(v10, v11));
    const glm::dvec3 n2 = glm::normalize(glm::cross(v11, v01)), n3 = glm::normalize(glm::cross(v01, v00));
    // Interior angles, and the solid angle as their sum minus 2 pi (Girard).
    auto angle = [](const glm::dvec3& a, const glm::dvec3& b) { return std::acos(std::clamp(-glm::dot(a, b), -1.0, 1.0)); };
    const double g0 = angle(n0, n1), g1 = angle(n1, n2), g2 = angle(n2, n3), g3 = angle(n3, n0);
    _b0 = n0.z;
    _b1 = n2.z;
    _k = kTwoPi - g2 - g3;
    _solidAngle = g0 + g1 - _k;
    _valid = _solidAngle > 0.0 && std::isfinite(_solidAngle);
}

glm::vec3 SphericalRectangle::sample(float u, float v) const {
    // Algorithm 1: the x coordinate from the area fraction u of the solid angle, then y from v
    // uniform in the height of the spherical segment at that x.
    const double au = double(u) * _solidAngle + _k;
    const double fu = (std::cos(au) * _b0 - _b1) / std::sin(au);
    double cu = (fu > 0.0 ? 1.0 : -1.0) / std::sqrt(fu * fu + _b0 * _b0);
    cu = std::clamp(cu, -1.0, 1.0);
    double xu = -(cu * _z0) / std::max(std::sqrt(1.0 - cu * cu), 1e-300);
    xu = std::clamp(xu, _x0, _x1);
    const double dd = std::sqrt(xu * xu + _z0 * _z0);
    const double h0 = _y0 / std::sqrt(dd * dd + _y0 * _y0), h1 = _y1 / std::sqrt(dd * dd + _y1 * _y1);
    const double hv = h0 + double(v) * (h1 - h0), hv2 = hv * hv;
    double yv = hv2 < 1.0 - 1e-12 ? (hv * dd) / std::sqrt(1.0 - hv2) : _y1;
    yv = std::clamp(yv, _y0, _y1);
    return glm::vec3(_p + xu * _x + yv * _y + _z0 * _z);
}

}  // namespace principled::embree
