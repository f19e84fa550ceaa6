// SPDX-License-Identifier: Apache-2.0
#include "delegate/light.h"

#include <algorithm>
#include <cmath>

#include "delegate/hd/sceneDelegate.h"
#include "delegate/hd/tokens.h"

namespace principled::embree {

using namespace hd;

namespace {

constexpr float kPi = 3.14159265358979323846f;

glm::vec3 finiteNonNegative(glm::vec3 v) {
    for (int i = 0; i < 3; ++i)
        if (!std::isfinite(v[i]) || v[i] < 0.0f) v[i] = 0.0f;
    return v;
}

}  // namespace

void Light::sync(SceneDelegate* delegate, RenderParam* renderParam, DirtyBits* bits) {
    auto* param = static_cast<EmbreeRenderParam*>(renderParam);
    if (!_registered) {
        param->add(static_cast<LightSource*>(this));
        _registered = true;
    }
    auto scalar = [&](const char* name, float fallback) {
        auto v = getFloat(delegate->getLightParamValue(id(), Token(name)));
        return (v && std::isfinite(*v)) ? *v : fallback;
    };
    if (*bits & (SprimDirty::Params | SprimDirty::Transform | SprimDirty::Resource |
                 SprimDirty::Visibility)) {
        _enabled = delegate->getVisible(id());
        // USD light units: L = color * intensity * 2^exposure (UsdLux LightAPI).
        glm::vec3 color = getVec3(delegate->getLightParamValue(id(), Token("color")))
                              .value_or(glm::vec3(1.0f));
        float intensity = scalar("intensity", _type == tokens::distantLight() ? 50000.0f : 1.0f);
        float exposure = scalar("exposure", 0.0f);
        bool normalize = scalar("normalize", 0.0f) > 0.5f;
        glm::vec3 scaled = finiteNonNegative(color * intensity * std::exp2(exposure));
        glm::dmat4 xf = delegate->getTransform(id());
        if (_type == tokens::distantLight()) {
            _record.kind = LightRecord::Kind::Distant;
            glm::dvec3 d = glm::dmat3(xf) * glm::dvec3(0.0, 0.0, -1.0);
            double len = glm::length(d);
            _record.direction = len > 0.0 ? glm::vec3(d / len) : glm::vec3(0, 0, -1);
            float angle = std::clamp(scalar("angle", 0.53f), 0.0f, 180.0f);
            float half = 0.5f * angle * kPi / 180.0f;
            _record.cosHalfAngle = std::cos(half);
            float s = std::sin(half);
            // The disc of angular diameter `angle` delivers E = L * pi * sin^2(angle/2) head-on
            // (solid angle of a cone, projected); a zero angle is a delta light with E = L.
            float solid = kPi * s * s;
            if (angle <= 0.0f || solid <= 1e-12f) {
                _record.cosHalfAngle = 1.0f;
                _record.irradiance = scaled;
                _record.radiance = scaled;
            } else if (normalize) {
                // normalize: intensity is the illuminance (lux) the light delivers.
                _record.irradiance = scaled;
                _record.radiance = scaled / solid;
            } else {
                _record.radiance = scaled;
                _record.irradiance = scaled * solid;
            }
        } else {
            _record.kind = LightRecord::Kind::Dome;
            _record.radiance = scaled;
            _record.irradiance = scaled * kPi;
        }
        param->markTablesDirty();
    }
    *bits = SprimDirty::Clean;
}

void Light::finalize(RenderParam* renderParam) {
    auto* param = static_cast<EmbreeRenderParam*>(renderParam);
    if (_registered) param->remove(static_cast<LightSource*>(this));
    _registered = false;
    param->markTablesDirty();
}

}  // namespace principled::embree
