// SPDX-License-Identifier: Apache-2.0
// Local shading frame helpers: z is the shading normal, directions point away from the surface.
#pragma once

#include <algorithm>
#include <cmath>

#include <glm/glm.hpp>

namespace principled::bsdf {

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float kInvPi = 1.0f / kPi;
inline constexpr float kTwoPi = 2.0f * kPi;

inline float cosTheta(const glm::vec3& w) { return w.z; }
inline float absCosTheta(const glm::vec3& w) { return std::abs(w.z); }
inline float safeSqrt(float x) { return std::sqrt(std::max(x, 0.0f)); }
inline float sqr(float x) { return x * x; }
inline glm::vec3 flipZ(const glm::vec3& w) { return {w.x, w.y, -w.z}; }

/// Mirror of w about the unit vector n (both pointing away from the surface).
inline glm::vec3 reflect(const glm::vec3& w, const glm::vec3& n) {
    return 2.0f * glm::dot(w, n) * n - w;
}

/// Snell refraction of w about the microfacet normal m (w·m > 0) with eta = n_t / n_i.
/// Returns false on total internal reflection.
inline bool refract(const glm::vec3& w, const glm::vec3& m, float eta, glm::vec3* out) {
    // Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces", eq. 40.
    float cosI = glm::dot(w, m);
    float sin2T = (1.0f - cosI * cosI) / (eta * eta);
    if (sin2T >= 1.0f) return false;
    float cosT = std::sqrt(1.0f - sin2T);
    *out = -w / eta + (cosI / eta - cosT) * m;
    return true;
}

/// Luminance weights of the Disney reference code (Burley 2012, wdas/brdf disney.brdf, Cdlum).
inline float luminance(const glm::vec3& c) { return 0.3f * c.x + 0.6f * c.y + 0.1f * c.z; }
inline float maxComponent(const glm::vec3& c) { return std::max(c.x, std::max(c.y, c.z)); }

/// Smallest |cos theta_o| the lobes ever see: views closer to the horizon (or below it, from a
/// shading normal that disagrees with the geometry) are bent back to this elevation.
inline constexpr float kMinCosWo = 1e-4f;  // 1e-4: ~0.006 degrees, keeps 1/cos finite in float

/// Bends a view direction so that its z (on the side given by sign) is at least kMinCosWo.
/// Straight-down views (no tangent component) are mirrored to the normal.
inline glm::vec3 bendToHemisphere(const glm::vec3& wo, float sign) {
    if (wo.z * sign >= kMinCosWo) return wo;
    float t = std::sqrt(wo.x * wo.x + wo.y * wo.y);
    if (t < 1e-6f) return {0.0f, 0.0f, sign};  // 1e-6: tangent part lost in float noise
    float s = std::sqrt(1.0f - kMinCosWo * kMinCosWo) / t;
    return {wo.x * s, wo.y * s, kMinCosWo * sign};
}

/// An orthonormal basis around a unit normal, for callers converting world to local.
struct Frame {
    glm::vec3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};

    /// Duff et al. 2017, "Building an Orthonormal Basis, Revisited", JCGT 6(1), listing 3.
    static Frame fromZ(const glm::vec3& n) {
        float s = std::copysign(1.0f, n.z);
        float a = -1.0f / (s + n.z);
        float b = n.x * n.y * a;
        Frame f;
        f.x = {1.0f + s * n.x * n.x * a, s * b, -s * n.x};
        f.y = {b, s + n.y * n.y * a, -n.y};
        f.z = n;
        return f;
    }
    /// A frame from a normal and a (not necessarily orthogonal) tangent for anisotropy.
    static Frame fromZX(const glm::vec3& n, const glm::vec3& t) {
        glm::vec3 x = t - glm::dot(t, n) * n;
        float l = glm::length(x);
        if (!(l > 1e-6f)) return fromZ(n);
        Frame f;
        f.z = n;
        f.x = x / l;
        f.y = glm::cross(n, f.x);
        return f;
    }
    glm::vec3 toLocal(const glm::vec3& v) const {
        return {glm::dot(v, x), glm::dot(v, y), glm::dot(v, z)};
    }
    glm::vec3 toWorld(const glm::vec3& v) const { return v.x * x + v.y * y + v.z * z; }
};

}  // namespace principled::bsdf
