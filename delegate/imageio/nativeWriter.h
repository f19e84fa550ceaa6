// SPDX-License-Identifier: Apache-2.0
// The two output formats `principled render` writes, encoded with OpenEXRCore (OpenEXR's C
// library) and libpng, so writing the image does not load OpenImageIO (libprincipled_oiio.so,
// ~0.25 s of CPU to load; see imageIO.h). Both libraries depend only on zlib and libc/libm
// (docs/performance.md, section 0, for the measured start-up cost).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace principled::imageio {

/// A single-part scanline OpenEXR file of 32-bit float channels, ZIP-compressed (blocks of 16
/// lines); names longer than 31 characters set the long-names flag. `pixels` holds
/// names.size() floats per pixel, interleaved, top row first; OpenEXR stores the channels
/// sorted by name. The header's pixelAspectRatio is `pixelAspectRatio`. False with *error
/// (OpenEXR's message).
bool writeExrFloat(const std::string& path, int width, int height,
                   const std::vector<std::string>& names, const float* pixels, std::string* error,
                   float pixelAspectRatio = 1.0f);

/// An 8-bit PNG of 3 (RGB) or 4 (RGBA, straight alpha) sRGB channels, interleaved, top row
/// first (libpng's simplified API, which also records the sRGB colour space in the file).
bool writePng8(const std::string& path, int width, int height, int channels,
               const uint8_t* pixels, std::string* error);

}  // namespace principled::imageio
