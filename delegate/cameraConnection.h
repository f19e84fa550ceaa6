// SPDX-License-Identifier: Apache-2.0
// Connecting a scene point to the camera (light tracing): which pixel sees it through which
// point of the lens, and the camera's importance for that connection under the box pixel filter
// the render pass samples with.
#pragma once

#include <glm/glm.hpp>

namespace principled::hd {
class Camera;
}

namespace principled::embree {

struct CameraConnection {
    glm::vec3 lensPoint{0.0f};  ///< world-space point of the lens (the pinhole without depth of field)
    glm::vec3 toCamera{0.0f};   ///< unit direction from the scene point toward lensPoint
    float distance = 0.0f;      ///< from the scene point to lensPoint
    int x = 0, y = 0;           ///< the pixel
    /// Importance per unit area of the scene surface over the pixel's solid angle:
    /// 1 / (A_pixel cos^3(theta) r^2), A_pixel the pixel's area on the image plane at unit
    /// distance, theta the angle to the viewing axis (Veach 1997, §8.1.1 with Pharr et al. 2023,
    /// §5.4.1 for the pinhole and thin-lens importance). The pixel's value is the mean of
    /// weight * f * |cos at the surface| * importance over the light paths traced.
    float importance = 0.0f;
};

/// A perspective camera (pinhole or thin lens) as seen by light tracing. Orthographic cameras
/// are not connectable (valid() is false).
class CameraConnector {
public:
    CameraConnector() = default;
    /// window: the camera's screen window for this image (Camera::screenWindow with the pass's framing).
    CameraConnector(const hd::Camera& camera, int width, int height, const glm::vec4& window);

    bool valid() const { return _valid; }
    /// Camera-space lens point from two uniform numbers (ignored for a pinhole).
    /// Projects world point p: false when it is behind the camera, outside the clipping range or
    /// outside the image.
    bool connect(const glm::vec3& p, const glm::vec2& uLens, CameraConnection* out) const;

private:
    bool _valid = false;
    const hd::Camera* _camera = nullptr;
    glm::dmat4 _toWorld{1.0}, _toCamera{1.0};
    glm::vec4 _window{0.0f};
    int _width = 0, _height = 0;
    float _lensRadius = 0.0f, _focus = 1.0f;
    float _near = 0.0f, _far = 1e30f;
    double _pixelArea = 0.0;
};

}  // namespace principled::embree
