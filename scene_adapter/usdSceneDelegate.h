// SPDX-License-Identifier: Apache-2.0
// UsdSceneDelegate: serves a composed USD stage to a render index. populate() inserts one prim
// per renderable USD prim (meshes, spheres, cameras, materials, lights); the pull methods answer
// from the stage at the delegate's time code.
#pragma once

#include <functional>
#include <map>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "delegate/hd/framing.h"
#include "delegate/hd/renderIndex.h"
#include "delegate/hd/sceneDelegate.h"
#include "scene_adapter/materialBinding.h"
#include "scene_adapter/skinning.h"

namespace principled::usd {
class Stage;
class Prim;
}  // namespace principled::usd

namespace principled::adapter {

struct ShapeMesh;

struct AdapterOptions {
    double time = std::numeric_limits<double>::quiet_NaN();  ///< NaN: the stage's default time
    /// Subdivision level for every mesh; -1 leaves it to the render delegate (adaptive). A mesh
    /// overrides it with the attribute `int principled:refineLevel`.
    int refineLevel = -1;
    /// UsdRenderSettings includedPurposes: the purposes drawn (guide and proxy are not, by default).
    std::vector<std::string> includedPurposes{"default", "render"};
    /// UsdRenderSettings materialBindingPurposes: binding purposes in order of preference.
    std::vector<std::string> materialBindingPurposes{"full", ""};
    /// UsdRenderSettings disableDepthOfField: every camera is a pinhole.
    bool disableDepthOfField = false;
};

class UsdSceneDelegate : public hd::SceneDelegate {
public:
    /// The stage must outlive the delegate.
    UsdSceneDelegate(const usd::Stage& stage, const AdapterOptions& options = {});
    ~UsdSceneDelegate() override;

    /// Inserts every renderable prim into the index. Unsupported prims are reported by
    /// warnings() and skipped.
    void populate(hd::RenderIndex* index);

    /// Camera prims found, in stage order.
    const std::vector<hd::Path>& cameras() const { return _cameras; }
    /// Adds (once) a camera framing the world bounds of the populated geometry, looking along
    /// the stage's horizontal axis from the front and slightly above; returns its id.
    hd::Path addDefaultCamera(hd::RenderIndex* index, double aspect);
    /// The same for an image of width x height pixels framed by `framing` (its conform policy and
    /// pixel aspect ratio shape the window the scene is fitted into).
    hd::Path addDefaultCamera(hd::RenderIndex* index, int width, int height, const hd::Framing& framing);

    /// Problems found while populating (prim path first).
    const std::vector<std::string>& warnings() const { return _warnings; }

    hd::MeshTopology getMeshTopology(const hd::Path& id) const override;
    hd::SubdivTags getSubdivTags(const hd::Path& id) const override;
    glm::dmat4 getTransform(const hd::Path& id) const override;
    bool getVisible(const hd::Path& id) const override;
    bool getDoubleSided(const hd::Path& id) const override;
    hd::Value get(const hd::Path& id, const hd::Token& key) const override;
    hd::Value getIndexedPrimvar(const hd::Path& id, const hd::Token& key,
                                std::vector<int>* indices) const override;
    std::vector<hd::PrimvarDescriptor> getPrimvarDescriptors(
        const hd::Path& id, hd::Interpolation interp) const override;
    hd::Path getMaterialId(const hd::Path& id) const override;
    std::vector<std::pair<hd::Path, std::vector<int>>> getMaterialSubsets(
        const hd::Path& id) const override;
    hd::Path getInstancerId(const hd::Path& id) const override;
    std::shared_ptr<const hd::InstancerArrays> getInstancerArrays(const hd::Path& instancerId) const override;
    std::vector<int> getInstanceIndices(const hd::Path& instancerId,
                                        const hd::Path& prototypeId) const override;
    hd::MaterialNetwork getMaterialResource(const hd::Path& materialId) const override;
    hd::Value getLightParamValue(const hd::Path& id, const hd::Token& param) const override;
    /// Light and shadow linking: the paths of the light-link and shadow-link collections
    /// ("</Light.collection:lightLink>") that hold this prim (only collections that do not hold
    /// everything name a category).
    std::vector<hd::Token> getCategories(const hd::Path& id) const override;
    hd::Value getCameraParamValue(const hd::Path& id, const hd::Token& param) const override;

    // ---- Change processing (usdSceneDelegateEdits.cpp) --------------------------------------
    // After the stage changed (usd::StageEdit, driven by adapter::StageEditor), these keep the
    // index in step, like UsdImaging's ObjectsChanged handling: each marks exactly the dirty
    // bits the change implies on the prims it affects, or inserts/removes index prims.

