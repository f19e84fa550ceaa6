// SPDX-License-Identifier: Apache-2.0
// ShadedMaterial: what a material evaluates to at one shading point.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>

#include "bsdf/bsdf.h"
#include "delegate/hd/token.h"

namespace principled::shading {

/// How opacity < 1 is rendered (UsdPreviewSurface opacityMode, MaterialX#2796).
enum class OpacityMode : uint8_t {
    Transparent,  ///< the spec's fallback: zero opacity still gets specular ("clear glass")
    Presence,     ///< zero opacity means no surface at all; partial opacity scales everything
};

/// The texture coordinates a normal map is looked up with: the primvar they derive from and
/// d st / d primvar along the graph (UsdTransform2d's linear part). The map's x and y follow
/// the surface's dP/ds and dP/dt in those coordinates (MaterialProgram::compile finds them).
struct NormalMapUv {
    hd::Token primvar;
    glm::mat2 jacobian{1.0f};
};

/// The evaluated material. Every field is finite and inside its valid range.
struct ShadedMaterial {
    bsdf::MaterialParams params;
    glm::vec3 emission{0.0f};       ///< added radiance, >= 0
    float opacity = 1.0f;           ///< [0,1]
    float opacityThreshold = 0.0f;  ///< [0,1]; > 0 makes opacity a cutout
    OpacityMode opacityMode = OpacityMode::Transparent;
    /// Specular workflow (useSpecularWorkflow = 1): F0 colour, edge white, no metal. Also
    /// approximated in params.specular/specularTint for BSDFs without an explicit F0.
    bool specularWorkflow = false;
    glm::vec3 specularColor{0.0f};  ///< [0,1]
    /// Normal input in tangent space (z along the geometric/shading normal), unit length. The
    /// integrator builds the tangent frame; hasNormalMap is false when it is the constant +z.
    bool hasNormalMap = false;
    glm::vec3 tangentNormal{0.0f, 0.0f, 1.0f};
    /// Owned by the material's program (which outlives shading); null: a constant normal input,
    /// or no primvar behind the map (the integrator then uses "st").
    const NormalMapUv* normalMapUv = nullptr;

    /// opacityMode "transparent" without a cutout threshold: the surface reflects at full
    /// specular strength however low its opacity, and lets (1 - opacity) of the light through
    /// unchanged; params.diffuseScale carries the opacity. Else presence() decides.
    bool keepsSpecular() const {
        return opacityMode == OpacityMode::Transparent && !(opacityThreshold > 0.0f) && opacity < 1.0f;
    }

    /// Fraction of hits that see the surface: with a threshold, 0 below it and 1 at or above
    /// it (an alpha cutout); without, the opacity itself (for stochastic transparency).
    float presence() const {
        if (opacityThreshold > 0.0f) return opacity < opacityThreshold ? 0.0f : 1.0f;
        return opacity;
    }
};

}  // namespace principled::shading
