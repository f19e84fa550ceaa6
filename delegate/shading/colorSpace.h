// SPDX-License-Identifier: Apache-2.0
// Colour-space decoding applied to texture lookups (UsdUVTexture sourceColorSpace).
#pragma once

#include <cmath>

namespace principled::shading {

/// The sRGB electro-optical transfer function: encoded [0,1] value -> linear.
inline float srgbToLinear(float c) {
    // IEC 61966-2-1:1999, sRGB EOTF: linear segment below 0.04045, 2.4 power above.
    return c <= 0.04045f ? c * (1.0f / 12.92f) : std::pow((c + 0.055f) * (1.0f / 1.055f), 2.4f);
}

/// The inverse of srgbToLinear (used by tests to author exact texel values).
inline float linearToSrgb(float l) {
    // IEC 61966-2-1:1999, inverse EOTF.
    return l <= 0.0031308f ? l * 12.92f : 1.055f * std::pow(l, 1.0f / 2.4f) - 0.055f;
}

}  // namespace principled::shading
