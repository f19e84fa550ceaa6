// SPDX-License-Identifier: Apache-2.0
// The mapping from a UsdPreviewSurface network onto the principled parameters (DESIGN.md §4,
// docs/materials.md). Kept apart from the material sprim so it can be tested alone.
#pragma once

#include <string>
#include <vector>

#include "delegate/hd/materialNetwork.h"
#include "delegate/sceneData.h"

namespace principled::embree {

/// Maps the network's surface shader to a MaterialRecord. Unknown shaders and inputs that
/// cannot be honoured yet are described in *notes (one line each) and fall back to the
/// UsdPreviewSurface defaults.
MaterialRecord mapPreviewSurface(const hd::MaterialNetwork& network, std::vector<std::string>* notes);

/// Disney "specular" from an index of refraction: ((ior-1)/(ior+1))^2 / 0.08, clamped to [0,1]
/// (Mitsuba 3 principled BSDF, the inverse of eta = 2/(1-sqrt(0.08 specular)) - 1).
float specularFromIor(float ior);

}  // namespace principled::embree
