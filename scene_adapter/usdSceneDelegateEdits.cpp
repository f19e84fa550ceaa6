// SPDX-License-Identifier: Apache-2.0
// UsdSceneDelegate, change processing: after the stage was edited, mark exactly the dirty bits
// each change implies (Hydra's change-tracking contract, reference/hydra.md section 2.4), or
// insert/remove index prims when the change is structural. The mapping, per change:
//   xformOp:*, xformOpOrder   Transform on every rprim, light, camera at or below the prim
//   visibility                Visibility on rprims and lights at or below
//   purpose                   the subtree is removed from and re-inserted into the index
//   points / radius           Points (a sphere's radius is its only "point")
//   normals                   Normals            primvars:*          Primvar
//   faceVertexCounts/Indices, holeIndices, orientation, subdivisionScheme   Topology
//   crease*/corner*, interpolateBoundary, ...   SubdivTags
//   doubleSided               DoubleSided        principled:refineLevel   DisplayStyle
//   implicit shape size/radius/height/axis      Points | Normals (regenerated mesh)
//   shader or material inputs:*   MaterialParams on that material sprim only (no rprim)
//   other shader attributes (info:id), outputs   Resource on that material
//   light attributes          Params             camera attributes   Params
//   PointInstancer arrays     Instancer / InstanceIndex on its prototype rprims
//   PointInstancer primvars:*   Instancer | Primvar on its prototype rprims (per instance, inherited)
//   primvars:* on other prims   Primvar on the rprims below (constant primvars are inherited)
//   material:binding          MaterialId on the rprims whose resolved material changed
//   GeomSubset changes        MaterialId on its mesh
// Edits that reach into instanceable prims' groups re-populate the groups (see repopulate).
#include <algorithm>
#include <functional>

#include "delegate/hd/tokens.h"
#include "scene_adapter/usdSceneDelegate.h"

#include "scene_adapter/skinning.h"
#include "scene_adapter/usda/stage.h"
#include "scene_adapter/xformOps.h"

namespace principled::adapter {

using namespace hd;

namespace {

const Token& instancerType() {
    static const Token t("instancer");  // as in usdSceneDelegateGeom.cpp
    return t;
}

bool isRprimType(const Token& t) {
    return t == tokens::mesh() || t == tokens::sphere() || t == tokens::pointsPrim() ||
           t == tokens::basisCurves();
}

bool isLightType(const Token& t) {
    return t == tokens::distantLight() || t == tokens::domeLight() || t == tokens::sphereLight() ||
           t == tokens::rectLight() || t == tokens::diskLight() || t == tokens::cylinderLight() ||
           t == tokens::portalLight();
}

bool isAtOrBelow(const std::string& path, const std::string& root) {
    if (root == "/") return !path.empty() && path[0] == '/';
    return path.size() >= root.size() && path.compare(0, root.size(), root) == 0 &&
           (path.size() == root.size() || path[root.size()] == '/');
}

bool startsWith(const std::string& s, const char* prefix) {
    return s.rfind(prefix, 0) == 0;
}

std::string tokenOf(const usd::Prim& prim, const char* name, double time,
                    const std::string& fallback) {
    if (const usd::Attribute* a = prim.attribute(name))
        if (auto s = a->get(time).getString()) return *s;
    return fallback;
}

DirtyBits meshAttributeBits(const std::string& a) {
    if (a == "points") return RprimDirty::Points;
    if (a == "normals" || a == "primvars:normals" || a == "primvars:normals:indices")
        return RprimDirty::Normals;
    if (startsWith(a, "primvars:")) return RprimDirty::Primvar;
    if (a == "faceVertexCounts" || a == "faceVertexIndices" || a == "holeIndices" ||
        a == "orientation" || a == "subdivisionScheme" || a == "curveVertexCounts" || a == "type" ||
        a == "basis" || a == "wrap")
        return RprimDirty::Topology;
    if (a == "widths") return RprimDirty::Widths;
    if (a == "interpolateBoundary" || a == "faceVaryingLinearInterpolation" ||
        a == "triangleSubdivisionRule" || startsWith(a, "crease") || startsWith(a, "corner"))
        return RprimDirty::SubdivTags;
    if (a == "doubleSided") return RprimDirty::DoubleSided;
    if (a == "principled:refineLevel") return RprimDirty::DisplayStyle;
    if (a == "extent") return RprimDirty::Extent;
    return RprimDirty::Clean;
}

}  // namespace

// ---- Lookups ------------------------------------------------------------------------------

UsdSceneDelegate::Ancestry UsdSceneDelegate::ancestry(const usd::Prim& prim) const {
    Ancestry a;
    std::vector<const usd::Prim*> chain;
    for (const usd::Prim* p = prim.parent(); p && p != _stage.pseudoRoot(); p = p->parent())
        chain.push_back(p);
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
        const usd::Prim& p = **it;
        if (!p.isActive() || p.isAbstract()) a.drawn = false;
        std::string purpose = tokenOf(p, "purpose", _time, "default");
        if (purpose == "guide" || purpose == "proxy") a.drawn = false;
        std::string warning;
        LocalTransform local = computeLocalTransform(p, _time, &warning);
        a.parentWorld = local.resetsXformStack ? local.matrix : a.parentWorld * local.matrix;
        a.parentVisible =
            a.parentVisible && tokenOf(p, "visibility", _time, "inherited") != "invisible";
        if (p.typeName() == "PointInstancer") a.pointInstancer = &p;
    }
    return a;
}

