// SPDX-License-Identifier: Apache-2.0
#include "delegate/hd/framing.h"

#include <algorithm>
#include <cmath>

namespace principled::hd {

std::optional<Framing::Conform> Framing::conformFromToken(std::string_view token) {
    if (token == "expandAperture") return Conform::ExpandAperture;
    if (token == "cropAperture") return Conform::CropAperture;
    if (token == "adjustApertureWidth") return Conform::AdjustApertureWidth;
    if (token == "adjustApertureHeight") return Conform::AdjustApertureHeight;
    if (token == "adjustPixelAspectRatio") return Conform::AdjustPixelAspectRatio;
    return std::nullopt;
}

glm::ivec4 Framing::pixelRect(int width, int height) const {
    // Pixel (x, y), y counted from the top, has its centre at NDC ((x + 0.5) / W, 1 - (y + 0.5) / H);
    // it is in when xmin <= cx < xmax and ymin <= cy < ymax.
    const glm::vec4& d = dataWindowNDC;
    auto clampTo = [](double v, int n) { return int(std::clamp(v, 0.0, double(n))); };
    const int x0 = clampTo(std::ceil(double(d.x) * width - 0.5), width);
    const int x1 = clampTo(std::ceil(double(d.z) * width - 0.5), width);
    const int y0 = clampTo(std::floor((1.0 - double(d.w)) * height - 0.5) + 1.0, height);
    const int y1 = clampTo(std::floor((1.0 - double(d.y)) * height - 0.5) + 1.0, height);
    return {x0, y0, std::max(x0, x1), std::max(y0, y1)};
}

}  // namespace principled::hd
