// SPDX-License-Identifier: Apache-2.0
#include "delegate/hd/camera.h"

#include <algorithm>
#include <cmath>

#include "bsdf/warp.h"
#include "delegate/hd/sceneDelegate.h"

namespace principled::hd {

void Camera::sync(SceneDelegate* delegate, RenderParam* renderParam, DirtyBits* dirtyBits) {
    if (*dirtyBits & SprimDirty::Transform) _transform = delegate->getTransform(id());
    if (*dirtyBits & SprimDirty::Params) {
        auto param = [&](const char* name, float fallback) {
            auto v = getFloat(delegate->getCameraParamValue(id(), Token(name)));
            return v ? *v : fallback;
        };
        _focalLength = param("focalLength", _focalLength);
        _hAperture = param("horizontalAperture", _hAperture);
        _vAperture = param("verticalAperture", _vAperture);
        _hOffset = param("horizontalApertureOffset", 0.0f);
        _vOffset = param("verticalApertureOffset", 0.0f);
        _fStop = param("fStop", 0.0f);
        _focusDistance = param("focusDistance", 0.0f);
        // Not UsdGeomCamera attributes: principled's own, for polygonal bokeh (Blender's blades).
        setAperture(int(std::lround(std::clamp(param("principled:apertureBlades", 0.0f), 0.0f, 64.0f))),
                    param("principled:apertureRotation", 0.0f));
        Value clip = delegate->getCameraParamValue(id(), Token("clippingRange"));
        if (auto* c = getIf<glm::vec2>(clip)) _clipping = *c;
        auto proj = getString(delegate->getCameraParamValue(id(), Token("projection")));
        _projection = (proj && *proj == "orthographic") ? Projection::Orthographic
                                                        : Projection::Perspective;
        const double scale = exposureScale(param("exposure", 0.0f), param("exposure:time", 1.0f),
                                           param("exposure:iso", 100.0f), param("exposure:fStop", 1.0f),
                                           param("exposure:responsivity", 1.0f));
        _exposureScale = scale >= 0.0 ? float(scale) : 1.0f;
        if (!(scale >= 0.0) && renderParam)
            renderParam->warn(id(), "exposure, exposure:time, exposure:iso, exposure:fStop and exposure:responsivity give "
                                    "no finite scale >= 0 (a negative or non-finite value, or fStop 0); exposure 1 used");
    }
    *dirtyBits = SprimDirty::Clean;
}

double Camera::exposureScale(double exposure, double time, double iso, double fStop, double responsivity) {
    // UsdGeomCamera's exposure model (USD 24.x, "Camera Exposure Model"; HdCamera::GetExposure):
    // responsivity * time * (iso / 100) * 2^exposure / fStop^2.
    const double s = responsivity * time * (iso / 100.0) * std::exp2(exposure) / (fStop * fStop);
    const bool inputsValid = time >= 0.0 && iso >= 0.0 && fStop > 0.0 && responsivity >= 0.0;
    // Finite as a float too: the image is scaled in float, and an infinite factor would turn
    // every sample into one the render buffer drops (a black image).
    return inputsValid && std::isfinite(s) && std::isfinite(float(s)) ? s : -1.0;
}

void Camera::set(const glm::dmat4& xform, float focalLength, float hAperture, float vAperture,
                 Projection projection) {
    _transform = xform;
    _focalLength = focalLength;
    _hAperture = hAperture;
    _vAperture = vAperture;
    _projection = projection;
}

float Camera::lensRadius() const {
    if (_projection != Projection::Perspective) return 0.0f;
    if (!(_fStop > 0.0f) || !(_focusDistance > 0.0f) || !std::isfinite(_focusDistance)) return 0.0f;
    // _focalLength is the authored value / 10: scene units (UsdGeomCamera, "Units").
    float r = _focalLength / (2.0f * _fStop);
    if (!(r > 0.0f)) return 0.0f;
    // A near-zero fStop: keep the lens within 1000 focus distances (finite ray origins).
    return std::min(r, 1000.0f * _focusDistance);
}

void Camera::setAperture(int blades, float rotationDegrees) {
    _blades = blades >= 3 && blades <= 64 ? blades : 0;
    _bladeRotation = std::isfinite(rotationDegrees) ? rotationDegrees * 0.017453292519943295f : 0.0f;
}

glm::vec2 Camera::apertureSample(glm::vec2 u) const {
    if (_blades < 3) return bsdf::squareToConcentricDisk(u);
    // A regular n-gon as n triangles (centre, corner k, corner k + 1) of equal area: u.x picks
    // the triangle and is reused within it; a point uniform in that triangle is
    // sqrt(a) ((1 - b) c_k + b c_k+1) (Pharr et al. 2023, §6.5.4, with one corner at the centre).
    // Corners at rotation + pi/n + 2 pi k/n, where Cycles puts its blades' corners.
    const float n = float(_blades);
    const float x = std::min(u.x * n, n - 1e-4f);
    const float k = std::floor(x);
    const float a = std::sqrt(std::clamp(x - k, 0.0f, 1.0f));
    const float step = 6.283185307179586f / n;
    const float t0 = _bladeRotation + 0.5f * step + k * step, t1 = t0 + step;
    const glm::vec2 c0(std::cos(t0), std::sin(t0)), c1(std::cos(t1), std::sin(t1));
    return a * ((1.0f - u.y) * c0 + u.y * c1);
}

glm::vec4 Camera::screenWindow(double imageAspect, Framing::Conform conform) const {
    // Perspective: the window at unit distance is aperture / focal length.
    double scale = _projection == Projection::Perspective
                       ? 1.0 / std::max(1e-6, static_cast<double>(_focalLength))
                       : 1.0;
    double w = std::max(1e-6, static_cast<double>(_hAperture)) * scale;
    double h = std::max(1e-6, static_cast<double>(_vAperture)) * scale;
    double cx = _hOffset * scale, cy = _vOffset * scale;
    if (!(imageAspect > 0.0) || !std::isfinite(imageAspect)) imageAspect = w / h;
    // UsdRenderSettingsBase aspectRatioConformPolicy: which side of the aperture follows the image.
    const bool wider = w / h > imageAspect;  // the aperture is wider than the image
    switch (conform) {
        case Framing::Conform::ExpandAperture:  // grow a side: the whole aperture stays visible
            if (wider) h = w / imageAspect; else w = h * imageAspect;
            break;
        case Framing::Conform::CropAperture:  // shrink a side: the image is filled
            if (wider) w = h * imageAspect; else h = w / imageAspect;
            break;
        case Framing::Conform::AdjustApertureWidth: w = h * imageAspect; break;
        case Framing::Conform::AdjustApertureHeight: h = w / imageAspect; break;
        case Framing::Conform::AdjustPixelAspectRatio: break;  // the aperture as authored
    }
    return glm::vec4(cx - 0.5 * w, cx + 0.5 * w, cy - 0.5 * h, cy + 0.5 * h);
}

}  // namespace principled::hd
