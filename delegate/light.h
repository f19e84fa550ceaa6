// SPDX-License-Identifier: Apache-2.0
// Light: the UsdLux light sprims (distant, dome, sphere, rect, disk, cylinder; ShapingAPI cones).
// Converts USD light units into the radiance and irradiance the integrator samples (docs/lights.md).
#pragma once

#include "delegate/hd/prim.h"
#include "delegate/hd/token.h"
#include "delegate/renderParam.h"

namespace principled::embree {

class Light : public hd::Sprim, public LightSource {
public:
    Light(const hd::Token& typeId, const hd::Path& id) : Sprim(id), _type(typeId) {}
    void sync(hd::SceneDelegate* delegate, hd::RenderParam* param, hd::DirtyBits* bits) override;
    void finalize(hd::RenderParam* param) override;

    const hd::Path& lightId() const override { return id(); }
    const LightRecord& record() const override { return _record; }
    bool enabled() const override { return _enabled; }

private:
    hd::Token _type;
    LightRecord _record;
    bool _enabled = true;
    bool _registered = false;
};

/// Commit-time tables of mesh light l (kind Mesh, mesh and meshTriangles set): its emitting
/// triangles in world space with their normals and areas (l->meshWorld), read by sampleLight()
/// and meshLightPdf() instead of transforming the mesh's points per sample. The mesh's points
/// are placed by objectToWorld (a PointInstancer or scene-graph instance), else by the mesh's own.
void prepareMeshLight(LightRecord* l);
void prepareMeshLight(LightRecord* l, const glm::mat4& objectToWorld);

}  // namespace principled::embree
