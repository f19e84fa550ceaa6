// SPDX-License-Identifier: Apache-2.0
// What a single lobe's sample() returns. Every lobe type (lambert.h, disneyDiffuse.h, sheen.h,
// specular.h, clearcoat.h, transmission.h) has the same three members, all in the local frame:
//   glm::vec3 eval(wo, wi)              f(wo, wi) |cos theta_i|
//   float pdf(wo, wi)                   solid-angle density of sample() producing wi
//   std::optional<LobeSample> sample(wo, u, uSub)
// plus selectionWeight(wo), a cheap albedo estimate that depends on wo only.
#pragma once

#include <optional>

#include <glm/glm.hpp>

#include "bsdf/warp.h"

namespace principled::bsdf {

struct LobeSample {
    glm::vec3 wi{0.0f};
    glm::vec3 f{0.0f};  ///< f |cos| (delta: throughput weight times pdf)
    float pdf = 0.0f;   ///< solid-angle pdf (delta: discrete probability inside the lobe)
    bool delta = false;
};

/// The pdf and sample() of a lobe that draws wi from the cosine-weighted upper hemisphere
/// (Malley's method, warp.h) whatever wo is, and is zero for views below the surface: the
/// shared half of Lambert and DisneyDiffuse, which differ only in eval().
inline float cosineLobePdf(const glm::vec3& wo, const glm::vec3& wi) {
    return wo.z > 0.0f ? cosineHemispherePdf(wi) : 0.0f;
}
template <typename Lobe>
std::optional<LobeSample> sampleCosineLobe(const Lobe& lobe, const glm::vec3& wo, const glm::vec2& u) {
    if (wo.z <= 0.0f) return std::nullopt;
    glm::vec3 wi = squareToCosineHemisphere(u);
    if (wi.z <= 0.0f) return std::nullopt;
    return LobeSample{wi, lobe.eval(wo, wi), cosineLobePdf(wo, wi), false};
}

}  // namespace principled::bsdf
