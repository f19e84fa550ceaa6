// SPDX-License-Identifier: Apache-2.0
#include "delegate/environmentFormat.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "delegate/lightSampling.h"

namespace principled::embree {

std::optional<DomeFormat> domeFormatFromToken(std::string_view token) {
    if (token.empty() || token == "automatic" || token == "latlong") return DomeFormat::LatLong;
    if (token == "mirroredBall") return DomeFormat::MirroredBall;
    if (token == "angular") return DomeFormat::Angular;
    return std::nullopt;
}

glm::vec2 domeImagePosition(DomeFormat format, const glm::vec3& d) {
    // Disc coordinates (x right, y up) in [-1, 1]^2, then image coordinates.
    glm::vec2 disc(0.0f);
    const float side = std::sqrt(d.x * d.x + d.y * d.y);
    if (format == DomeFormat::MirroredBall) {
        // The sphere's normal n halves d and the view back to the camera (+Z): n = (d + z) / |d + z|,
        // and the orthographic image shows it at (n.x, n.y).
        const glm::vec3 h(d.x, d.y, d.z + 1.0f);
        const float l = std::sqrt(h.x * h.x + h.y * h.y + h.z * h.z);
        if (l > 1e-6f)
            disc = glm::vec2(h.x, h.y) / l;
        else if (side > 0.0f)
            disc = glm::vec2(d.x, d.y) / side;  // straight back: the rim
        else
            disc = glm::vec2(1.0f, 0.0f);
    } else if (format == DomeFormat::Angular) {
        const float angle = std::acos(std::clamp(d.z, -1.0f, 1.0f));  // from +Z
        if (side > 0.0f) disc = glm::vec2(d.x, d.y) * (angle / (3.14159265358979f * side));
        else if (d.z < 0.0f) disc = glm::vec2(1.0f, 0.0f);
    } else {
        return directionToLatLong(d);
    }
    return {0.5f + 0.5f * disc.x, 0.5f - 0.5f * disc.y};
}

namespace {
// Bilinear lookup at (u, v) in [0, 1]^2 (texel centres at (i + 0.5) / n), clamped to the edge.
glm::vec3 bilinear(const EnvironmentMap& m, glm::vec2 uv) {
    const float x = std::clamp(uv.x * float(m.width) - 0.5f, 0.0f, float(m.width - 1));
    const float y = std::clamp(uv.y * float(m.height) - 0.5f, 0.0f, float(m.height - 1));
    const int x0 = int(x), y0 = int(y);
    const int x1 = std::min(x0 + 1, m.width - 1), y1 = std::min(y0 + 1, m.height - 1);
    const float fx = x - float(x0), fy = y - float(y0);
    auto at = [&](int i, int j) { return m.texels[size_t(j) * size_t(m.width) + size_t(i)]; };
    return (1.0f - fy) * ((1.0f - fx) * at(x0, y0) + fx * at(x1, y0)) + fy * ((1.0f - fx) * at(x0, y1) + fx * at(x1, y1));
}
}  // namespace

EnvironmentMap resampleToLatLong(const EnvironmentMap& src, DomeFormat format) {
    EnvironmentMap out;
    // As many texels as the image has, about: N = sqrt(area) rows (a 1 x 4096 image is not a
    // 8192 x 4096 map), at most 4096 (a 8192 x 4096 map, 400 MB).
    const double area = double(std::max(0, src.width)) * double(std::max(0, src.height));
    out.height = int(std::clamp(std::lround(std::sqrt(area)), 1L, 4096L));
    out.width = 2 * out.height;
    out.texels.resize(size_t(out.width) * size_t(out.height));
    if (src.width <= 0 || src.height <= 0 || src.texels.empty()) return out;
    tbb::parallel_for(0, out.height, [&](int y) {
        for (int x = 0; x < out.width; ++x) {
            const glm::vec3 d = latLongToDirection({(float(x) + 0.5f) / float(out.width), (float(y) + 0.5f) / float(out.height)});
            out.texels[size_t(y) * size_t(out.width) + size_t(x)] = bilinear(src, domeImagePosition(format, d));
        }
    });
    glm::dvec3 sum(0.0);
    for (const auto& t : out.texels) sum += glm::dvec3(t);
    out.mean = glm::vec3(sum / double(out.texels.size()));
    return out;
}

}  // namespace principled::embree
