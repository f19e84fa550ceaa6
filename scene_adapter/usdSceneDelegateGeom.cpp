// SPDX-License-Identifier: Apache-2.0
// UsdSceneDelegate, geometry beyond Mesh and Sphere: implicit shapes served as meshes,
// GeomSubset material bindings, and PointInstancers (prototype rprims drawn only through
// their instancer, Hydra-style: getInstancerId / getInstanceIndices / instancer arrays).
#include <algorithm>
#include <cmath>
#include <set>
#include <unordered_set>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "delegate/hd/tokens.h"
#include "scene_adapter/implicitShapes.h"
#include "scene_adapter/primvars.h"
#include "scene_adapter/purpose.h"
#include "scene_adapter/usdSceneDelegate.h"
#include "scene_adapter/usda/stage.h"
#include "scene_adapter/valueConvert.h"
#include "scene_adapter/xformOps.h"

namespace principled::adapter {

using namespace hd;

namespace {

const Token& instancerType() {
    static const Token t("instancer");  // adapter-only entry type; not inserted in the index
    return t;
}

std::string tokenOf(const usd::Prim& prim, const char* name, double time, const std::string& fallback) {
    if (const usd::Attribute* a = prim.attribute(name))
        if (auto s = a->get(time).getString()) return *s;
    return fallback;
}

std::vector<int> intArray(const Value& v) {
    if (auto* a = getIf<std::vector<int>>(v)) return *a;
    return {};
}

// An int64[] attribute as the parser's doubles (exact to 2^53; an int conversion of larger
// ids was undefined), or empty.
std::vector<double> idArray(const usd::Prim& prim, const char* name, double time) {
    const usd::Attribute* a = prim.attribute(name);
    if (!a || !a->hasValue()) return {};
    const usd::Value v = a->get(time);
    const std::vector<double>* n = v.numbers();
    return n ? *n : std::vector<double>{};
}

// The time sample of `a` at or before `time` (the first one before them all); nullopt without
// samples.
std::optional<double> lowerSample(const usd::Attribute& a, double time) {
    const auto& samples = a.timeSamples();
    if (samples.empty()) return std::nullopt;
    auto it = samples.upper_bound(time);
    return it == samples.begin() ? it->first : std::prev(it)->first;
}

}  // namespace

bool UsdSceneDelegate::prepareShape(const usd::Prim& prim, Entry* e) {
    ShapeParams params = shapeFallbacks(prim.typeName());
    auto number = [&](const char* name, double fallback) {
        auto f = getFloat(attributeValue(prim, name));
        return f ? double(*f) : fallback;
    };
    params.size = number("size", params.size);
    params.radius = number("radius", params.radius);
    params.height = number("height", params.height);
    params.width = number("width", params.width);
    params.length = number("length", params.length);
    std::string axis = tokenOf(prim, "axis", _time, "Z");
    if (axis != "X" && axis != "Y" && axis != "Z") {
        warn(prim.location().str() + ": " + prim.path(), "axis '" + axis + "' is not X, Y or Z; using Z");
        axis = "Z";
    }
    params.axis = axis[0];
    auto mesh = std::make_shared<ShapeMesh>();
    std::string error;
    if (!buildImplicitShape(prim.typeName(), params, mesh.get(), &error)) {
        warn(prim.location().str() + ": " + prim.path(), prim.typeName() + " not rendered: " + error);
        return false;
    }
    e->shape = std::move(mesh);
    return true;
}

Value UsdSceneDelegate::shapeOrInstancerValue(const Entry& e, const Token& key) const {
    if (e.shape) {
        if (key == tokens::points()) return Value(e.shape->points);
        if (key == tokens::normals()) return Value(e.shape->normals);
        return {};
    }
    if (e.type == instancerType() && e.instanceXforms) {
        if (key == tokens::instanceTransforms()) return Value(*e.instanceXforms);
        return {};
    }
    if (e.type == instancerType()) {
        if (key == tokens::instanceTranslations()) return instancerPositions(*e.prim);
        if (key == tokens::instanceRotations()) return attributeValue(*e.prim, "orientations");
        if (key == tokens::instanceScales()) return attributeValue(*e.prim, "scales");
    }
    return {};
}

std::vector<std::pair<Path, std::vector<int>>> UsdSceneDelegate::getMaterialSubsets(const Path& id) const {
    std::vector<std::pair<Path, std::vector<int>>> out;
    const usd::Prim* p = prim(id);
    if (!p || p->typeName() != "Mesh") return out;
    const Entry* meshEntry = entry(id);
    for (const usd::Prim* child : p->children()) {
        if (child->typeName() != "GeomSubset" || !child->isActive()) continue;
        if (tokenOf(*child, "familyName", _time, "") != "materialBind") continue;
        if (tokenOf(*child, "elementType", _time, "face") != "face") continue;
        // The subset's resolved binding (its own, a collection holding it, or a stronger one
        // above); faces whose subset resolves to the mesh's material need no split.
        const std::string m = _bindings.resolve(*child);
        if (!m.empty() && (!meshEntry || Path(m) != meshEntry->material))
            out.emplace_back(Path(m), intArray(attributeValue(*child, "indices")));
    }
    return out;
}

Value UsdSceneDelegate::instancerPositions(const usd::Prim& prim) const {
    // UsdGeomPointInstancer: when velocities (and accelerations) have a sample at the
    // positions' sample at or before the time, the positions move on from that sample,
    // p + v dt + a dt^2 / 2 with dt in seconds (a particle cache sampled once per frame, rendered
    // between its frames); otherwise they interpolate like any attribute.
    Value interpolated = attributeValue(prim, "positions");
    const usd::Attribute* pa = prim.attribute("positions");
    const usd::Attribute* va = prim.attribute("velocities");
    if (!pa || !va) return interpolated;
    const std::optional<double> s = lowerSample(*pa, _time);
    if (!s || lowerSample(*va, _time) != s) return interpolated;
    const Value pv = toHdValue(pa->get(*s)), vv = toHdValue(va->get(*s));
    auto* p = getIf<std::vector<glm::vec3>>(pv);
    auto* v = getIf<std::vector<glm::vec3>>(vv);
    if (!p || !v || v->size() != p->size()) return interpolated;
    const double tcps = _stage.timeCodesPerSecond();
    const float dt = float((_time - *s) / (tcps > 0.0 ? tcps : 24.0));
    std::vector<glm::vec3> out(*p);
    for (size_t i = 0; i < out.size(); ++i) out[i] += (*v)[i] * dt;
    if (const usd::Attribute* aa = prim.attribute("accelerations"); aa && lowerSample(*aa, _time) == s) {
        const Value av = toHdValue(aa->get(*s));
        if (auto* a = getIf<std::vector<glm::vec3>>(av); a && a->size() == out.size())
            for (size_t i = 0; i < out.size(); ++i) out[i] += (*a)[i] * (0.5f * dt * dt);
    }
    for (const glm::vec3& q : out)
        if (!std::isfinite(q.x) || !std::isfinite(q.y) || !std::isfinite(q.z)) return interpolated;
    return Value(std::move(out));
}

Path UsdSceneDelegate::getInstancerId(const Path& id) const {
    const Entry* e = entry(id);
    return e ? e->instancer : Path();
}

const UsdSceneDelegate::InstancerCache& UsdSceneDelegate::instancerCache(const Path& instancerId,
                                                                        const Entry& inst) const {
    // Built under the lock: the prototypes of one instancer sync at once, and the first builds it
    // for all (others wait instead of each converting the arrays again).
    std::lock_guard<std::mutex> lock(_instancerCacheMutex);
    InstancerCache& c = _instancerCache[instancerId];
    if (c.arrays) return c;
    std::shared_ptr<hd::InstancerArrays> arrays =
        hd::readInstancerArrays([&](const Token& key) { return shapeOrInstancerValue(inst, key); });
    auto byPrototype = std::make_shared<std::vector<std::vector<int>>>();
    if (inst.prim && !inst.instanceXforms) {
        std::vector<int> protoIndices = intArray(attributeValue(*inst.prim, "protoIndices"));
        const std::vector<double> ids = idArray(*inst.prim, "ids", _time);
        // Hidden: invisibleIds (an attribute) and inactiveIds (an int64 list-op metadata).
        std::vector<double> off = idArray(*inst.prim, "invisibleIds", _time);
        if (const usd::Value* inactive = inst.prim->metadata("inactiveIds"))
            if (const std::vector<double>* n = inactive->numbers()) off.insert(off.end(), n->begin(), n->end());
        std::unordered_set<double> hidden(off.begin(), off.end());
        const bool useIds = ids.size() == protoIndices.size();  // ids, when authored, name the instances
        for (size_t i = 0; i < protoIndices.size(); ++i) {
            const int p = protoIndices[i];
            if (p < 0 || p > 1000000) continue;  // no prototype has that index
            if (!hidden.empty() && hidden.count(useIds ? ids[i] : double(i))) continue;
            if (size_t(p) >= byPrototype->size()) byPrototype->resize(size_t(p) + 1);
            (*byPrototype)[size_t(p)].push_back(int(i));
        }
    }
    c.arrays = std::move(arrays);
    c.byPrototype = std::move(byPrototype);
    return c;
}

void UsdSceneDelegate::invalidateInstancerCache() {
    {
        std::lock_guard<std::mutex> lock(_instancerCacheMutex);
        _instancerCache.clear();
    }
    _bindings.invalidate();  // collections may have been edited too
}

std::shared_ptr<const hd::InstancerArrays> UsdSceneDelegate::getInstancerArrays(const Path& instancerId) const {
    const Entry* inst = entry(instancerId);
    if (!inst) return std::make_shared<hd::InstancerArrays>();
    return instancerCache(instancerId, *inst).arrays;
}

std::vector<int> UsdSceneDelegate::getInstanceIndices(const Path& instancerId,
                                                      const Path& prototypeId) const {
    std::vector<int> out;
    const Entry* inst = entry(instancerId);
    const Entry* proto = entry(prototypeId);
    if (!inst || !proto || proto->instancer != instancerId || !inst->prim) return out;
    if (inst->instanceXforms) {  // instanceable prims: every (visible) instance
        out.resize(inst->instanceXforms->size());
        for (size_t i = 0; i < out.size(); ++i) out[i] = int(i);
        return out;
    }
    const auto& byPrototype = *instancerCache(instancerId, *inst).byPrototype;
    if (proto->protoIndex >= 0 && size_t(proto->protoIndex) < byPrototype.size())
        out = byPrototype[size_t(proto->protoIndex)];
    return out;
}

// True when a subtree holds only what a prototype can draw (gprims, their materials and
// grouping prims): instances holding lights, cameras or PointInstancers are expanded instead.
static bool onlyPrototypeGeometry(const usd::Prim& prim) {
    static const std::set<std::string> ok{"", "Xform", "Scope", "Mesh", "Sphere", "Points", "BasisCurves", "Cube", "Cylinder",
                                          "Cone", "Capsule", "Material", "Shader", "NodeGraph",
                                          "GeomSubset"};
    if (!ok.count(prim.typeName())) return false;
    for (const usd::Prim* child : prim.children())
        if (child->isActive() && !onlyPrototypeGeometry(*child)) return false;
    return true;
}

bool UsdSceneDelegate::visitInstance(const usd::Prim& prim, const glm::dmat4& world, bool visible,
                                     RenderIndex* index) {
    const std::string& type = prim.typeName();
    if (type == "Mesh" || type == "Sphere" || type == "Points" || type == "BasisCurves" ||
        type == "PointInstancer" || isImplicitShape(type))
        return false;  // an instanceable gprim is simply drawn
    if (!onlyPrototypeGeometry(prim)) return false;
    // Instances of one prototype share its BLAS unless an inherited binding, light links or the
    // constant primvars its rprims inherit from the instance and its ancestors (a per-asset
    // displayColor, say) differ.
    std::string key = prim.instanceKey() + "|" + _bindings.inheritedKey(prim) + "|" + lightLinkKey(prim) + "|" +
                      inheritablePrimvarKey(prim, _time);
    auto it = _instanceGroups.find(key);
    if (it == _instanceGroups.end()) {
        // The first instance's subtree is the prototype; its rprims keep their own paths and
        // are drawn only through a synthetic instancer placing every instance.
        Path instancer = Path("/__principled/instancers").appendChild("i" + std::to_string(_instanceGroups.size()));
        Entry e;
        e.prim = &prim;
        e.type = instancerType();
        e.instanceXforms = std::make_shared<std::vector<glm::dmat4>>();
        _entries[instancer] = e;
        it = _instanceGroups.emplace(key, instancer).first;
        for (const usd::Prim* child : prim.children())
            visitPrototype(*child, Path(child->path()), glm::dmat4(1.0), true, instancer, 0, index);
    }
    if (visible) _entries[it->second].instanceXforms->push_back(world);
    _instancePrims.push_back(prim.path());
    return true;
}

void UsdSceneDelegate::visitPointInstancer(const usd::Prim& prim, const glm::dmat4& world,
                                           bool visible, RenderIndex* index) {
    Path id(prim.path());
    Entry e;
    e.prim = &prim;
    e.type = instancerType();
    e.world = world;
    e.visible = visible;
    _entries[id] = e;
    const usd::Relationship* rel = prim.relationship("prototypes");
    if (!rel || rel->targets().empty()) {
        warn(prim.location().str() + ": " + prim.path(), "PointInstancer has no prototypes");
        return;
    }
    for (size_t k = 0; k < rel->targets().size(); ++k) {
        const std::string& target = rel->targets()[k];
        const usd::Prim* proto = _stage.prim(target);
        if (!proto) {
            warn(rel->location().str() + ": " + prim.path(), "prototype '" + target + "' does not exist");
            continue;
        }
        // A prototype outside the instancer is also drawn where it is; its instanced copy
        // needs an id of its own.
        Path protoId = Path(target).hasPrefix(id) ? Path(target) : id.appendChild("__prototype" + std::to_string(k));
        visitPrototype(*proto, protoId, glm::dmat4(1.0), visible, id, int(k), index);
    }
}

void UsdSceneDelegate::visitPrototype(const usd::Prim& prim, const Path& id, const glm::dmat4& parentRel,
                                      bool parentVisible, const Path& instancer, int protoIndex,
                                      RenderIndex* index) {
    if (!prim.isActive() || prim.isAbstract()) return;
    const std::string& type = prim.typeName();
    if (type == "Material") {
        visit(prim, glm::dmat4(1.0), true, index);
        return;
    }
    std::string warning;
    LocalTransform local = computeLocalTransform(prim, _time, &warning);
    if (!warning.empty()) warn(prim.location().str() + ": " + prim.path(), warning);
    // Relative to the instancer: the prototype root's own ops and everything below it.
    glm::dmat4 rel = local.resetsXformStack ? local.matrix : parentRel * local.matrix;
    bool visible = parentVisible && tokenOf(prim, "visibility", _time, "inherited") != "invisible";
    if (type == "PointInstancer") {
        warn(prim.location().str() + ": " + prim.path(), "nested PointInstancers are not supported yet; skipped");
        return;
    }
    bool shape = isImplicitShape(type);
    if ((type == "Mesh" || type == "Sphere" || type == "Points" || type == "BasisCurves" || shape) &&
        prim.isDefined() && renderPurpose(prim, _time, _options.includedPurposes)) {
        Entry e;
        e.prim = &prim;
        e.type = type == "Sphere"        ? tokens::sphere()
                 : type == "Points"      ? tokens::pointsPrim()
                 : type == "BasisCurves" ? tokens::basisCurves()
                                         : tokens::mesh();
        e.world = rel;
        e.visible = visible;
        e.material = resolveMaterialBinding(prim);
        e.subsetMaterials = subsetBindings(prim);
        e.instancer = instancer;
        e.protoIndex = protoIndex;
        if ((!shape || prepareShape(prim, &e)) && index->insertRprim(e.type, this, id)) _entries[id] = e;
    }
    for (const usd::Prim* child : prim.children())
        visitPrototype(*child, id.appendChild(child->name()), rel, visible, instancer, protoIndex, index);
}

void UsdSceneDelegate::growInstancedBounds(
    const Path& id, const Entry& e, const std::function<void(const glm::dmat4&, const glm::dvec3&)>& grow) const {
    // The prototype's object-space box, placed by every instance.
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    if (e.type == tokens::sphere()) {
        double r = getFloat(get(id, tokens::radius())).value_or(1.0f);
        lo = glm::dvec3(-r), hi = glm::dvec3(r);
    } else {
        Value points = get(id, tokens::points());
        if (auto* pts = getIf<std::vector<glm::vec3>>(points))
            for (const auto& p : *pts) lo = glm::min(lo, glm::dvec3(p)), hi = glm::max(hi, glm::dvec3(p));
    }
    if (lo.x > hi.x) return;
    const Entry* inst = entry(e.instancer);
    if (!inst) return;
    if (inst->instanceXforms) {
        for (const glm::dmat4& x : *inst->instanceXforms)
            for (int c = 0; c < 8; ++c)
                grow(x * e.world, glm::dvec3(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z));
        return;
    }
    const std::shared_ptr<const hd::InstancerArrays> arrays = getInstancerArrays(e.instancer);
    const auto* t = arrays->translations ? &*arrays->translations : nullptr;
    const auto* r = arrays->rotations ? &*arrays->rotations : nullptr;
    const auto* s = arrays->scales ? &*arrays->scales : nullptr;
    if (!t) return;
    for (int i : getInstanceIndices(e.instancer, id)) {
        if (size_t(i) >= t->size()) continue;
        glm::dmat4 m(1.0);
        if (r && r->size() == t->size()) {
            glm::dquat q((*r)[size_t(i)].x, (*r)[size_t(i)].y, (*r)[size_t(i)].z, (*r)[size_t(i)].w);
            if (glm::length(q) > 0.0) m = glm::mat4_cast(glm::normalize(q));
        }
        if (s && s->size() == t->size()) m = m * glm::scale(glm::dmat4(1.0), glm::dvec3((*s)[size_t(i)]));
        m = glm::translate(glm::dmat4(1.0), glm::dvec3((*t)[size_t(i)])) * m;
        glm::dmat4 full = inst->world * m * e.world;
        for (int c = 0; c < 8; ++c)
            grow(full, glm::dvec3(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z));
    }
}

}  // namespace principled::adapter