std::vector<Path> UsdSceneDelegate::idsOf(const usd::Prim* prim) const {
    std::vector<Path> ids;
    for (const auto& [id, e] : _entries)
        if (e.prim == prim) ids.push_back(id);
    std::sort(ids.begin(), ids.end());
    return ids;
}

std::string UsdSceneDelegate::enclosingInstance(const std::string& path) const {
    const usd::Prim* p = _stage.prim(path);
    for (p = p ? p->parent() : nullptr; p; p = p->parent())
        if (p->isInstance()) return p->path();
    return "";
}

bool UsdSceneDelegate::subtreeHasInstances(const std::string& path) const {
    for (const std::string& inst : _instancePrims)
        if (isAtOrBelow(inst, path)) return true;
    return !enclosingInstance(path).empty();
}

std::vector<Path> UsdSceneDelegate::instancersDrawing(const std::string& path) const {
    std::vector<Path> out;
    for (const auto& [id, e] : _entries) {
        if (e.type != instancerType() || e.instanceXforms || !e.prim) continue;
        const std::string& ip = e.prim->path();
        if (isAtOrBelow(ip, path)) continue;  // inside the subtree: handled with it
        bool draws = isAtOrBelow(path, ip);   // strictly inside the instancer
        if (const usd::Relationship* r = e.prim->relationship("prototypes"))
            for (const std::string& t : r->targets())
                draws = draws || isAtOrBelow(path, t) || isAtOrBelow(t, path);
        if (draws) out.push_back(id);
    }
    std::sort(out.begin(), out.end());
    return out;
}

// ---- Structural changes -------------------------------------------------------------------

void UsdSceneDelegate::removeEntry(const Path& id, RenderIndex* index) {
    auto it = _entries.find(id);
    if (it == _entries.end()) return;
    const Token& t = it->second.type;
    if (isRprimType(t))
        index->removeRprim(id);
    else if (t != instancerType())
        index->removeSprim(id);
    _cameras.erase(std::remove(_cameras.begin(), _cameras.end(), id), _cameras.end());
    _entries.erase(it);
}

void UsdSceneDelegate::resyncSubtree(const std::string& path, RenderIndex* index) {
    invalidateInstancerCache();  // any edit may change an instancer's arrays or entries
    if (subtreeHasInstances(path)) {
        repopulate(index);
        return;
    }
    std::vector<Path> drawing = instancersDrawing(path);
    std::vector<Path> gone;
    for (const auto& [id, e] : _entries)
        if ((e.prim && isAtOrBelow(e.prim->path(), path)) || isAtOrBelow(id.str(), path))
            gone.push_back(id);
    for (const Path& id : gone) removeEntry(id, index);
    if (const usd::Prim* p = _stage.prim(path)) {
        Ancestry a = ancestry(*p);
        if (a.drawn && !a.pointInstancer) visit(*p, a.parentWorld, a.parentVisible, index);
    }
    for (const Path& inst : drawing) {
        const Entry* e = entry(inst);
        if (e && e->prim) resyncSubtree(e->prim->path(), index);
    }
}