    /// `attribute` of the prim at `primPath` has a new value.
    void attributeChanged(const std::string& primPath, const std::string& attribute,
                          hd::RenderIndex* index);
    /// Relationship `name` of the prim at `primPath` has new targets.
    void relationshipChanged(const std::string& primPath, const std::string& name,
                             hd::RenderIndex* index);
    /// A prim was defined at `path` (empty: no children yet).
    void primAdded(const std::string& path, hd::RenderIndex* index);
    /// The prim at `path` and its subtree are about to leave the stage: removes their index
    /// prims while the stage objects are still in place.
    void primRemoving(const std::string& path, hd::RenderIndex* index);
    /// ...and have left it: rebinds prims whose material went away (to the default material),
    /// re-populates instancers that drew it.
    void primRemoved(const std::string& path, hd::RenderIndex* index);
    /// The instanceable prim whose subtree holds `path` (an instance proxy, read-only as in
    /// USD), or "" when there is none.
    std::string enclosingInstance(const std::string& path) const;

private:
    struct Entry {
        const usd::Prim* prim = nullptr;
        hd::Token type;
        glm::dmat4 world{1.0};
        bool visible = true;
        hd::Path material;
        /// What the mesh's materialBind GeomSubsets resolve to (subsetBindings()), so an edit
        /// re-splits only meshes whose subsets changed.
        std::string subsetMaterials;
        // Implicit shapes (Cube, Cylinder, Cone, Capsule): the generated mesh.
        std::shared_ptr<const ShapeMesh> shape;
        // UsdSkel: the mesh posed by its skeleton (points, normals; world is the skeleton's).
        std::shared_ptr<const SkinnedMesh> skinned;
        // PointInstancer prototypes: the instancer drawing them and their prototype index
        // (getTransform is then relative to the instancer).
        hd::Path instancer;
        int protoIndex = -1;
        // Instanceable prims: the synthetic instancer's per-instance world matrices.
        std::shared_ptr<std::vector<glm::dmat4>> instanceXforms;
    };

    void visit(const usd::Prim& prim, const glm::dmat4& parentWorld, bool parentVisible,
               hd::RenderIndex* index);
    // Implicit shapes and PointInstancers (usdSceneDelegateGeom.cpp).
    bool prepareShape(const usd::Prim& prim, Entry* e);
    void visitPointInstancer(const usd::Prim& prim, const glm::dmat4& world, bool visible,
                             hd::RenderIndex* index);
    void visitPrototype(const usd::Prim& prim, const hd::Path& id, const glm::dmat4& parentRel,
                        bool parentVisible, const hd::Path& instancer, int protoIndex,
                        hd::RenderIndex* index);
    bool visitInstance(const usd::Prim& prim, const glm::dmat4& world, bool visible,
                       hd::RenderIndex* index);
    hd::Value shapeOrInstancerValue(const Entry& e, const hd::Token& key) const;
    /// A PointInstancer's positions at the current time (velocities and accelerations applied).
    hd::Value instancerPositions(const usd::Prim& prim) const;
    void growInstancedBounds(const hd::Path& id, const Entry& e,
                             const std::function<void(const glm::dmat4&, const glm::dvec3&)>& grow) const;

