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

namespace principled::bsdf {

struct LobeSample {
    glm::vec3 wi{0.0f};
    glm::vec3 f{0.0f};  ///< f |cos| (delta: throughput weight times pdf)
    float pdf = 0.0f;   ///< solid-angle pdf (delta: discrete probability inside the lobe)
    bool delta = false;
};

}  // namespace principled::bsdf
