// SPDX-License-Identifier: Apache-2.0
// PreviewSurfaceParams: the inputs of one UsdPreviewSurface (plus the Disney inputs it cannot
// express) as values, and the mapping of those values onto the principled parameters.
#pragma once

#include <glm/glm.hpp>
#include <optional>

#include "delegate/shading/shadedMaterial.h"

namespace principled::shading {

/// UsdPreviewSurface inputs with the spec 2.5 fallbacks (reference/hydra.md §4.1).
struct PreviewSurfaceParams {
    glm::vec3 diffuseColor{0.18f};
    glm::vec3 emissiveColor{0.0f};
    bool useSpecularWorkflow = false;
    glm::vec3 specularColor{0.0f};
    float metallic = 0.0f;
    float roughness = 0.5f;
    float clearcoat = 0.0f;
    float clearcoatRoughness = 0.01f;
    float opacity = 1.0f;
    float opacityThreshold = 0.0f;
    OpacityMode opacityMode = OpacityMode::Transparent;
    float ior = 1.5f;
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    bool normalVaries = false;  ///< the normal input is connected (a normal map)
    bool thin = false;          ///< thin-walled transmission (Standard Surface thin_walled)
    // Disney inputs read from the same shader under MaterialX Disney BSDF names; unset ones
    // keep the values derived from the UsdPreviewSurface inputs.
    std::optional<float> subsurface, specular, specularTint, anisotropic, sheen, sheenTint,
        clearcoatGloss, specTrans;
};

/// Maps UsdPreviewSurface values onto the principled model (DESIGN.md §4, docs/materials.md)
/// and clamps every output to its range; NaN and Inf never pass. No allocation.
ShadedMaterial mapPreviewSurface(const PreviewSurfaceParams& in);

/// Disney "specular" from an index of refraction: ((ior-1)/(ior+1))^2 / 0.08, clamped to
/// [0, bsdf::kMaxSpecular] (Burley's [0, 1] ends at ior 1.8); 0.5 for a non-positive or
/// non-finite ior.
float specularFromIor(float ior);

}  // namespace principled::shading
