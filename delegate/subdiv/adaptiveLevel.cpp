// SPDX-License-Identifier: Apache-2.0
#include "delegate/subdiv/adaptiveLevel.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace principled::subdiv {

float adaptiveLog2Ratio(const glm::vec3& boundsMin, const glm::vec3& boundsMax, size_t faceCount,
                        const ScreenMetric& view) {
    constexpr float kNone = -std::numeric_limits<float>::infinity();
    const glm::vec3 size = boundsMax - boundsMin;
    const float area = 2.0f * (size.x * size.y + size.y * size.z + size.z * size.x);
    if (!(area > 0.0f) || !std::isfinite(area) || faceCount == 0 || view.imageHeight <= 0 ||
        !(view.verticalFov > 0.0f) || !(view.verticalFov < 3.14159265f) ||
        !(view.targetEdgePixels > 0.0f))
        return kNone;
    const float edge = std::sqrt(area / float(faceCount));
    const glm::vec3 center = 0.5f * (boundsMin + boundsMax);
    const float radius = 0.5f * glm::length(size);
    const float distance =
        std::max(glm::length(center - view.cameraPosition) - radius, radius * 1e-3f);
    // Pinhole projection: a length s at distance d covers s * H / (2 d tan(fov/2)) pixels.
    const float pixelsPerUnit =
        float(view.imageHeight) / (2.0f * distance * std::tan(0.5f * view.verticalFov));
    const float ratio = edge * pixelsPerUnit / view.targetEdgePixels;
    if (!(ratio > 1.0f)) return kNone;
    if (!std::isfinite(ratio)) return std::numeric_limits<float>::infinity();
    return std::log2(ratio);
}

int levelFromLog2Ratio(float x, int maxLevel) {
    maxLevel = std::max(maxLevel, 0);
    if (std::isnan(x) || x == -std::numeric_limits<float>::infinity()) return 0;
    if (x == std::numeric_limits<float>::infinity() || x > float(maxLevel)) return maxLevel;
    return std::clamp(int(std::ceil(x)), 0, maxLevel);
}

int adaptiveLevel(const glm::vec3& boundsMin, const glm::vec3& boundsMax, size_t faceCount,
                  const ScreenMetric& view) {
    return levelFromLog2Ratio(adaptiveLog2Ratio(boundsMin, boundsMax, faceCount, view), view.maxLevel);
}

int adaptiveLevel(const std::vector<glm::vec3>& objectPoints, const glm::dmat4& objectToWorld,
                  size_t faceCount, const ScreenMetric& view) {
    if (objectPoints.empty()) return 0;
    glm::vec3 lo(objectPoints[0]), hi(objectPoints[0]);
    for (const glm::vec3& p : objectPoints) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    glm::vec3 worldLo(std::numeric_limits<float>::max()),
        worldHi(-std::numeric_limits<float>::max());
    for (int corner = 0; corner < 8; ++corner) {
        const glm::dvec4 p((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y,
                           (corner & 4) ? hi.z : lo.z, 1.0);
        const glm::vec3 w(objectToWorld * p);
        worldLo = glm::min(worldLo, w);
        worldHi = glm::max(worldHi, w);
    }
    return adaptiveLevel(worldLo, worldHi, faceCount, view);
}

}  // namespace principled::subdiv
