// SPDX-License-Identifier: Apache-2.0
#include "delegate/subdiv/adaptiveLevel.h"

#include <algorithm>
#include <cmath>

namespace principled::subdiv {

int adaptiveLevel(const glm::vec3& boundsMin, const glm::vec3& boundsMax, size_t faceCount,
                  const ScreenMetric& view) {
    const int maxLevel = std::max(view.maxLevel, 0);
    const glm::vec3 size = boundsMax - boundsMin;
    const float area = 2.0f * (size.x * size.y + size.y * size.z + size.z * size.x);
    if (!(area > 0.0f) || !std::isfinite(area) || faceCount == 0 || view.imageHeight <= 0 ||
        !(view.verticalFov > 0.0f) || !(view.verticalFov < 3.14159265f) ||
        !(view.targetEdgePixels > 0.0f))
        return 0;
    const float edge = std::sqrt(area / float(faceCount));
    const glm::vec3 center = 0.5f * (boundsMin + boundsMax);
    const float radius = 0.5f * glm::length(size);
    const float distance =
        std::max(glm::length(center - view.cameraPosition) - radius, radius * 1e-3f);
    // Pinhole projection: a length s at distance d covers s * H / (2 d tan(fov/2)) pixels.
    const float pixelsPerUnit =
        float(view.imageHeight) / (2.0f * distance * std::tan(0.5f * view.verticalFov));
    const float ratio = edge * pixelsPerUnit / view.targetEdgePixels;
    if (!(ratio > 1.0f)) return 0;
    if (!std::isfinite(ratio)) return maxLevel;
    const int level = int(std::ceil(std::log2(ratio)));
    return std::clamp(level, 0, maxLevel);
}

}  // namespace principled::subdiv
