// SPDX-License-Identifier: Apache-2.0
// Mesh: the Embree rprim for UsdGeomMesh. Polygonal meshes are fan-triangulated; subdivision
// meshes are refined with OpenSubdiv (uniform level, fixed or picked from the projected size),
// their topology refined once and re-posed by stencils. Primvars are kept per triangle corner,
// except on refined meshes: vertex/varying primvars and normals per point, uniform per triangle.
#pragma once

#include <memory>

#include <optional>

#include "delegate/geometryPrim.h"
#include "delegate/subdiv/levelBudget.h"
#include "delegate/subdiv/refinedMesh.h"
#include "delegate/subdiv/subdivTopology.h"

namespace principled::embree {

class Mesh : public GeometryPrim {
public:
    using GeometryPrim::GeometryPrim;

    /// Bytes held for this mesh: its GeometryRecord plus the subdivision topology (stencils,
    /// triangles) kept for re-posing. Not Embree's BVH.
    size_t memoryBytes() const;

    /// The subdivision level used at the last rebuild (0: the polygons themselves).
    int refineLevel() const { return _level; }

    /// Asks for a refit of the subdivision budget when this mesh held part of it.
    void finalize(hd::RenderParam* param) override;

    /// Whether a sync with these dirty bits rebuilds the geometry (and so picks a level).
    bool rebuildsOn(hd::DirtyBits bits) const { return (bits & geometryBits()) != 0; }
    /// What a rebuild now would ask of the scene-wide subdivision budget, read from the scene
    /// delegate (before sync: the transform may not be pulled yet); none for a polygon mesh
    /// (scheme "none") or a cage that will not build.
    std::optional<subdiv::LevelPlan> levelPlan(hd::SceneDelegate* delegate, EmbreeRenderParam* param) const;
    /// The plan the mesh was last built from (none: a polygon mesh, or nothing built).
    const std::optional<subdiv::LevelPlan>& plan() const { return _plan; }
    /// The level the next rebuild uses, from `plan` (the budget's fit); level -1: its own.
    void grantLevel(int level, const std::optional<subdiv::LevelPlan>& plan) {
        _grantedLevel = level;
        _plan = plan;
    }

protected:
    hd::DirtyBits geometryBits() const override;
    RTCGeometry rebuildGeometry(hd::SceneDelegate* delegate, EmbreeRenderParam* param) override;

private:
    RTCGeometry buildGeometry(hd::SceneDelegate* delegate, EmbreeRenderParam* param, int granted);
    int chooseLevel(hd::SceneDelegate* delegate, const hd::MeshTopology& topo, const hd::SubdivTags& tags,
                    const std::vector<glm::vec3>& points, EmbreeRenderParam* param, int granted);
    bool buildCage(hd::SceneDelegate* delegate, EmbreeRenderParam* param,
                   const hd::MeshTopology& topo, const std::vector<glm::vec3>& points);
    bool buildSubdivided(hd::SceneDelegate* delegate, EmbreeRenderParam* param,
                         const hd::MeshTopology& topo, const std::vector<glm::vec3>& points,
                         int level);

    std::unique_ptr<subdiv::SubdivTopology> _subdiv;
    /// SubdivTopology::id() whose triangles _record holds (0: none). The refined mesh is
    /// built in _record's own arrays, so re-posing copies points and normals only.
    uint64_t _refinedTopologyId = 0;
    int _level = 0;
    int _grantedLevel = -1;
    std::optional<subdiv::LevelPlan> _plan;
};

}  // namespace principled::embree