void UsdSceneDelegate::repopulate(RenderIndex* index) {
    invalidateInstancerCache();  // any edit may change an instancer's arrays or entries
    // Instanceable prims share prototypes through synthetic instancers whose per-instance
    // matrices are gathered in one traversal; re-running it is the simple exact answer.
    std::vector<Path> all;
    for (const auto& [id, e] : _entries)
        if (id != _defaultCamera) all.push_back(id);
    for (const Path& id : all) removeEntry(id, index);
    _instanceGroups.clear();
    _instancePrims.clear();
    _cameras.clear();
    populate(index);
}

void UsdSceneDelegate::primAdded(const std::string& path, RenderIndex* index) {
    _skeletonPoses.clear();  // any edit may change a skeleton's pose
    invalidateInstancerCache();  // any edit may change an instancer's arrays or entries
    const usd::Prim* p = _stage.prim(path);
    if (!p) return;
    if (subtreeHasInstances(path)) {
        repopulate(index);
        return;
    }
    std::vector<Path> drawing = instancersDrawing(path);
    Ancestry a = ancestry(*p);
    if (a.drawn && !a.pointInstancer) visit(*p, a.parentWorld, a.parentVisible, index);
    for (const Path& inst : drawing)
        if (const Entry* e = entry(inst); e && e->prim) resyncSubtree(e->prim->path(), index);
    const std::string& type = p->typeName();
    // A new light, or a prim that a link collection holds or includes a collection from.
    if (!_lightLinks.empty() || (type.size() > 5 && type.compare(type.size() - 5, 5, "Light") == 0))
        refreshLightLinks(index);
    if (type == "Material") rebind("/", "", index);  // bindings waiting for it now resolve
    if (type == "Shader" || type == "NodeGraph")
        materialNetworkChanged(*p, SprimDirty::Resource, index);
    if (type == "GeomSubset" && p->parent()) subsetsChanged(*p->parent(), index);
}

void UsdSceneDelegate::primRemoving(const std::string& path, RenderIndex* index) {
    _skeletonPoses.clear();  // any edit may change a skeleton's pose
    invalidateInstancerCache();  // any edit may change an instancer's arrays or entries
    _removing = _stage.prim(path);
    _removingHadInstances = subtreeHasInstances(path);
    _removingDrawnBy = instancersDrawing(path);
    std::vector<Path> gone;
    for (const auto& [id, e] : _entries)
        if ((e.prim && isAtOrBelow(e.prim->path(), path)) || isAtOrBelow(id.str(), path))
            gone.push_back(id);
    for (const Path& id : gone) removeEntry(id, index);
}

void UsdSceneDelegate::primRemoved(const std::string& path, RenderIndex* index) {
    _skeletonPoses.clear();  // any edit may change a skeleton's pose
    invalidateInstancerCache();  // any edit may change an instancer's arrays or entries
    // A skeleton or animation may have gone: skinned meshes are posed again (or unposed).
    if (hasSkinnedMeshes()) reposeSkinned([](const Entry& e) { return e.skinned != nullptr; }, index);
    const usd::Prim* removed = _removing;
    _removing = nullptr;
    if (_removingHadInstances) {
        repopulate(index);
        return;
    }
    for (const Path& inst : _removingDrawnBy)
        if (const Entry* e = entry(inst); e && e->prim) resyncSubtree(e->prim->path(), index);
    // Prims bound to a removed material fall back to the default material. With collection
    // bindings anything may have depended on the removed prim (a collection, a Material one
    // reaches): every prim is resolved again.
    rebind(_bindings.sawCollectionBindings() ? "/" : "", path, index);
    if (!removed) return;
    const std::string& type = removed->typeName();
    if (!_lightLinks.empty() || (type.size() > 5 && type.compare(type.size() - 5, 5, "Light") == 0))
        refreshLightLinks(index);
    const usd::Prim* parent = removed->parent();  // still allocated (StageEdit keeps it)
    if ((type == "Shader" || type == "NodeGraph") && parent)
        materialNetworkChanged(*parent, SprimDirty::Resource, index);
    if (type == "GeomSubset" && parent) subsetsChanged(*parent, index);
}

