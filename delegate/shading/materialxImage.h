// SPDX-License-Identifier: Apache-2.0
// MaterialX image nodes (ND_image_*, ND_tiledimage_*) resolved onto the UsdUVTexture lookup.
#pragma once

#include <string>
#include <vector>

#include "delegate/hd/materialNetwork.h"
#include "delegate/shading/textureCache.h"
#include "delegate/shading/transform2d.h"
#include "delegate/shading/uvTexture.h"

namespace principled::shading {

/// Resolves an ND_image_* or ND_tiledimage_* node for lookups: `file`, `default` (the value
/// when the file is missing), `uaddressmode`/`vaddressmode` (periodic | clamp | mirror |
/// constant), `filtertype`, and, for color3/color4 images, the file's colour space from the
/// "colorSpace:file" parameter (srgb_texture decodes sRGB; lin_rec709, lin_srgb, raw are
/// linear; absent: as UsdUVTexture auto); float and vector images are always read raw.
/// What cannot be honoured (constant addressing with a non-zero default, closest
/// filtering, unknown colour spaces) is appended to *notes.
UvTexture resolveMaterialXImage(const hd::MaterialNode& node, TextureCache& cache,
                                std::vector<std::string>* notes);

/// The texture-coordinate transform of ND_tiledimage_*: (uv * uvtiling - uvoffset) /
/// realworldimagesize * realworldtilesize (MaterialX stdlib NG_tiledimage_*).
Transform2d tiledImageTransform(const hd::MaterialNode& node);

/// The transform of ND_place2d_vector2 (MaterialX stdlib NG_place2d_vector2): with R the
/// clockwise rotation by `rotate` degrees, operationorder 0 (SRT) gives
/// R((uv - pivot) / scale) - offset + pivot, 1 (TRS) gives R(uv - pivot - offset) / scale + pivot.
/// A zero scale component reads as 1; connected inputs are the caller's business.
Transform2d place2dTransform(const hd::MaterialNode& node);

}  // namespace principled::shading
