// SPDX-License-Identifier: Apache-2.0
// The GTR1 ("Berry") distribution of the Disney clearcoat, and sampling from it.
#pragma once

#include "bsdf/frame.h"

namespace principled::bsdf {

struct Gtr1 {
    float alpha = 0.1f;

    /// Burley 2012, "Physically-Based Shading at Disney", appendix B.2, eq. 4 (normalised GTR1):
    /// D = (a^2 - 1) / (pi ln(a^2) (1 + (a^2 - 1) cos^2 theta_h)); 1/pi when a >= 1.
    float D(float cosH) const {
        if (cosH <= 0.0f) return 0.0f;
        if (alpha >= 1.0f) return kInvPi;
        float a2 = alpha * alpha;
        // 1 + (a^2 - 1) c^2 = a^2 c^2 + (1 - c)(1 + c): no cancellation at the peak.
        float t = a2 * cosH * cosH + (1.0f - cosH) * (1.0f + cosH);
        return (a2 - 1.0f) / (kPi * std::log(a2) * t);
    }
    /// D() with pi ln(a^2) precomputed (piLogA2 = kPi * std::log(alpha^2)); bit-identical to D().
    float D(float cosH, float piLogA2) const {
        if (cosH <= 0.0f) return 0.0f;
        if (alpha >= 1.0f) return kInvPi;
        float a2 = alpha * alpha;
        float t = a2 * cosH * cosH + (1.0f - cosH) * (1.0f + cosH);
        return (a2 - 1.0f) / (piLogA2 * t);
    }
    float piLogA2() const { return alpha >= 1.0f ? 0.0f : kPi * std::log(alpha * alpha); }

    /// Burley 2012, appendix B.2, eq. 5: cos^2 theta_h = (1 - a^(2(1-u))) / (1 - a^2),
    /// phi = 2 pi u.y. Density of m: D(m.z) m.z.
    glm::vec3 sample(const glm::vec2& u) const {
        float a2 = alpha * alpha;
        float cos2 = alpha >= 1.0f ? 1.0f - u.x  // uniform cosine-weighted limit (D = 1/pi)
                                   : (1.0f - std::pow(a2, 1.0f - u.x)) / (1.0f - a2);
        float c = safeSqrt(cos2), s = safeSqrt(1.0f - cos2), phi = kTwoPi * u.y;
        return {s * std::cos(phi), s * std::sin(phi), c};
    }
    float pdf(const glm::vec3& m) const { return D(m.z) * std::max(m.z, 0.0f); }
};

}  // namespace principled::bsdf