// ---- Value changes ------------------------------------------------------------------------

void UsdSceneDelegate::transformChanged(const usd::Prim& prim, RenderIndex* index) {
    invalidateInstancerCache();  // any edit may change an instancer's arrays or entries
    if (subtreeHasInstances(prim.path())) {
        repopulate(index);
        return;
    }
    Ancestry a = ancestry(prim);
    if (a.pointInstancer) {  // prototype placement relative to the instancer
        resyncSubtree(a.pointInstancer->path(), index);
        return;
    }
    ChangeTracker& tracker = index->changeTracker();
    std::vector<Path> prototypeOf;  // instancers outside the subtree using prims in it
    for (const Path& inst : instancersDrawing(prim.path())) prototypeOf.push_back(inst);
    std::function<void(const usd::Prim&, const glm::dmat4&)> walk =
        [&](const usd::Prim& p, const glm::dmat4& parentWorld) {
            std::string warning;
            LocalTransform local = computeLocalTransform(p, _time, &warning);
            if (!warning.empty()) warn(p.location().str() + ": " + p.path(), warning);
            glm::dmat4 world = local.resetsXformStack ? local.matrix : parentWorld * local.matrix;
            auto it = _entries.find(Path(p.path()));
            if (it != _entries.end() && it->second.instancer.empty()) {
                Entry& e = it->second;
                e.world = world;
                if (isRprimType(e.type)) {
                    tracker.markRprimDirty(it->first, RprimDirty::Transform);
                } else if (e.type == tokens::camera() || isLightType(e.type)) {
                    tracker.markSprimDirty(it->first, SprimDirty::Transform);
                } else if (e.type == instancerType()) {
                    // Prototypes are placed relative to the instancer: re-place the instances.
                    for (const auto& [id, proto] : _entries)
                        if (proto.instancer == it->first)
                            tracker.markRprimDirty(id, RprimDirty::Transform);
                }
            }
            if (p.typeName() == "PointInstancer") return;  // below: relative to it
            for (const usd::Prim* child : p.children()) walk(*child, world);
        };
    walk(prim, a.parentWorld);
    for (const Path& inst : prototypeOf)
        if (const Entry* e = entry(inst); e && e->prim) resyncSubtree(e->prim->path(), index);
}

void UsdSceneDelegate::visibilityChanged(const usd::Prim& prim, RenderIndex* index) {
    invalidateInstancerCache();  // any edit may change an instancer's arrays or entries
    if (subtreeHasInstances(prim.path())) {
        repopulate(index);
        return;
    }
    Ancestry a = ancestry(prim);
    if (a.pointInstancer) {
        resyncSubtree(a.pointInstancer->path(), index);
        return;
    }
    ChangeTracker& tracker = index->changeTracker();
    std::vector<std::string> instancers;
    std::function<void(const usd::Prim&, bool)> walk = [&](const usd::Prim& p, bool parentVisible) {
        bool visible = parentVisible && tokenOf(p, "visibility", _time, "inherited") != "invisible";
        auto it = _entries.find(Path(p.path()));
        if (it != _entries.end() && it->second.instancer.empty()) {
            Entry& e = it->second;
            e.visible = visible;
            if (isRprimType(e.type))
                tracker.markRprimDirty(it->first, RprimDirty::Visibility);
            else if (isLightType(e.type))
                tracker.markSprimDirty(it->first, SprimDirty::Visibility);
        }
        if (p.typeName() == "PointInstancer") {  // prototypes carry the instancer's visibility
            instancers.push_back(p.path());
            return;
        }
        for (const usd::Prim* child : p.children()) walk(*child, visible);
    };
    walk(prim, a.parentVisible);
    for (const std::string& inst : instancers) resyncSubtree(inst, index);
}

