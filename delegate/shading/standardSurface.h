// SPDX-License-Identifier: Apache-2.0
// StandardSurfaceParams: the inputs of one Autodesk Standard Surface node (MaterialX
// ND_standard_surface_surfaceshader) as values, and their mapping onto the principled inputs.
#pragma once

#include <glm/glm.hpp>
#include <string>

#include "delegate/hd/token.h"
#include "delegate/shading/previewSurfaceParams.h"

namespace principled::shading {

/// The Standard Surface inputs the principled model can use, with the defaults of version 1.0.1
/// (Autodesk Standard Surface 2021; MaterialX 1.39 ND_standard_surface_surfaceshader).
/// Version 1.0.0 (ND_standard_surface_surfaceshader_100, and MaterialX 1.38's default) differs
/// only in base 0.8 and base_color 1.
struct StandardSurfaceParams {
    float base = 1.0f;
    glm::vec3 baseColor{0.8f};
    float metalness = 0.0f;
    float specular = 1.0f;
    glm::vec3 specularColor{1.0f};
    float specularRoughness = 0.2f;
    float specularIor = 1.5f;
    float specularAnisotropy = 0.0f;
    float transmission = 0.0f;
    float subsurface = 0.0f;
    float sheen = 0.0f;
    glm::vec3 sheenColor{1.0f};
    float coat = 0.0f;
    float coatRoughness = 0.1f;
    float emission = 0.0f;
    glm::vec3 emissionColor{1.0f};
    glm::vec3 opacity{1.0f};
    bool thinWalled = false;

    /// The defaults of node `id` (1.0.0 for the "_100" definition, else 1.0.1).
    static StandardSurfaceParams defaults(const hd::Token& id);
    /// Sets input `name` (Standard Surface spelling) from v (`count` components; a scalar feeding
    /// a colour is splatted). False when the name is not one of the inputs above.
    bool set(const std::string& name, const glm::vec4& v, int count);
};

/// True for the Standard Surface node definitions (1.0.1 and 1.0.0).
bool isStandardSurface(const hd::Token& id);

/// Maps Standard Surface values onto UsdPreviewSurface plus the Disney extras
/// (docs/materials.md): the result goes through mapPreviewSurface() like any other material.
PreviewSurfaceParams mapStandardSurface(const StandardSurfaceParams& s);

/// Disney `specular` per unit of the Standard Surface `specular` weight: the F0 of specular_IOR
/// over 0.08, times the luminance of specular_color (a textured weight is multiplied by it).
float disneySpecularPerWeight(const StandardSurfaceParams& s);

/// Disney `sheen` per unit of the Standard Surface `sheen` weight: the luminance of sheen_color.
float disneySheenPerWeight(const StandardSurfaceParams& s);

/// Rec. 709 luminance of a linear colour.
float luminance(const glm::vec3& c);

}  // namespace principled::shading
