// SPDX-License-Identifier: Apache-2.0
#include "delegate/sphericalTriangle.h"

#include <algorithm>
#include <cmath>

namespace principled::embree {

namespace {
using dvec3 = glm::dvec3;
}  // namespace

bool makeSphericalTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                           SphericalTriangle* out) {
    glm::vec3 A = a - p, B = b - p, C = c - p;
    float la = glm::length(A), lb = glm::length(B), lc = glm::length(C);
    out->tripleProduct = out->solidAngle = 0.0f;
    if (!(la > 0.0f) || !(lb > 0.0f) || !(lc > 0.0f)) {
        out->A = out->B = out->C = glm::vec3(0.0f);
        return false;
    }
    A /= la, B /= lb, C /= lc;
    out->A = A, out->B = B, out->C = C;
    // Van Oosterom & Strackee 1983, eq. 8 over unit vectors; atan2 keeps the half angle in
    // [0, pi). The triple product of nearly parallel vectors cancels: it and the dots are summed
    // in double (a few multiplies), the arctangent is taken in float.
    dvec3 dA(A), dB(B), dC(C);
    double tp = std::abs(glm::dot(dA, glm::cross(dB, dC)));
    double den = 1.0 + glm::dot(dA, dB) + glm::dot(dA, dC) + glm::dot(dB, dC);
    float omega = 2.0f * std::atan2(float(tp), float(den));
    if (!std::isfinite(omega)) return false;
    out->tripleProduct = float(tp);
    out->solidAngle = std::max(0.0f, omega);
    return out->tripleProduct > 0.0f && out->solidAngle > 0.0f;
}

float triangleSolidAngle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
    SphericalTriangle t;
    makeSphericalTriangle(p, a, b, c, &t);
    return t.solidAngle;
}

bool sampleSphericalTriangle(const SphericalTriangle& t, const glm::vec2& u, glm::vec3* dir) {
    if (!(t.tripleProduct > 0.0f) || !(t.solidAngle > 0.0f)) return false;
    // In double: for a small triangle the cosines below are all close to 1 and their float
    // differences would put samples off the triangle by ~1e-4 of its size. Double arithmetic
    // costs the same as float; only the one sin/cos pair is a double libm call. The float unit
    // vectors are off unit length by ~4e-8, which is as much as 1 - cos of a short arc makes
    // them: normalised again in double by one Newton step for 1/sqrt(|v|^2) about 1,
    // v (3 - |v|^2) / 2 (relative error ~1e-15 from 4e-8; no square root or division).
    auto renormalise = [](const glm::vec3& v) {
        dvec3 d(v);
        return d * (1.5 - 0.5 * glm::dot(d, d));
    };
    const dvec3 A = renormalise(t.A), B = renormalise(t.B), C = renormalise(t.C);
    // The interior angle alpha at A is the angle between the tangents of arcs AB and AC at A:
    // B and C with their components along A removed. |Bt x Ct| = |A . (B x C)| (Bt, Ct _|_ A).
    double cosC = glm::dot(A, B);  // the side opposite C
    dvec3 Bt = B - cosC * A, Ct = C - glm::dot(A, C) * A;
    double lBt = glm::length(Bt), lCt = glm::length(Ct);
    if (!(lBt > 0.0) || !(lCt > 0.0)) return false;
    double inv = 1.0 / (lBt * lCt);
    double cosAlpha = glm::dot(Bt, Ct) * inv, sinAlpha = std::abs(glm::dot(A, glm::cross(B, C))) * inv;
    // Arvo 1995, figure 2: the sub-triangle A B C' of area u.x * Omega; s, c = sin, cos of
    // (areaHat - alpha) by the angle-difference identities from one sin/cos of areaHat.
    double areaHat = double(u.x) * double(t.solidAngle);
    double sA = std::sin(areaHat), cA = std::cos(areaHat);
    double s = sA * cosAlpha - cA * sinAlpha, c = cA * cosAlpha + sA * sinAlpha;
    double uu = c - cosAlpha;
    double vv = s + sinAlpha * cosC;
    double den = (vv * s + uu * c) * sinAlpha;
    double q = den != 0.0 ? ((vv * c - uu * s) * cosAlpha - vv) / den : 1.0;  // cos of arc A C'
    q = std::clamp(q, -1.0, 1.0);
    dvec3 Chat = q * A + std::sqrt(std::max(0.0, 1.0 - q * q)) * (Ct / lCt);
    // ... then a point on the arc from B to C' with cos(theta) uniform in [C'.B, 1]. 1 - C'.B is
    // taken as |C' - B|^2 / 2 (no cancellation for short arcs), and sin(theta) as
    // sqrt((1 - z)(1 + z)).
    dvec3 dCB = Chat - B;
    double h = 0.5 * glm::dot(dCB, dCB);
    double oneMinusZ = double(u.y) * h;
    double z = 1.0 - oneMinusZ;
    double sinTheta = std::sqrt(std::max(0.0, oneMinusZ * (2.0 - oneMinusZ)));
    dvec3 Ot = Chat - (1.0 - h) * B;  // C' without its component along B
    double lOt = glm::length(Ot);
    // Unit up to rounding: C' is unit and Ot _|_ B, so z^2 + sin^2(theta) = 1.
    dvec3 P = z * B + (lOt > 0.0 ? sinTheta / lOt : 0.0) * Ot;
    if (!std::isfinite(P.x) || !std::isfinite(P.y) || !std::isfinite(P.z)) return false;
    *dir = glm::vec3(P);
    return true;
}

bool sampleSphericalTriangle(const glm::vec3& p, const glm::vec3& a, const glm::vec3& b, const glm::vec3& c,
                             const glm::vec2& u, glm::vec3* dir) {
    SphericalTriangle t;
    if (!makeSphericalTriangle(p, a, b, c, &t)) return false;
    return sampleSphericalTriangle(t, u, dir);
}

}  // namespace principled::embree