void UsdSceneDelegate::inheritedPrimvarChanged(const usd::Prim& prim, RenderIndex* index) {
    // A constant primvar on an ancestor is inherited by the rprims below that do not author
    // their own (UsdGeomPrimvarsAPI::FindInheritablePrimvars); instance groups are keyed by it.
    if (subtreeHasInstances(prim.path())) return repopulate(index);
    ChangeTracker& tracker = index->changeTracker();
    std::function<void(const usd::Prim&)> walk = [&](const usd::Prim& p) {
        for (const Path& id : idsOf(&p)) {
            const Entry& e = _entries[id];
            if (isRprimType(e.type)) tracker.markRprimDirty(id, RprimDirty::Primvar);
            else if (e.type == instancerType() && !e.instanceXforms)
                for (const auto& [protoId, proto] : _entries)
                    if (proto.instancer == id) tracker.markRprimDirty(protoId, RprimDirty::Primvar);
        }
        for (const usd::Prim* child : p.children()) walk(*child);
    };
    walk(prim);
}

void UsdSceneDelegate::subsetsChanged(const usd::Prim& mesh, RenderIndex* index) {
    for (const Path& id : idsOf(&mesh)) {
        Entry& e = _entries[id];
        if (!isRprimType(e.type)) continue;
        index->changeTracker().markRprimDirty(id, RprimDirty::MaterialId);
        if (e.prim) e.subsetMaterials = subsetBindings(*e.prim);
    }
}

void UsdSceneDelegate::collectionChanged(RenderIndex* index) {
    // Membership can reach any prim below a collection binding: every binding is resolved
    // again (instance groups are keyed by bindings and links, so a stage with instances is
    // rebuilt, links included).
    if (subtreeHasInstances("/")) return repopulate(index);
    refreshLightLinks(index);
    rebind("/", "", index);
}

void UsdSceneDelegate::refreshLightLinks(RenderIndex* index) {
    // Any light's link may now hold other prims: every rprim asks for its categories again
    // (through MaterialId) and every light for its link.
    const bool hadLinks = !_lightLinks.empty();
    readLightLinks();
    if (!hadLinks && _lightLinks.empty()) return;
    // Instance groups are keyed by link membership (lightLinkKey): regroup them.
    if (subtreeHasInstances("/")) return repopulate(index);
    ChangeTracker& tracker = index->changeTracker();
    for (const auto& [id, e] : _entries) {
        if (isRprimType(e.type)) tracker.markRprimDirty(id, RprimDirty::MaterialId);
        else if (isLightType(e.type)) tracker.markSprimDirty(id, SprimDirty::Params);
    }
}

void UsdSceneDelegate::rebind(const std::string& root, const std::string& material,
                              RenderIndex* index) {

    auto subsetTargets = [&](const usd::Prim& mesh) {
        for (const usd::Prim* child : mesh.children()) {
            if (child->typeName() != "GeomSubset") continue;
            for (const usd::Relationship* r : child->relationships())
                if (startsWith(r->name(), "material:binding"))
                    for (const std::string& t : r->targets())
                        if (isAtOrBelow(t, material)) return true;
        }
        return false;
    };
    for (auto& [id, e] : _entries) {
        if (!isRprimType(e.type) || !e.prim) continue;
        bool resolve =
            (!root.empty() && isAtOrBelow(e.prim->path(), root)) ||
            (!material.empty() && !e.material.empty() && isAtOrBelow(e.material.str(), material));
        bool dirty = false;
        if (resolve) {
            Path now = resolveMaterialBinding(*e.prim);
            dirty = now != e.material;
            e.material = now;
        }
        if (!material.empty() && subsetTargets(*e.prim)) dirty = true;
        // Subsets may bind through collections or bindings above the mesh.
        if (resolve) {
            std::string subsets = subsetBindings(*e.prim);
            dirty = dirty || subsets != e.subsetMaterials;
            e.subsetMaterials = std::move(subsets);
        }
        if (dirty) index->changeTracker().markRprimDirty(id, RprimDirty::MaterialId);
    }
}

