// SPDX-License-Identifier: Apache-2.0
#include "delegate/sphere.h"

#include <cmath>

#include "delegate/hd/sceneDelegate.h"
#include "delegate/hd/tokens.h"
#include "delegate/primvarUtil.h"

namespace principled::embree {

using namespace hd;

DirtyBits Sphere::geometryBits() const {
    return RprimDirty::Points | RprimDirty::Primvar | RprimDirty::Topology;
}

RTCGeometry Sphere::rebuildGeometry(SceneDelegate* delegate, EmbreeRenderParam* param) {
    float r = getFloat(delegate->get(id(), tokens::radius())).value_or(1.0f);
    if (!std::isfinite(r) || r <= 0.0f) {
        param->warn(id(), "sphere radius must be a positive finite number; not rendered");
        return nullptr;
    }
    _record.kind = GeometryRecord::Kind::Sphere;
    _record.radius = r;
    _record.center = glm::vec3(0.0f);
    if (auto c = constantDisplayColor(delegate, id())) _record.displayColor = *c;
    RTCGeometry geom = rtcNewGeometry(param->device(), RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* v = static_cast<glm::vec4*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, sizeof(glm::vec4), 1));
    v[0] = glm::vec4(_record.center, r);
    return geom;
}

}  // namespace principled::embree
