// SPDX-License-Identifier: Apache-2.0
// Blackbody colour for UsdLux colorTemperature.
#pragma once

#include <glm/glm.hpp>

namespace principled::embree {

/// Linear Rec.709 colour of a blackbody at `kelvin` (clamped to [1000, 25000] K), scaled to
/// luminance Y = 1 so that enabling a colour temperature tints a light without changing its
/// brightness. Chromaticity from Kang et al. 2002, "Design of Advanced Color Temperature
/// Control System for HDTV Applications", eq. 1-2 (cubic spline fit of the Planckian locus).
glm::vec3 blackbodyColor(float kelvin);

}  // namespace principled::embree