void UsdSceneDelegate::materialNetworkChanged(const usd::Prim& prim, DirtyBits bits,
                                              RenderIndex* index) {
    // A network lives under its Material: the enclosing material sprim is the one to mark.
    for (const usd::Prim* p = &prim; p; p = p->parent()) {
        if (p->typeName() != "Material") continue;
        Path id(p->path());
        if (const Entry* e = entry(id); e && e->type == tokens::material()) {
            index->changeTracker().markSprimDirty(id, bits);
            return;
        }
    }
    // A shader outside any material: every material whose network uses it.
    Path node(prim.path());
    for (const auto& [id, e] : _entries)
        if (e.type == tokens::material() && getMaterialResource(id).node(node))
            index->changeTracker().markSprimDirty(id, bits);
}

void UsdSceneDelegate::reposeSkinned(const std::function<bool(const Entry&)>& which, RenderIndex* index) {
    _skeletonPoses.clear();  // the edit may have changed any skeleton's pose
    ChangeTracker& tracker = index->changeTracker();
    for (auto& [id, e] : _entries) {
        if (!e.prim || e.prim->typeName() != "Mesh" || !e.instancer.empty() || !which(e)) continue;
        std::vector<std::string> warnings;
        std::optional<SkinnedMesh> posed = skinMesh(_stage, *e.prim, _time, &warnings, &_skeletonPoses);
        for (const std::string& w : warnings) warn(e.prim->location().str() + ": " + e.prim->path(), w);
        if (!posed && !e.skinned) continue;
        if (posed) {
            e.world = posed->world;
            e.skinned = std::make_shared<const SkinnedMesh>(std::move(*posed));
            _anySkinned = true;
        } else {  // no longer skinned: its own points and transform again
            e.skinned.reset();
            e.world = worldTransform(*e.prim, _time);
        }
        tracker.markRprimDirty(id, RprimDirty::Points | RprimDirty::Normals | RprimDirty::Transform |
                                       RprimDirty::Primvar);
    }
}

void UsdSceneDelegate::skeletonSpaceMoved(const std::string& moved, RenderIndex* index) {
    // Posed points live in the skeleton's space: only the transform follows it.
    ChangeTracker& tracker = index->changeTracker();
    auto atOrBelow = [&](const std::string& path) {
        return path == moved || moved == "/" || path.rfind(moved + "/", 0) == 0;
    };
    _skeletonPoses.clear();  // their poses hold the skeletons' old world transforms
    for (auto& [id, e] : _entries) {
        if (!e.skinned || !(atOrBelow(e.skinned->skeleton) || atOrBelow(e.prim->path()))) continue;
        if (!e.skinned->inSkeletonSpace)
            e.world = worldTransform(*e.prim, _time);  // blend shapes alone: the mesh's own
        else if (const usd::Prim* skel = _stage.prim(e.skinned->skeleton))
            e.world = worldTransform(*skel, _time);
        tracker.markRprimDirty(id, RprimDirty::Transform);
    }
}

