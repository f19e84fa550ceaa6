// SPDX-License-Identifier: Apache-2.0
// UsdRender: the camera and resolution a stage asks to be rendered with.
#pragma once

#include <string>
#include <vector>

namespace principled::usd {
class Stage;
}

namespace principled::adapter {

/// What the stage's UsdRenderSettings prim says about the image: the prim named by the root
/// layer's `renderSettingsPrimPath` metadata, else the first RenderSettings prim in namespace
/// order. Its first RenderProduct's `camera` and `resolution` win over the settings' own, as
/// UsdRender products override their settings; a settings prim without a resolution gives the
/// schema's fallback, 2048 x 1080. Empty camera: not authored; zero size: no settings prim.
/// Inactive, undefined or abstract prims are not used. pixelAspectRatio,
/// aspectRatioConformPolicy and dataWindowNDC are warned about and not applied.
struct StageRenderSettings {
    std::string prim;    ///< the RenderSettings prim used ("" when none)
    std::string camera;  ///< camera prim path
    int width = 0, height = 0;
    std::vector<std::string> warnings;  ///< "path: message"
};
StageRenderSettings readRenderSettings(const usd::Stage& stage);

}  // namespace principled::adapter
