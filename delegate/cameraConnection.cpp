// SPDX-License-Identifier: Apache-2.0
#include "delegate/cameraConnection.h"

#include <cmath>

#include "delegate/hd/camera.h"

namespace principled::embree {

CameraConnector::CameraConnector(const hd::Camera& camera, int width, int height, const glm::vec4& window)
    : _camera(&camera), _width(width), _height(height) {
    if (camera.projection() != hd::Camera::Projection::Perspective || width <= 0 || height <= 0) return;
    _toWorld = camera.transform();
    _toCamera = glm::inverse(_toWorld);
    _window = window;
    _lensRadius = camera.lensRadius();
    _focus = camera.focusDistance();
    _near = camera.clippingRange().x;
    _far = camera.clippingRange().y;
    _pixelArea = double(_window.y - _window.x) * double(_window.w - _window.z) / (double(width) * double(height));
    _valid = _pixelArea > 0.0 && std::isfinite(_pixelArea) && std::isfinite(_toCamera[3][3]);
}

bool CameraConnector::connect(const glm::vec3& p, const glm::vec2& uLens, CameraConnection* out) const {
    if (!_valid) return false;
    const glm::dvec3 pc = glm::dvec3(_toCamera * glm::dvec4(glm::dvec3(p), 1.0));
    // The camera ray's clipping range is a depth along -z (render pass, cameraRay).
    if (!(-pc.z >= _near && -pc.z <= _far)) return false;
    glm::dvec3 lens(0.0);
    if (_lensRadius > 0.0f) {
        const glm::vec2 a = _camera->apertureSample(uLens);
        lens = glm::dvec3(double(a.x) * _lensRadius, double(a.y) * _lensRadius, 0.0);
    }
    const glm::dvec3 v = pc - lens;
    if (!(v.z < 0.0)) return false;
    // Where the ray from the lens point through p crosses the focus plane, as an image-plane
    // position at unit distance (the render pass's camera ray inverted; a pinhole has lens = 0).
    const double lx = _lensRadius > 0.0f ? lens.x / _focus : 0.0, ly = _lensRadius > 0.0f ? lens.y / _focus : 0.0;
    const double sx = lx + v.x / -v.z, sy = ly + v.y / -v.z;
    const double px = (sx - _window.x) / double(_window.y - _window.x) * _width;
    const double py = (double(_window.w) - sy) / double(_window.w - _window.z) * _height;
    if (!(px >= 0.0 && px < _width && py >= 0.0 && py < _height)) return false;
    const glm::dvec3 lensWorld = glm::dvec3(_toWorld * glm::dvec4(lens, 1.0));
    const glm::dvec3 toLens = lensWorld - glm::dvec3(p);
    const double r = glm::length(toLens);
    const glm::dvec3 forward = glm::normalize(glm::dvec3(_toWorld * glm::dvec4(0.0, 0.0, -1.0, 0.0)));
    const double cosTheta = glm::dot(-toLens / r, forward);
    if (!(r > 0.0) || !(cosTheta > 0.0)) return false;
    out->lensPoint = glm::vec3(lensWorld);
    out->toCamera = glm::vec3(toLens / r);
    out->distance = float(r);
    out->x = std::min(int(px), _width - 1);
    out->y = std::min(int(py), _height - 1);
    out->importance = float(1.0 / (_pixelArea * cosTheta * cosTheta * cosTheta * r * r));
    return std::isfinite(out->importance);
}

}  // namespace principled::embree
