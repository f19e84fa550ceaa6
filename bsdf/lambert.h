// SPDX-License-Identifier: Apache-2.0
// Lambertian diffuse (the UE4 diffuse, Karis 2013), cosine-sampled.
#pragma once

#include "bsdf/lobe.h"
#include "bsdf/warp.h"

namespace principled::bsdf {

struct Lambert {
    glm::vec3 color{0.0f};

    /// Lambert 1760; Karis 2013, "Real Shading in Unreal Engine 4", eq. 1: f = c_diff / pi.
    glm::vec3 eval(const glm::vec3& wo, const glm::vec3& wi) const {
        if (wo.z <= 0.0f || wi.z <= 0.0f) return glm::vec3(0.0f);
        return color * (kInvPi * wi.z);
    }
    float pdf(const glm::vec3& wo, const glm::vec3& wi) const { return cosineLobePdf(wo, wi); }
    std::optional<LobeSample> sample(const glm::vec3& wo, const glm::vec2& u, float) const {
        return sampleCosineLobe(*this, wo, u);
    }
    float selectionWeight(const glm::vec3&) const { return luminance(color); }
};

}  // namespace principled::bsdf
