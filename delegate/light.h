// SPDX-License-Identifier: Apache-2.0
// Light: the UsdLux light sprims (distant, dome, sphere, rect, disk, cylinder; ShapingAPI cones).
// Converts USD light units into the radiance and irradiance the integrator samples (docs/lights.md).
#pragma once

#include <memory>
#include <string>

#include "delegate/environmentFormat.h"
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
    /// The light's texture (dome or rect) for `file`: the image an earlier sync read when the
    /// same file in the same layout has not been reloaded since (TextureCache::fileVersion), so
    /// an intensity, colour or transform edit does not read and resample it again; else read now.
    /// Null with *error when it cannot be read.
    std::shared_ptr<const EnvironmentMap> image(EmbreeRenderParam* param, const std::string& file, bool dome,
                                                DomeFormat format, std::string* error);

    hd::Token _type;
    struct CachedImage {
        std::string key;       ///< dome or rect, layout and path
        uint64_t version = 0;  ///< TextureCache::fileVersion of the path when it was read
        std::shared_ptr<const EnvironmentMap> image;
    };
    CachedImage _cached;
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