void UsdSceneDelegate::attributeChanged(const std::string& primPath, const std::string& attr,
                                        RenderIndex* index) {
    _skeletonPoses.clear();  // any edit may change a skeleton's pose
    invalidateInstancerCache();  // any edit may change an instancer's arrays or entries
    const usd::Prim* p = _stage.prim(primPath);
    if (!p) return;
    if (startsWith(attr, "xformOp:") || attr == "xformOpOrder") {
        transformChanged(*p, index);
        if (hasSkinnedMeshes()) skeletonSpaceMoved(primPath, index);  // and a skinned mesh's own is ignored
        return;
    }
    // UsdSkel: a skeleton, its animation or a binding changed: every mesh is checked again
    // (one that did not skin may now); a mesh's own points or normals: that mesh.
    if (p->typeName() == "Skeleton" || p->typeName() == "SkelAnimation" || p->typeName() == "BlendShape" ||
        startsWith(attr, "primvars:skel:") || startsWith(attr, "skel:"))
        return reposeSkinned([](const Entry&) { return true; }, index);
    if ((attr == "points" || attr == "normals" || attr == "primvars:normals") && p->typeName() == "Mesh") {
        reposeSkinned([&](const Entry& e) { return e.prim == p; }, index);
        if (const Entry* e = entry(Path(primPath)); e && e->skinned) return;  // posed: nothing else to mark
    }
    if (attr == "visibility") return visibilityChanged(*p, index);
    if (attr == "purpose") return resyncSubtree(primPath, index);
    if (startsWith(attr, "collection:")) return collectionChanged(index);
    const std::string& type = p->typeName();
    ChangeTracker& tracker = index->changeTracker();
    if (type == "Shader" || type == "NodeGraph")
        return materialNetworkChanged(
            *p, startsWith(attr, "inputs:") ? SprimDirty::MaterialParams : SprimDirty::Resource,
            index);
    if (type == "GeomSubset") {
        if (p->parent()) subsetsChanged(*p->parent(), index);
        return;
    }
    if (type == "PointInstancer" && attr == "prototypes") return resyncSubtree(primPath, index);
    if (startsWith(attr, "primvars:") && type != "PointInstancer") {
        const Entry* own = entry(Path(primPath));
        if (!own || !isRprimType(own->type)) return inheritedPrimvarChanged(*p, index);
    }
    for (const Path& id : idsOf(p)) {
        Entry& e = _entries[id];
        if (isRprimType(e.type)) {
            DirtyBits bits = meshAttributeBits(attr);
            if (e.type == tokens::sphere() && attr == "radius") bits = RprimDirty::Points;
            if (e.shape &&
                (attr == "size" || attr == "radius" || attr == "height" || attr == "axis" || attr == "width" ||
                 attr == "length")) {
                prepareShape(*p, &e);  // keeps the previous mesh (and warns) when invalid
                bits = RprimDirty::Points | RprimDirty::Normals;
            }
            if (bits) tracker.markRprimDirty(id, bits);
        } else if (e.type == tokens::material()) {
            tracker.markSprimDirty(id, startsWith(attr, "inputs:") ? SprimDirty::MaterialParams
                                                                   : SprimDirty::Resource);
        } else if (e.type == tokens::camera()) {
            tracker.markSprimDirty(id, SprimDirty::Params);
        } else if (isLightType(e.type)) {
            bool texture = attr == "inputs:texture:file" || attr == "texture:file";
            tracker.markSprimDirty(id, texture ? SprimDirty::Resource : SprimDirty::Params);
        } else if (e.type == instancerType() && !e.instanceXforms) {
            DirtyBits bits = 0;
            if (attr == "positions" || attr == "orientations" || attr == "scales" || attr == "velocities" ||
                attr == "accelerations")
                bits = RprimDirty::Instancer;
            else if (startsWith(attr, "primvars:"))  // per instance (the records), or inherited
                bits = RprimDirty::Instancer | RprimDirty::Primvar;
            else if (attr == "protoIndices" || attr == "ids" || attr == "invisibleIds")
                bits = RprimDirty::InstanceIndex;
            if (bits)
                for (const auto& [protoId, proto] : _entries)
                    if (proto.instancer == id) tracker.markRprimDirty(protoId, bits);
        }
    }
}

void UsdSceneDelegate::relationshipChanged(const std::string& primPath, const std::string& name,
                                           RenderIndex* index) {
    _skeletonPoses.clear();  // any edit may change a skeleton's pose
    invalidateInstancerCache();  // any edit may change an instancer's arrays or entries
    const usd::Prim* p = _stage.prim(primPath);
    if (!p) return;
    if (startsWith(name, "collection:")) return collectionChanged(index);
    if (startsWith(name, "skel:")) return reposeSkinned([](const Entry&) { return true; }, index);
    if (startsWith(name, "material:binding")) {
        if (p->typeName() == "GeomSubset") return attributeChanged(primPath, name, index);
        if (subtreeHasInstances(primPath)) return repopulate(index);  // keys hold the binding
        return rebind(primPath, "", index);
    }
    if (name == "prototypes" && p->typeName() == "PointInstancer") resyncSubtree(primPath, index);
}

}  // namespace principled::adapter
