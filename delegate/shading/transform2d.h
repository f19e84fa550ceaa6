// SPDX-License-Identifier: Apache-2.0
// UsdTransform2d: the affine 2D transform applied to texture coordinates.
#pragma once

#include <cmath>
#include <glm/glm.hpp>

namespace principled::shading {

/// result = rotate(in * scale) + translation, rotation counter-clockwise in degrees
/// (UsdPreviewSurface spec 2.5, UsdTransform2d: "in * scale * rotate + translation").
struct Transform2d {
    glm::mat2 linear{1.0f};  ///< rotation * diag(scale), column-major
    glm::vec2 translation{0.0f};

    static Transform2d make(float rotationDegrees, glm::vec2 scale, glm::vec2 translation) {
        float r = glm::radians(rotationDegrees);
        float c = std::cos(r), s = std::sin(r);
        Transform2d t;
        // Columns of R = [[c, -s], [s, c]] scaled by the per-axis scale.
        t.linear = glm::mat2(glm::vec2(c, s) * scale.x, glm::vec2(-s, c) * scale.y);
        t.translation = translation;
        return t;
    }

    glm::vec2 apply(glm::vec2 in) const { return linear * in + translation; }
};

}  // namespace principled::shading
