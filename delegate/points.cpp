// SPDX-License-Identifier: Apache-2.0
#include "delegate/points.h"

#include <cmath>
#include <string>

#include "delegate/hd/sceneDelegate.h"
#include "delegate/hd/tokens.h"
#include "delegate/primitivePrimvars.h"
#include "delegate/primvarUtil.h"

namespace principled::embree {

using namespace hd;

DirtyBits Points::geometryBits() const {
    return RprimDirty::Points | RprimDirty::Primvar | RprimDirty::Topology | RprimDirty::Widths;
}

RTCGeometry Points::rebuildGeometry(SceneDelegate* delegate, EmbreeRenderParam* param) {
    Value pv = delegate->get(id(), tokens::points());
    const auto* pts = getIf<std::vector<glm::vec3>>(pv);
    if (!pts || pts->empty()) {
        param->warn(id(), "points has no point positions; not rendered");
        return nullptr;
    }
    std::vector<float> widths;
    int wc = 0;
    flattenFloats(delegate->get(id(), tokens::widths()), &widths, &wc);
    if (wc != 1) widths.clear();
    // UsdGeomPoints: widths is constant (one value) or one per point; without it, diameter 1.
    if (widths.size() > 1 && widths.size() != pts->size()) {
        param->warn(id(), "widths has " + std::to_string(widths.size()) + " values for " +
                              std::to_string(pts->size()) + " points; using the first");
        widths.resize(1);
    }
    _record.kind = GeometryRecord::Kind::Points;
    _record.points.clear();
    _record.triangleFace.clear();
    std::vector<glm::vec4> spheres;
    size_t skipped = 0;
    for (size_t i = 0; i < pts->size(); ++i) {
        float w = widths.empty() ? 1.0f : widths[widths.size() == 1 ? 0 : i];
        const glm::vec3& p = (*pts)[i];
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(w) || w <= 0.0f) {
            ++skipped;
            continue;
        }
        spheres.emplace_back(p, 0.5f * w);
        _record.points.push_back(p);
        _record.triangleFace.push_back(int(i));  // elementId: the authored point
    }
    if (skipped)
        param->warn(id(), std::to_string(skipped) + " points with a non-finite position or a width <= 0 skipped");
    if (spheres.empty()) return nullptr;
    if (auto c = constantDisplayColor(delegate, id())) _record.displayColor = *c;
    std::vector<Token> dropped;
    const auto& source = _record.triangleFace;
    _record.primvars = primitivePrimvars(
        delegate, id(), spheres.size(),
        [&](Interpolation, size_t i, size_t) { return size_t(source[i]); }, &dropped);
    for (const Token& t : dropped) param->warn(id(), "primvar '" + t.str() + "' does not have one value per point; ignored");
    RTCGeometry geom = rtcNewGeometry(param->device(), RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* v = static_cast<glm::vec4*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                              sizeof(glm::vec4), spheres.size()));
    std::copy(spheres.begin(), spheres.end(), v);
    return geom;
}

}  // namespace principled::embree