    // Change processing helpers (usdSceneDelegateEdits.cpp).
    /// UsdSkel: poses again the meshes `which` selects (skinned or not; drawn as authored when
    /// they no longer skin), marking those that are or were skinned.
    void reposeSkinned(const std::function<bool(const Entry&)>& which, hd::RenderIndex* index);
    /// UsdSkel: the prim at `moved` was moved; skinned meshes whose skeleton or own prim is at
    /// or below it take their skeleton's new world transform.
    void skeletonSpaceMoved(const std::string& moved, hd::RenderIndex* index);
    SkeletonPoseCache _skeletonPoses;  ///< per populate / edit pass (poses at _time)
    /// Some mesh has been posed (stays true once set: a cheap, conservative test for the edit
    /// paths, instead of a scan of every entry per edit).
    bool hasSkinnedMeshes() const { return _anySkinned; }
    bool _anySkinned = false;
    struct Ancestry {
        glm::dmat4 parentWorld{1.0};
        bool parentVisible = true;
        bool drawn = true;                          ///< no ancestor hides the subtree (purpose)
        const usd::Prim* pointInstancer = nullptr;  ///< strict ancestor PointInstancer
    };
    Ancestry ancestry(const usd::Prim& prim) const;
    std::vector<hd::Path> idsOf(const usd::Prim* prim) const;
    void removeEntry(const hd::Path& id, hd::RenderIndex* index);
    void resyncSubtree(const std::string& path, hd::RenderIndex* index);
    void repopulate(hd::RenderIndex* index);
    void transformChanged(const usd::Prim& prim, hd::RenderIndex* index);
    void visibilityChanged(const usd::Prim& prim, hd::RenderIndex* index);
    void rebind(const std::string& root, const std::string& material, hd::RenderIndex* index);
    void collectionChanged(hd::RenderIndex* index);
    /// A mesh's GeomSubsets changed: its rprims re-split (MaterialId) and record what the
    /// subsets now resolve to.
    void subsetsChanged(const usd::Prim& mesh, hd::RenderIndex* index);
    /// Reads the light-link and shadow-link collections of every light entry into _lightLinks
    /// (collections that hold everything, the default, are left out).
    void readLightLinks();
    /// Instance groups: which link collections hold each prim below root ("" without links).
    std::string lightLinkKey(const usd::Prim& root) const;
    /// readLightLinks() after an edit, marking what linking may have changed.
    void refreshLightLinks(hd::RenderIndex* index);
    void materialNetworkChanged(const usd::Prim& prim, hd::DirtyBits bits, hd::RenderIndex* index);
    /// Instancers that draw `path` or anything below it (as prototypes or by containing it).
    std::vector<hd::Path> instancersDrawing(const std::string& path) const;
    bool subtreeHasInstances(const std::string& path) const;
    /// A primvar of a prim that is not an rprim changed: the rprims below inherit it.
    void inheritedPrimvarChanged(const usd::Prim& prim, hd::RenderIndex* index);

    const Entry* entry(const hd::Path& id) const;
    const usd::Prim* prim(const hd::Path& id) const;
    hd::Value attributeValue(const usd::Prim& prim, const std::string& name) const;
    hd::Path resolveMaterialBinding(const usd::Prim& prim) const;
    /// The resolved materials of a mesh's materialBind GeomSubsets, in order ("" without any).
    std::string subsetBindings(const usd::Prim& mesh) const;
    void warn(const std::string& where, const std::string& message);
    void checkExtent(const usd::Prim& prim);
    /// The same for an implicit shape, against its analytic bounds.
    void checkShapeExtent(const usd::Prim& prim, const ShapeMesh& shape);
    /// Warns when a camera with depth of field has a focal length over a metre long (likely
    /// authored in millimetres on a stage that is not in centimetres).
    void checkLens(const usd::Prim& camera);
    /// Warns about GeomSubset face indices outside the mesh (they are ignored).
    void checkSubsets(const usd::Prim& mesh);

    const usd::Stage& _stage;
    AdapterOptions _options;
    double _time;
    std::unordered_map<hd::Path, Entry> _entries;
    std::unordered_map<std::string, hd::Path> _instanceGroups;  ///< instance key -> instancer
    std::vector<hd::Path> _cameras;
    std::vector<std::string> _instancePrims;  ///< instanceable prims drawn through a group
    std::vector<std::string> _warnings;
    std::mutex _warningsMutex;  ///< warn() may be called from parallel rprim syncs
    std::unordered_set<std::string> _warningSet;  ///< each warning is reported once
    std::unordered_set<std::string> _unsupportedTypes;  ///< prim types reported as not drawn
    MaterialBindingResolver _bindings;
    /// Collection path (</Light.collection:lightLink> or :shadowLink) -> its membership, for
    /// the collections that do not hold everything.
    std::map<std::string, std::shared_ptr<const CollectionMembership>> _lightLinks;
    // Between primRemoving and primRemoved.
    const usd::Prim* _removing = nullptr;
    bool _removingHadInstances = false;
    std::vector<hd::Path> _removingDrawnBy;
    hd::Path _defaultCamera;
    glm::dmat4 _defaultCameraXform{1.0};
    float _defaultCameraFocal = 5.0f;
    glm::vec2 _defaultCameraClip{1.0f, 1e6f};
    // A PointInstancer's arrays and its instance indices by prototype index, read once and
    // shared by its prototypes' syncs (which run in parallel); dropped by every edit.
    struct InstancerCache {
        std::shared_ptr<const hd::InstancerArrays> arrays;
        std::shared_ptr<const std::vector<std::vector<int>>> byPrototype;
    };
    const InstancerCache& instancerCache(const hd::Path& instancerId, const Entry& inst) const;
    void invalidateInstancerCache();
    mutable std::mutex _instancerCacheMutex;
    mutable std::unordered_map<hd::Path, InstancerCache> _instancerCache;
};

}  // namespace principled::adapter
