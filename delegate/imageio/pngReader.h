// SPDX-License-Identifier: Apache-2.0
// PngReader: PNG textures decoded with libpng (already linked for PNG output), so a scene whose
// textures are all PNG never loads the OpenImageIO backend. Gives what OpenImageIO 2.4's PNG
// reader gives a texture read (straight alpha): the same channels and pixel values, and the
// metadata the texture cache's colour rules read.
#pragma once

#include <memory>
#include <string>

#include "delegate/imageio/imageIO.h"

namespace principled::imageio {

/// Opens `path` if it is a PNG file libpng can read the header of; null otherwise (*error says
/// why). Pixels as OpenImageIO reads them: palette -> RGB, tRNS -> an alpha channel, 1/2/4-bit
/// gray -> 8-bit, 16-bit kept; alpha never premultiplied. Spec metadata (as OpenImageIO 2.4
/// reports it): fileFormat "png"; oiio:ColorSpace ("sRGB", or from gAMA "linear" / "Gamma<g>")
/// and oiio:Gamma (1 / gAMA) unless an sRGB chunk is present; ICCProfile:profile_description
/// (the iCCP profile's 'desc' tag); Exif:ColorSpace (eXIf chunk or XMP exif:ColorSpace);
/// photoshop:ICCProfile (XMP); every text chunk by its key (Description, Author and Title as
/// ImageDescription, Artist and DocumentName). read() decodes once; a libpng error there
/// returns false.
std::unique_ptr<ImageReader> openPng(const std::string& path, std::string* error);

}  // namespace principled::imageio
