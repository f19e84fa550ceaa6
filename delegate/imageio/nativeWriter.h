// SPDX-License-Identifier: Apache-2.0
// The two output formats `principled render` writes, encoded here with zlib only, so writing
// the image does not load OpenImageIO (libprincipled_oiio.so, ~0.25 s of CPU to load; see
// imageIO.h). Readers (OpenImageIO, OpenEXR, libpng) see ordinary files.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace principled::imageio {

/// A scanline OpenEXR 2 file of 32-bit float channels, ZIP-compressed in blocks of 16 lines
/// (the layout OpenEXR's ZIP_COMPRESSION uses). `pixels` holds names.size() floats per pixel,
/// interleaved, top row first; channels are stored sorted by name, as OpenEXR requires.
bool writeExrFloat(const std::string& path, int width, int height,
                   const std::vector<std::string>& names, const float* pixels, std::string* error);

/// An 8-bit PNG of 3 (RGB) or 4 (RGBA) channels, interleaved, top row first.
bool writePng8(const std::string& path, int width, int height, int channels,
               const uint8_t* pixels, std::string* error);

}  // namespace principled::imageio
