// SPDX-License-Identifier: Apache-2.0
#include "delegate/mesh.h"

#include <cmath>
#include <cstring>

#include "delegate/hd/sceneDelegate.h"
#include "delegate/hd/tokens.h"
#include "delegate/primvarUtil.h"
#include "delegate/triangulate.h"

namespace principled::embree {

using namespace hd;

DirtyBits Mesh::geometryBits() const {
    return RprimDirty::Points | RprimDirty::Topology | RprimDirty::Normals | RprimDirty::Primvar |
           RprimDirty::DisplayStyle | RprimDirty::SubdivTags;
}

RTCGeometry Mesh::rebuildGeometry(SceneDelegate* delegate, EmbreeRenderParam* param) {
    Value pointsValue = delegate->get(id(), tokens::points());
    const auto* points = getIf<std::vector<glm::vec3>>(pointsValue);
    MeshTopology topo = delegate->getMeshTopology(id());
    Triangulation tri;
    std::string error;
    bool ok = points && triangulate(topo, points->size(), &tri, &error);
    if (points && ok) {
        for (const glm::vec3& p : *points)
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
                ok = false;
                error = "points contain NaN or Inf";
                break;
            }
    }
    if (!points) error = "has no points";
    if (ok && tri.skippedFaces > 0)
        param->warn(id(), "skipped " + std::to_string(tri.skippedFaces) + " invalid face(s); " +
                              tri.firstProblem);
    if (!ok || tri.triangles.empty()) {
        if (!ok) param->warn(id(), "mesh not rendered: " + error);
        return nullptr;
    }

    _record.kind = GeometryRecord::Kind::Triangles;
    _record.points = *points;
    _record.triangles = std::move(tri.triangles);
    _record.triangleFace = std::move(tri.triangleFace);
    _record.cornerNormals = authoredCornerNormals(delegate, id(), _record.points.size(),
                                                  topo.faceVertexCounts.size(), tri.corners,
                                                  _record.triangles, _record.triangleFace);
    // Subdivision surfaces without authored normals are shaded smooth (the cage is the
    // approximation until refinement applies); polygonal meshes ("none") stay faceted.
    if (_record.cornerNormals.empty() && topo.scheme != Token("none"))
        _record.cornerNormals = smoothCornerNormals(_record.points, _record.triangles);
    if (auto c = constantDisplayColor(delegate, id())) _record.displayColor = *c;

    RTCGeometry geom = rtcNewGeometry(param->device(), RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<glm::vec3*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, sizeof(glm::vec3),
        _record.points.size()));
    std::memcpy(v, _record.points.data(), _record.points.size() * sizeof(glm::vec3));
    auto* t = static_cast<glm::uvec3*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, sizeof(glm::uvec3),
        _record.triangles.size()));
    std::memcpy(t, _record.triangles.data(), _record.triangles.size() * sizeof(glm::uvec3));
    param->meshesRebuilt++;
    return geom;
}

}  // namespace principled::embree
