// SPDX-License-Identifier: Apache-2.0
// Dome textures that are not lat-long maps (UsdLux DomeLight texture:format mirroredBall and
// angular), resampled into the lat-long layout the renderer samples and looks up.
#pragma once

#include <optional>
#include <string_view>

#include <glm/glm.hpp>

#include "delegate/sceneData.h"

namespace principled::embree {

enum class DomeFormat { LatLong, MirroredBall, Angular };

/// The format a texture:format token names ("automatic" and "latlong": LatLong); nullopt for
/// the ones not supported (cubeMapVerticalCross, unknown tokens).
std::optional<DomeFormat> domeFormatFromToken(std::string_view token);

/// Where the dome direction d (unit, the dome's frame) lies in a mirroredBall or angular
/// image: (u, v) in [0, 1]^2, u to the right, v down from the top row. Both put +Z (the
/// lat-long map's centre, OpenEXR's longitude 0) at the image centre and +Y up, -Z on the
/// rim. mirroredBall: the orthographic image of a mirror sphere seen from +Z (the point whose
/// normal halves d and +Z). angular: the distance from the centre is the angle to +Z over pi
/// (Debevec 1998, "Rendering Synthetic Objects into Real Scenes", the angular map).
glm::vec2 domeImagePosition(DomeFormat format, const glm::vec3& d);

/// A lat-long map of 2N x N texels (N = sqrt of the source's texel count, at most 4096) whose
/// texels are bilinear lookups
/// of `src` (a mirroredBall or angular image) at their centres' directions. Sampling
/// distributions are not prepared; the mean texel is set.
EnvironmentMap resampleToLatLong(const EnvironmentMap& src, DomeFormat format);

}  // namespace principled::embree
