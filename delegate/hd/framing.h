// SPDX-License-Identifier: Apache-2.0
// Framing: how an image frames its camera (UsdRender's conform policy, pixel aspect ratio and
// data window), shared by the render pass state, the camera and the scene adapter.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include <glm/glm.hpp>

namespace principled::hd {

/// How an image frames a camera (UsdRenderSettingsBase: aspectRatioConformPolicy,
/// pixelAspectRatio, dataWindowNDC; Hydra's CameraUtilFraming and conform window policy).
struct Framing {
    enum class Conform : uint8_t {
        ExpandAperture,          ///< grow the aperture to the image's aspect (the fallback; all of it seen)
        CropAperture,            ///< shrink it to the image's aspect (the image is filled)
        AdjustApertureWidth,     ///< keep the height, set the width
        AdjustApertureHeight,    ///< keep the width, set the height
        AdjustPixelAspectRatio,  ///< the aperture as it is: pixels take its aspect
    };
    Conform conform = Conform::ExpandAperture;
    float pixelAspectRatio = 1.0f;        ///< pixel width / height (ignored by AdjustPixelAspectRatio)
    glm::vec4 dataWindowNDC{0, 0, 1, 1};  ///< (xmin, ymin, xmax, ymax) of the conformed window, (0, 0) bottom left

    /// The pixels whose centres lie in the data window, clipped to the image: {x0, y0, x1, y1},
    /// half open, rows counted from the top. The window's edges are half open too (xmin <= x <
    /// xmax), so windows that tile the unit square render every pixel once.
    glm::ivec4 pixelRect(int width, int height) const;
    bool operator==(const Framing&) const = default;

    /// Pixel aspect ratios the renderer accepts: 1e-4 to 1e4 (beyond them the window's far side
    /// overflows or collapses in float).
    static bool validPixelAspectRatio(double r) { return r >= 1e-4 && r <= 1e4; }
    /// The policy a UsdRender aspectRatioConformPolicy token names; nullopt for any other text.
    static std::optional<Conform> conformFromToken(std::string_view token);
    /// The names conformFromToken accepts, for messages.
    static constexpr const char* kConformTokens =
        "expandAperture, cropAperture, adjustApertureWidth, adjustApertureHeight or adjustPixelAspectRatio";
};

}  // namespace principled::hd
