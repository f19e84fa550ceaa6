// SPDX-License-Identifier: Apache-2.0
// UsdRender: the camera and resolution a stage asks to be rendered with.
#pragma once

#include <string>
#include <vector>

#include "delegate/hd/framing.h"

namespace principled::usd {
class Stage;
}

namespace principled::adapter {

/// What the stage's UsdRenderSettings prim says about the image: the prim named by the root
/// layer's `renderSettingsPrimPath` metadata, else the first RenderSettings prim in namespace
/// order. Its first RenderProduct's `camera` and `resolution` win over the settings' own, as
/// UsdRender products override their settings; a settings prim without a resolution gives the
/// schema's fallback, 2048 x 1080. Empty camera: not authored; zero size: no settings prim.
/// Inactive, undefined or abstract prims are not used. The framing (pixelAspectRatio,
/// aspectRatioConformPolicy, dataWindowNDC) is read the same way, the product's attributes
/// over the settings'; a data window beyond the unit square (overscan) is clipped to it.
/// includedPurposes, materialBindingPurposes and disableDepthOfField are read; RenderVars
/// (orderedVars), products after the first and motion-blur settings are reported as not used.
struct StageRenderSettings {
    std::string prim;    ///< the RenderSettings prim used ("" when none)
    std::string camera;  ///< camera prim path
    int width = 0, height = 0;
    hd::Framing framing;  ///< the schema's fallbacks when no prim authors them
    /// includedPurposes, materialBindingPurposes (the schema's fallbacks when not authored) and
    /// disableDepthOfField of the settings prim.
    std::vector<std::string> includedPurposes{"default", "render"};
    std::vector<std::string> materialBindingPurposes{"full", ""};
    bool disableDepthOfField = false;
    std::vector<std::string> warnings;  ///< "path: message"
};
StageRenderSettings readRenderSettings(const usd::Stage& stage);

}  // namespace principled::adapter
