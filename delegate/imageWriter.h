// SPDX-License-Identifier: Apache-2.0
// Image output: float EXR (linear, ZIP) and 8-bit PNG (sRGB transfer), encoded by
// delegate/imageio/nativeWriter.cpp with OpenEXRCore and libpng, without OpenImageIO
// (PRINCIPLED_IMAGE_WRITER=oiio: through the image I/O backend, delegate/imageio/imageIO.h).
#pragma once

#include <string>
#include <vector>

namespace principled::embree {

/// One named channel group of an image, e.g. {"color", {"R","G","B","A"}, data}.
struct ImageLayer {
    std::string name;                 ///< EXR layer prefix; empty for the main RGBA
    std::vector<std::string> channels;
    const float* pixels = nullptr;    ///< width*height*channels.size() floats, top row first
};

/// Writes layers to path: ".exr" keeps every layer as float channels ("layer.R"); ".png" writes
/// the first layer's RGB with the sRGB transfer function, clamped to [0,1] (no alpha).
/// Returns false with *error naming the file and the reason.
/// pixelAspectRatio: the pixels' width / height, recorded in an EXR header.
bool writeImage(const std::string& path, int width, int height,
                const std::vector<ImageLayer>& layers, std::string* error, float pixelAspectRatio = 1.0f);

/// The sRGB transfer function (IEC 61966-2-1) from linear [0,1].
float linearToSrgb(float v);

}  // namespace principled::embree
