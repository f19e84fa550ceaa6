// SPDX-License-Identifier: Apache-2.0
#include "delegate/sphericalTriangle.h"

#include <algorithm>
#include <cmath>

namespace principled::embree {
namespace {

using dvec3 = glm::dvec3;

// v minus its component along unit w, normalised (zero if v is parallel to w).
dvec3 orthoNormalised(const dvec3& v, const dvec3& w) {
    dvec3 o = v - glm::dot(v, w) * w;
    double l = glm::length(o);
    return l > 0.0 ? o / l : dvec3(0.0);
}

}  // namespace

float triangleSolidAngle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    dvec3 A = dvec3(a) - dvec3(p), B = dvec3(b) - dvec3(p), C = dvec3(c) - dvec3(p);
    double la = glm::length(A), lb = glm::length(B), lc = glm::length(C);
    // Van Oosterom & Strackee 1983, eq. 8.
    double num = std::abs(glm::dot(A, glm::cross(B, C)));
    double den = la * lb * lc + glm::dot(A, B) * lc + glm::dot(A, C) * lb + glm::dot(B, C) * la;
    double omega = 2.0 * std::atan2(num, den);  // atan2 keeps the half angle in [0, pi)
    return float(std::max(0.0, omega));
}

bool sampleSphericalTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                             const glm::vec2& u, glm::vec3* dir) {
    const double kPi = 3.14159265358979323846;
    dvec3 A = dvec3(a) - dvec3(p), B = dvec3(b) - dvec3(p), C = dvec3(c) - dvec3(p);
    double la = glm::length(A), lb = glm::length(B), lc = glm::length(C);
    if (!(la > 0.0) || !(lb > 0.0) || !(lc > 0.0)) return false;
    A /= la, B /= lb, C /= lc;
    // Interior angles from the great-circle planes through each pair of vertices.
    dvec3 nAB = glm::cross(A, B), nBC = glm::cross(B, C), nCA = glm::cross(C, A);
    double lAB = glm::length(nAB), lBC = glm::length(nBC), lCA = glm::length(nCA);
    if (!(lAB > 0.0) || !(lBC > 0.0) || !(lCA > 0.0)) return false;
    nAB /= lAB, nBC /= lBC, nCA /= lCA;
    // Spherical-triangle geometry: the interior angle at a vertex is the angle between the
    // two great circles meeting there.
    double alpha = std::acos(std::clamp(-glm::dot(nAB, nCA), -1.0, 1.0));
    double beta = std::acos(std::clamp(-glm::dot(nAB, nBC), -1.0, 1.0));
    double gamma = std::acos(std::clamp(-glm::dot(nBC, nCA), -1.0, 1.0));
    // Girard's theorem: the area is the angle excess.
    double area = alpha + beta + gamma - kPi;
    if (!(area > 0.0)) return false;
    // Arvo 1995, figure 2: choose the sub-triangle A B C' of area u.x * area ...
    double areaHat = double(u.x) * area;
    double s = std::sin(areaHat - alpha), t = std::cos(areaHat - alpha);
    double cosAlpha = std::cos(alpha), sinAlpha = std::sin(alpha);
    double cosC = glm::dot(A, B);  // the side opposite C
    double uu = t - cosAlpha;
    double vv = s + sinAlpha * cosC;
    double den = (vv * s + uu * t) * sinAlpha;
    double q = den != 0.0 ? ((vv * t - uu * s) * cosAlpha - vv) / den : 1.0;
    q = std::clamp(q, -1.0, 1.0);
    dvec3 Chat = q * A + std::sqrt(std::max(0.0, 1.0 - q * q)) * orthoNormalised(C, A);
    // ... then a point on the arc from B to C' with cos(theta) uniform in [C'.B, 1].
    double z = 1.0 - double(u.y) * (1.0 - glm::dot(Chat, B));
    z = std::clamp(z, -1.0, 1.0);
    dvec3 P = z * B + std::sqrt(std::max(0.0, 1.0 - z * z)) * orthoNormalised(Chat, B);
    double lp = glm::length(P);
    if (!(lp > 0.0) || !std::isfinite(lp)) return false;
    *dir = glm::vec3(P / lp);
    return true;
}

}  // namespace principled::embree
