// SPDX-License-Identifier: Apache-2.0
// Screen-space choice of the uniform subdivision level for one mesh.
#pragma once

#include <cstddef>
#include <glm/glm.hpp>
#include <vector>

namespace principled::subdiv {

/// The camera as adaptiveLevel() sees it.
struct ScreenMetric {
    glm::vec3 cameraPosition{0.0f};
    float verticalFov = 0.8f;       ///< radians (full angle)
    int imageHeight = 1080;         ///< pixels
    float targetEdgePixels = 1.5f;  ///< wanted projected length of a refined edge
    int maxLevel = 6;
};

/// Smallest uniform level L in [0, maxLevel] whose average refined edge projects to at most
/// targetEdgePixels at the mesh's nearest point:
///   e0  = sqrt(A / F)                    average coarse edge, A = bounding-box surface area,
///                                        F = coarse faces (a square face of area A/F);
///   ppu = H / (2 d tan(fov/2))           pixels per world unit at distance d (pinhole);
///   d   = max(|c - eye| - r, r * 1e-3)   distance to the bounding sphere (c, r), the
///                                        1e-3 floor stands for "the camera is inside";
///   L   = ceil(log2(e0 * ppu / target))  each uniform step halves the edges.
/// Deterministic; a degenerate box, no faces or a bad camera give 0.
int adaptiveLevel(const glm::vec3& boundsMin, const glm::vec3& boundsMax, size_t faceCount,
                  const ScreenMetric& view);

/// log2(e0 * ppu / target) of adaptiveLevel(), before the ceiling and the clamp: -inf where
/// adaptiveLevel() gives 0 for want of refinement or of a usable input, +inf where the ratio
/// overflows (adaptiveLevel() gives maxLevel). adaptiveLevel() == levelFromLog2Ratio(this,
/// view.maxLevel); a scene-wide budget (delegate/subdivBudget.h) lowers it in half steps.
float adaptiveLog2Ratio(const glm::vec3& boundsMin, const glm::vec3& boundsMax, size_t faceCount,
                        const ScreenMetric& view);

/// clamp(ceil(x), 0, maxLevel), with -inf -> 0 and +inf -> maxLevel.
int levelFromLog2Ratio(float x, int maxLevel);

/// Convenience: the same for object-space cage points under objectToWorld (the world box
/// of the transformed object-space box, a conservative bound).
int adaptiveLevel(const std::vector<glm::vec3>& objectPoints, const glm::dmat4& objectToWorld,
                  size_t faceCount, const ScreenMetric& view);

}  // namespace principled::subdiv
