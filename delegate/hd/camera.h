// SPDX-License-Identifier: Apache-2.0
// Camera: the generic camera sprim (Hydra's HdCamera). Holds the camera's transform and
// projection parameters in scene units; render delegates turn it into rays.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

#include "delegate/hd/framing.h"
#include "delegate/hd/prim.h"
#include "delegate/hd/token.h"

namespace principled::hd {

class Camera : public Sprim {
public:
    enum class Projection { Perspective, Orthographic };

    using Sprim::Sprim;
    void sync(SceneDelegate* delegate, RenderParam* param, DirtyBits* dirtyBits) override;

    /// Camera-to-world (column-vector convention); the camera looks down -Z with +Y up.
    const glm::dmat4& transform() const { return _transform; }
    Projection projection() const { return _projection; }
    float focalLength() const { return _focalLength; }
    float horizontalAperture() const { return _hAperture; }
    float verticalAperture() const { return _vAperture; }
    float horizontalApertureOffset() const { return _hOffset; }
    float verticalApertureOffset() const { return _vOffset; }
    glm::vec2 clippingRange() const { return _clipping; }
    /// UsdGeomCamera fStop (0 = pinhole, the schema fallback) and focusDistance (scene units).
    float fStop() const { return _fStop; }
    float focusDistance() const { return _focusDistance; }
    /// Thin-lens aperture radius in scene units: f / (2 fStop) (the f-number N = f / D), the
    /// focal length f in scene units as the schema defines it (tenths of a scene unit as
    /// authored: millimetres on a centimetre stage; Blender writes lens / 100 on a metre stage,
    /// and reads it back the same way). 0 (a pinhole) when fStop <= 0, focusDistance <= 0 (the
    /// schema fallback would put the focus plane at the lens), orthographic, or any value is not
    /// finite.
    float lensRadius() const;
    /// A point of the aperture (the unit disk, or with `principled:apertureBlades` n >= 3 the
    /// regular n-gon inscribed in it, turned by `principled:apertureRotation` degrees: polygonal
    /// bokeh as Cycles' blades), uniform in area, from two uniform numbers. Scaled by lensRadius().
    glm::vec2 apertureSample(glm::vec2 u) const;
    int apertureBlades() const { return _blades; }
    /// The factor the rendered image's light is multiplied by (UsdGeomCamera exposure model,
    /// USD 24: responsivity * time * iso / 100 * 2^exposure / fStop^2, from the attributes
    /// exposure, exposure:time, exposure:iso, exposure:fStop and exposure:responsivity; 1 with
    /// their fallbacks). Radiance AOVs (color and the per-lobe light AOVs) are scaled, data AOVs
    /// are not. A product that is negative or not finite is replaced by 1 with a warning.
    float exposureScale() const { return _exposureScale; }
    /// The exposure model's product for the given attribute values; -1 when it is not a finite
    /// number >= 0 within float range (a negative or non-finite input, or fStop 0).
    static double exposureScale(double exposure, double time, double iso, double fStop, double responsivity);

    /// The image-plane window at distance 1 (perspective) or in scene units (orthographic)
    /// for an image of the given aspect ratio: {xmin, xmax, ymin, ymax}. By default the aperture
    /// is fitted to the image (UsdRender expandAperture, conformWindow "fit"): all of it stays visible.
    glm::vec4 screenWindow(double imageAspect) const { return screenWindow(imageAspect, Framing::Conform::ExpandAperture); }
    /// The same under a UsdRender conform policy; imageAspect is the image's width / height in
    /// pixels times the pixel aspect ratio.
    glm::vec4 screenWindow(double imageAspect, Framing::Conform conform) const;
    /// The window of an image of width x height pixels framed by `framing`.
    glm::vec4 screenWindow(int width, int height, const Framing& framing) const {
        return screenWindow(double(width) * double(framing.pixelAspectRatio) / double(height), framing.conform);
    }

    /// Sets parameters directly (hosts and tests that build cameras without a scene delegate).
    void set(const glm::dmat4& xform, float focalLength, float hAperture, float vAperture,
             Projection projection = Projection::Perspective);
    /// Sets the depth-of-field parameters directly (fStop 0 turns it off).
    void setDepthOfField(float fStop, float focusDistance) {
        _fStop = fStop;
        _focusDistance = focusDistance;
    }
    /// Sets the aperture shape directly: blades < 3 is round; rotation in degrees.
    void setAperture(int blades, float rotationDegrees);
    /// Sets the image's exposure scale directly (hosts without a scene delegate); values that are
    /// negative or not finite give 1.
    void setExposureScale(float scale) { _exposureScale = std::isfinite(scale) && scale >= 0.0f ? scale : 1.0f; }

private:
    glm::dmat4 _transform{1.0};
    Projection _projection = Projection::Perspective;
    // USD fallbacks (usdGeom schema), converted to scene units (tenths): 50 mm, 20.955 mm, 15.2908 mm.
    int _blades = 0;              ///< aperture polygon corners (< 3: round)
    float _bladeRotation = 0.0f;  ///< radians
    float _focalLength = 5.0f;
    float _hAperture = 2.0955f;
    float _vAperture = 1.52908f;
    float _hOffset = 0.0f;
    float _vOffset = 0.0f;
    glm::vec2 _clipping{1.0f, 1e6f};
    float _fStop = 0.0f;
    float _focusDistance = 0.0f;
    float _exposureScale = 1.0f;
};

}  // namespace principled::hd
