// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usdSceneDelegate.h"

#include "scene_adapter/skinning.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "delegate/hd/camera.h"
#include "delegate/hd/tokens.h"
#include "scene_adapter/implicitShapes.h"
#include "scene_adapter/lightTypes.h"
#include "scene_adapter/primvars.h"
#include "scene_adapter/purpose.h"
#include "scene_adapter/usda/stage.h"
#include "scene_adapter/valueConvert.h"
#include "scene_adapter/xformOps.h"

namespace principled::adapter {

using namespace hd;

namespace {

// UsdGeomCamera stores lengths in tenths of a scene unit (GfCamera::APERTURE_UNIT).
constexpr double kCameraUnit = 0.1;

std::string tokenAttr(const usd::Prim& prim, const char* name, double time,
                      const std::string& fallback) {
    if (const usd::Attribute* a = prim.attribute(name))
        if (auto s = a->get(time).getString()) return *s;
    return fallback;
}

const std::set<std::string>& ignoredTypes() {
    static const std::set<std::string> t{"",        "Xform",    "Scope",         "Shader",
                                         "NodeGraph", "GeomSubset", "SkelRoot",  "RenderSettings",
                                         "Skeleton", "SkelAnimation", "BlendShape",
                                         "RenderProduct", "RenderVar", "Material"};
    return t;
}

// Schemas that describe no geometry or light a renderer draws (physics, audio, render passes,
// a Volume's field assets: the Volume itself is reported): skipped without a warning.
bool drawsNothing(const std::string& type) {
    static const std::set<std::string> t{"RenderPass", "RenderDenoisePass", "SpatialAudio", "OpenVDBAsset",
                                         "Field3DAsset", "FieldAsset", "CollisionGroup", "GeomSubsetAPI"};
    return t.count(type) || type.rfind("Physics", 0) == 0;
}

// Whether the prim authors a value for the attribute (a declaration without one is as if the
// attribute were not there: it hides no inherited primvar, UsdGeomPrimvarsAPI).
bool hasValue(const usd::Prim& p, const std::string& name) {
    const usd::Attribute* a = p.attribute(name);
    return a && a->hasValue();
}

// "/Mat/Shader.outputs:rgb" -> ("/Mat/Shader", "outputs:rgb").
std::pair<std::string, std::string> splitProperty(const std::string& path) {
    size_t slash = path.rfind('/');
    size_t dot = path.find('.', slash == std::string::npos ? 0 : slash);
    if (dot == std::string::npos) return {path, ""};
    return {path.substr(0, dot), path.substr(dot + 1)};
}

std::string stripNamespace(const std::string& name, const std::string& ns) {
    return name.rfind(ns, 0) == 0 ? name.substr(ns.size()) : name;
}

}  // namespace

UsdSceneDelegate::UsdSceneDelegate(const usd::Stage& stage, const AdapterOptions& options)
    : _stage(stage), _options(options),
      _bindings(stage, [this](const std::string& where, const std::string& message) { warn(where, message); },
                options.materialBindingPurposes) {
    _time = std::isnan(options.time) ? stage.defaultTime() : options.time;
}

UsdSceneDelegate::~UsdSceneDelegate() = default;

void UsdSceneDelegate::warn(const std::string& where, const std::string& message) {
    std::lock_guard<std::mutex> lock(_warningsMutex);
    std::string text = where + ": " + message;
    if (_warningSet.insert(text).second) _warnings.push_back(std::move(text));
}

void UsdSceneDelegate::populate(RenderIndex* index) {
    invalidateInstancerCache();
    _skeletonPoses.clear();
    const usd::Prim* root = _stage.pseudoRoot();
    if (!root) return;
    readLightLinks();  // instance groups are keyed by link membership (visitInstance)
    for (const usd::Prim* child : root->children()) visit(*child, glm::dmat4(1.0), true, index);
}

void UsdSceneDelegate::visit(const usd::Prim& prim, const glm::dmat4& parentWorld,
                             bool parentVisible, RenderIndex* index) {
    // UsdPrimDefaultPredicate: active, defined, not abstract (an `over` whose prim nothing
    // defines, say a renamed upstream prim, is not traversed, nor what it holds).
    if (!prim.isActive() || prim.isAbstract() || !prim.isDefined()) return;
    // Render purpose only; a descendant that authors its own purpose keeps it (UsdGeomImageable
    // ComputePurposeInfo), so the subtree of a guide is still walked.
    const bool drawn = renderPurpose(prim, _time, _options.includedPurposes);

    std::string warning;
    LocalTransform local = computeLocalTransform(prim, _time, &warning);
    if (!warning.empty()) warn(prim.location().str() + ": " + prim.path(), warning);
    glm::dmat4 world = local.resetsXformStack ? local.matrix : parentWorld * local.matrix;
    bool visible = parentVisible && tokenAttr(prim, "visibility", _time, "inherited") != "invisible";

    const std::string& type = prim.typeName();
    if (!drawn) {
        for (const usd::Prim* child : prim.children()) visit(*child, world, visible, index);
        return;
    }
    // Instanceable prims with the same prototype share its BLAS (usdSceneDelegateGeom.cpp).
    if (prim.isInstance() && prim.isDefined() && visitInstance(prim, world, visible, index)) return;
    Path id(prim.path());
    Token hdType;
    bool isRprim = false;
    if (type == "Mesh") hdType = tokens::mesh(), isRprim = true;
    else if (type == "Sphere") hdType = tokens::sphere(), isRprim = true;
    else if (type == "Points") hdType = tokens::pointsPrim(), isRprim = true;
    else if (type == "BasisCurves") hdType = tokens::basisCurves(), isRprim = true;
    else if (isImplicitShape(type)) hdType = tokens::mesh(), isRprim = true;
    else if (type == "PointInstancer") {
        // Its prototypes are drawn only through it; nothing below it is drawn directly.
        if (prim.isDefined()) visitPointInstancer(prim, world, visible, index);
        return;
    }
    else if (type == "Camera") hdType = tokens::camera();
    else if (type == "Material") hdType = tokens::material();
    else if (Token light = lightTypeOf(type); !light.empty()) hdType = light;
    else if (!ignoredTypes().count(type) && !drawsNothing(type)) {
        // Once per type: a scene of thousands of NURBS patches gives one line, not thousands.
        bool first;
        {
            std::lock_guard<std::mutex> lock(_warningsMutex);
            first = _unsupportedTypes.insert(type).second;
        }
        if (first)
            warn(prim.location().str() + ": " + prim.path(),
                 "prim type '" + type + "' is not supported yet; this prim and every other '" + type +
                     "' prim are skipped");
    }

    if (!hdType.empty() && prim.isDefined()) {
        Entry e;
        e.prim = &prim;
        e.type = hdType;
        e.world = world;
        e.visible = visible;
        if (isRprim) {
            e.material = resolveMaterialBinding(prim);
            e.subsetMaterials = subsetBindings(prim);
        }
        if (hdType == tokens::mesh() && type == "Mesh") {
            checkExtent(prim);
            checkSubsets(prim);
            std::vector<std::string> skinWarnings;
            if (auto posed = skinMesh(_stage, prim, _time, &skinWarnings, &_skeletonPoses)) {
                e.world = posed->world;  // UsdSkel: the skeleton's space, not the mesh's own
                e.skinned = std::make_shared<const SkinnedMesh>(std::move(*posed));
                _anySkinned = true;
            }
            for (const std::string& w : skinWarnings) warn(prim.location().str() + ": " + prim.path(), w);
        }
        bool ok = !isImplicitShape(type) || prepareShape(prim, &e);  // warns when not
        if (ok && e.shape) checkShapeExtent(prim, *e.shape);
        if (type == "Sphere") {  // drawn analytically: its bounds are the radius
            ShapeMesh bounds;
            const float r = std::abs(getFloat(attributeValue(prim, "radius")).value_or(1.0f));
            bounds.extentMin = glm::vec3(-r);
            bounds.extentMax = glm::vec3(r);
            checkShapeExtent(prim, bounds);
        }
        bool inserted = ok && (isRprim ? index->insertRprim(hdType, this, id)
                                       : index->insertSprim(hdType, this, id));
        if (inserted) {
            _entries[id] = e;
            if (hdType == tokens::camera()) {
                _cameras.push_back(id);
                checkLens(prim);
            }
        }
    }
    for (const usd::Prim* child : prim.children()) visit(*child, world, visible, index);
}

Path UsdSceneDelegate::resolveMaterialBinding(const usd::Prim& start) const {
    const std::string m = _bindings.resolve(start);  // scene_adapter/materialBinding.h
    return m.empty() ? Path() : Path(m);
}

std::string UsdSceneDelegate::subsetBindings(const usd::Prim& mesh) const {
    std::string key;
    if (mesh.typeName() != "Mesh") return key;
    for (const usd::Prim* child : mesh.children())
        if (child->typeName() == "GeomSubset") key += child->name() + "=" + _bindings.resolve(*child) + ";";
    return key;
}

void UsdSceneDelegate::checkLens(const usd::Prim& camera) {
    // Lens lengths are tenths of a scene unit: on a metre stage 50 mm is 0.5. A focal length
    // that makes a lens over a metre long was most likely written in millimetres; with depth of
    // field on, its aperture would be that much too large.
    const usd::Attribute* f = camera.attribute("focalLength");
    const usd::Attribute* n = camera.attribute("fStop");
    if (!f || !f->hasValue() || !n || !n->hasValue()) return;
    const double focal = f->get(_time).getDouble().value_or(0.0), fStop = n->get(_time).getDouble().value_or(0.0);
    const double mpu = _stage.metersPerUnit();
    const double metres = focal * 0.1 * mpu;
    if (fStop > 0.0 && metres > 1.0 && std::isfinite(metres)) {
        char text[320];
        std::snprintf(text, sizeof text,
                      "focalLength %g is a %g m lens on this stage (tenths of a scene unit, metersPerUnit %g): "
                      "depth of field follows it; %g would be %g mm",
                      focal, metres, mpu, focal / (100.0 * mpu), focal);
        warn(f->location().str() + ": " + camera.path(), text);
    }
}

void UsdSceneDelegate::checkSubsets(const usd::Prim& mesh) {
    const usd::Attribute* counts = mesh.attribute("faceVertexCounts");
    if (!counts || !counts->hasValue()) return;
    const usd::Value cv = counts->get(_time);
    const size_t faces = cv.numbers() ? cv.numbers()->size() : 0;
    for (const usd::Prim* child : mesh.children()) {
        if (child->typeName() != "GeomSubset" || !child->isActive()) continue;
        const usd::Attribute* idx = child->attribute("indices");
        if (!idx || !idx->hasValue()) continue;
        const usd::Value iv = idx->get(_time);
        if (!iv.numbers()) continue;
        size_t outside = 0;
        double first = 0;
        for (double f : *iv.numbers())
            if (!(f >= 0.0 && f < double(faces)) && outside++ == 0) first = f;
        if (outside > 0)
            warn(idx->location().str() + ": " + child->path(),
                 "GeomSubset indices name " + std::to_string(outside) + " face(s) outside the mesh's [0, " +
                     std::to_string(faces) + ") (the first: " + std::to_string(static_cast<long long>(first)) + "); ignored");
    }
}

void UsdSceneDelegate::checkExtent(const usd::Prim& prim) {
    // UsdGeomBoundable extent: [min, max] bounding the points. A wrong extent makes
    // extent-culling renderers drop the prim; here it is reported (geometry is not culled).
    const usd::Attribute* ext = prim.attribute("extent");
    const usd::Attribute* pts = prim.attribute("points");
    if (!ext || !ext->hasValue() || !pts || !pts->hasValue()) return;
    usd::Value e = ext->get(_time), p = pts->get(_time);
    const std::vector<double>* en = e.numbers();
    const std::vector<double>* pn = p.numbers();
    if (!en || en->size() != 6 || e.components() != 3) return;
    std::string where = ext->location().str() + ": " + prim.path();
    for (int k = 0; k < 3; ++k)
        if ((*en)[k] > (*en)[3 + k]) {
            warn(where, "extent min > max (inverted); it should bound the points");
            return;
        }
    if (!pn || p.components() != 3) return;
    double tol = 1e-4;
    for (int k = 0; k < 3; ++k) tol = std::max(tol, 1e-4 * std::abs((*en)[3 + k] - (*en)[k]));
    for (size_t i = 0; i + 2 < pn->size(); i += 3)
        for (int k = 0; k < 3; ++k)
            if ((*pn)[i + k] < (*en)[k] - tol || (*pn)[i + k] > (*en)[3 + k] + tol) {
                warn(where, "points lie outside the authored extent");
                return;
            }
}

void UsdSceneDelegate::checkShapeExtent(const usd::Prim& prim, const ShapeMesh& shape) {
    // An implicit shape's extent should hold its analytic bounds (size, radius, height, axis).
    const usd::Attribute* ext = prim.attribute("extent");
    if (!ext || !ext->hasValue()) return;
    const usd::Value e = ext->get(_time);
    const std::vector<double>* en = e.numbers();
    if (!en || en->size() != 6 || e.components() != 3) return;
    double tol = 1e-4;
    for (int k = 0; k < 3; ++k) tol = std::max(tol, 1e-4 * std::abs((*en)[3 + k] - (*en)[k]));
    for (int k = 0; k < 3; ++k)
        if (shape.extentMin[k] < (*en)[k] - tol || shape.extentMax[k] > (*en)[3 + k] + tol) {
            warn(ext->location().str() + ": " + prim.path(),
                 "the " + prim.typeName() + " reaches outside its authored extent (its size, radius or height say otherwise)");
            return;
        }
}

const UsdSceneDelegate::Entry* UsdSceneDelegate::entry(const Path& id) const {
    auto it = _entries.find(id);
    return it == _entries.end() ? nullptr : &it->second;
}

const usd::Prim* UsdSceneDelegate::prim(const Path& id) const {
    const Entry* e = entry(id);
    return e ? e->prim : nullptr;
}

Value UsdSceneDelegate::attributeValue(const usd::Prim& p, const std::string& name) const {
    const usd::Attribute* a = p.attribute(name);
    if (!a || !a->hasValue()) return {};
    return toHdValue(a->get(_time));
}

MeshTopology UsdSceneDelegate::getMeshTopology(const Path& id) const {
    MeshTopology t;
    const usd::Prim* p = prim(id);
    if (!p) return t;
    if (const Entry* e = entry(id); e->shape) {
        t.faceVertexCounts = e->shape->faceVertexCounts;
        t.faceVertexIndices = e->shape->faceVertexIndices;
        t.scheme = Token("none");
        return t;
    }
    auto ints = [&](const char* name) {
        Value v = attributeValue(*p, name);
        if (auto* a = getIf<std::vector<int>>(v)) return *a;
        return std::vector<int>();
    };
    t.faceVertexCounts = ints("faceVertexCounts");
    t.faceVertexIndices = ints("faceVertexIndices");
    t.holeIndices = ints("holeIndices");
    t.scheme = Token(tokenAttr(*p, "subdivisionScheme", _time, "catmullClark"));
    t.orientation = Token(tokenAttr(*p, "orientation", _time, "rightHanded"));
    t.refineLevel = _options.refineLevel;
    Value level = attributeValue(*p, "principled:refineLevel");
    if (auto* l = getIf<int>(level)) t.refineLevel = std::clamp(*l, -1, 8);
    return t;
}

SubdivTags UsdSceneDelegate::getSubdivTags(const Path& id) const {
    SubdivTags s;
    const usd::Prim* p = prim(id);
    if (!p) return s;
    s.interpolateBoundary = Token(tokenAttr(*p, "interpolateBoundary", _time, "edgeAndCorner"));
    s.faceVaryingLinearInterpolation =
        Token(tokenAttr(*p, "faceVaryingLinearInterpolation", _time, "cornersPlus1"));
    s.triangleSubdivisionRule =
        Token(tokenAttr(*p, "triangleSubdivisionRule", _time, "catmullClark"));
    auto ints = [&](const char* name) {
        Value v = attributeValue(*p, name);
        auto* a = getIf<std::vector<int>>(v);
        return a ? *a : std::vector<int>();
    };
    auto floats = [&](const char* name) {
        Value v = attributeValue(*p, name);
        auto* a = getIf<std::vector<float>>(v);
        return a ? *a : std::vector<float>();
    };
    s.creaseIndices = ints("creaseIndices");
    s.creaseLengths = ints("creaseLengths");
    s.creaseSharpnesses = floats("creaseSharpnesses");
    s.cornerIndices = ints("cornerIndices");
    s.cornerSharpnesses = floats("cornerSharpnesses");
    return s;
}

glm::dmat4 UsdSceneDelegate::getTransform(const Path& id) const {
    if (id == _defaultCamera) return _defaultCameraXform;
    const Entry* e = entry(id);
    if (!e) return glm::dmat4(1.0);
    // UsdLuxDomeLight_1 poleAxis: "Z", or "scene" on a Z-up stage, turns the dome (only the
    // dome, not its children) by +90 degrees about X so its top pole is +Z.
    if (e->prim && e->prim->typeName() == "DomeLight_1") {
        const std::string pole = tokenAttr(*e->prim, "poleAxis", _time, "scene");
        if (pole == "Z" || (pole == "scene" && _stage.upAxis() == "Z")) {
            const glm::dmat4 zUp(1, 0, 0, 0,  0, 0, 1, 0,  0, -1, 0, 0,  0, 0, 0, 1);  // columns: x, y -> z, z -> -y
            return e->world * zUp;
        }
    }
    return e->world;
}

bool UsdSceneDelegate::getVisible(const Path& id) const {
    const Entry* e = entry(id);
    return e ? e->visible : true;
}

bool UsdSceneDelegate::getDoubleSided(const Path& id) const {
    const usd::Prim* p = prim(id);
    if (!p) return false;
    Value v = attributeValue(*p, "doubleSided");
    auto* b = getIf<bool>(v);
    if (!b) return p->typeName() == "Plane";  // UsdGeomPlane's fallback is doubleSided = 1
    return *b;
}

Value UsdSceneDelegate::get(const Path& id, const Token& key) const {
    const usd::Prim* p = prim(id);
    if (!p) return {};
    if (const Entry* e = entry(id); e->shape || !e->instancer.empty() || e->type == Token("instancer"))
        if (Value v = shapeOrInstancerValue(*e, key); !isEmpty(v)) return v;
    const std::string& k = key.str();
    if (const Entry* e = entry(id); e && e->skinned) {
        if (key == tokens::points()) return Value(e->skinned->points);
        if (key == tokens::normals()) return e->skinned->normals.empty() ? Value() : Value(e->skinned->normals);
    }
    if (k == "points" || k == "radius") return attributeValue(*p, k);
    if (k == "normals") {
        Value v = attributeValue(*p, "primvars:normals");
        return isEmpty(v) ? attributeValue(*p, "normals") : v;
    }
    Value v = attributeValue(*p, "primvars:" + k);
    if (isEmpty(v)) v = attributeValue(*p, k);
    // Display colour and opacity an ancestor authors (other primvars: getIndexedPrimvar).
    if (isEmpty(v) && (key == tokens::displayColor() || k == "displayOpacity") && !hasValue(*p, "primvars:" + k))
        if (const InheritedPrimvar i = inheritedPrimvar(*p, "primvars:" + k); i.attribute) v = toHdValue(i.attribute->get(_time));
    return v;
}

Value UsdSceneDelegate::getIndexedPrimvar(const Path& id, const Token& key,
                                          std::vector<int>* indices) const {
    indices->clear();
    const usd::Prim* p = prim(id);
    if (!p) return {};
    std::string name = "primvars:" + key.str();
    if (p->attribute(name)) {
        Value idx = attributeValue(*p, name + ":indices");
        if (auto* a = getIf<std::vector<int>>(idx)) *indices = *a;
    }
    Value v = get(id, key);
    if (isEmpty(v) && !hasValue(*p, name))
        if (const InheritedPrimvar i = inheritedPrimvar(*p, name); i.attribute) {
            // Inherited from an ancestor (constant, so an index array selects its one value).
            v = toHdValue(i.attribute->get(_time));
            if (const usd::Attribute* idx = i.owner->attribute(name + ":indices"); idx && idx->hasValue()) {
                const Value iv = toHdValue(idx->get(_time));
                if (auto* a = getIf<std::vector<int>>(iv)) *indices = *a;
            }
        }
    return v;
}

std::vector<PrimvarDescriptor> UsdSceneDelegate::getPrimvarDescriptors(const Path& id,
                                                                       Interpolation interp) const {
    std::vector<PrimvarDescriptor> out;
    const usd::Prim* p = prim(id);
    if (!p) return out;
    bool primvarNormals = false;
    for (const usd::Attribute* a : p->attributes()) {
        const std::string& n = a->name();
        if (n.rfind("primvars:", 0) != 0) continue;
        if (n.size() > 8 && n.compare(n.size() - 8, 8, ":indices") == 0) continue;
        if (!a->hasValue()) continue;
        std::string name = stripNamespace(n, "primvars:");
        if (name.rfind("skel:", 0) == 0) continue;  // UsdSkel's influences, not shading data
        if (name == "normals") primvarNormals = true;
        Interpolation i = attributeInterpolation(*a, Interpolation::Constant);
        if (i != interp) continue;
        PrimvarDescriptor d;
        d.name = Token(name);
        d.interpolation = i;
        d.indexed = p->attribute(n + ":indices") != nullptr;
        out.push_back(d);
    }
    // Constant primvars inherited from ancestors, unless the prim authors one of that name.
    if (interp == Interpolation::Constant)
        for (const InheritedPrimvar& i : inheritablePrimvars(p->parent())) {
            if (hasValue(*p, i.attribute->name())) continue;
            PrimvarDescriptor d;
            d.name = Token(stripNamespace(i.attribute->name(), "primvars:"));
            d.interpolation = Interpolation::Constant;
            d.indexed = i.owner->attribute(i.attribute->name() + ":indices") != nullptr;
            out.push_back(d);
        }
    // A skinned mesh whose normals could not be posed has none.
    if (const Entry* e = entry(id); e && e->skinned && e->skinned->normals.empty()) {
        out.erase(std::remove_if(out.begin(), out.end(), [](const PrimvarDescriptor& d) { return d.name == tokens::normals(); }),
                  out.end());
        return out;
    }
    // UsdGeomPointBased "normals": vertex interpolation unless authored otherwise.
    if (!primvarNormals)
        if (const usd::Attribute* a = p->attribute("normals"); a && a->hasValue())
            if (attributeInterpolation(*a, Interpolation::Vertex) == interp)
                out.push_back({tokens::normals(), interp, Token("normal"), false});
    if (entry(id)->shape && interp == Interpolation::FaceVarying)
        out.push_back({tokens::normals(), interp, Token("normal"), false});
    return out;
}

Path UsdSceneDelegate::getMaterialId(const Path& id) const {
    const Entry* e = entry(id);
    return e ? e->material : Path();
}

MaterialNetwork UsdSceneDelegate::getMaterialResource(const Path& materialId) const {
    MaterialNetwork net;
    const usd::Prim* mat = prim(materialId);
    if (!mat) return net;
    // Follows a connection to its source: through material/node-graph interface inputs to a
    // shader output. Returns the shader prim path and output name, or the interface value (and
    // its colorSpace metadata, when asked for).
    auto resolve = [&](std::string target, Value* interfaceValue,
                       std::string* interfaceColorSpace = nullptr) -> std::pair<std::string, std::string> {
        for (int hop = 0; hop < 32; ++hop) {
            auto [primPath, prop] = splitProperty(target);
            const usd::Prim* up = _stage.prim(primPath);
            if (!up) return {"", ""};
            if (up->typeName() == "Shader") return {primPath, stripNamespace(prop, "outputs:")};
            const usd::Attribute* a = up->attribute(prop);
            if (!a) return {"", ""};
            if (!a->connections().empty()) {
                target = a->connections().front();
                continue;
            }
            if (a->hasValue()) *interfaceValue = toHdValue(a->get(_time));
            if (const usd::Value* cs = a->metadata("colorSpace"); cs && interfaceColorSpace)
                *interfaceColorSpace = cs->getString().value_or("");
            return {"", ""};
        }
        // A connection cycle (or a chain of more than 32 interface inputs): unconnected.
        net.problems.push_back(target + ": its connection goes round in a cycle through interface inputs; "
                               "treated as unconnected");
        return {"", ""};
    };
    std::vector<std::string> stack;
    std::set<std::string> seen;
    // The universal render context first, then MaterialX; other contexts (mdl, ri) are ignored.
    for (const char* terminal : {"outputs:surface", "outputs:mtlx:surface"}) {
        const usd::Attribute* surf = mat->attribute(terminal);
        if (!surf || surf->connections().empty()) continue;
        Value unused;
        auto [shader, output] = resolve(surf->connections().front(), &unused);
        if (shader.empty()) continue;
        net.surfaceTerminal = Path(shader);
        stack.push_back(shader);
        break;
    }
    std::vector<MaterialNode> ordered;
    while (!stack.empty()) {
        std::string path = stack.back();
        stack.pop_back();
        if (!seen.insert(path).second) continue;
        const usd::Prim* sh = _stage.prim(path);
        if (!sh) continue;
        MaterialNode node;
        node.path = Path(path);
        // UsdShadeShader: info:id names the shader only when implementationSource is "id" (its
        // fallback); a sourceAsset or sourceCode shader (MDL, OSL, GLSL) is none this renderer
        // knows, whatever stale id it carries.
        const std::string source = tokenAttr(*sh, "info:implementationSource", _time, "id");
        node.identifier = Token(source == "id" ? tokenAttr(*sh, "info:id", _time, "")
                                               : "info:implementationSource " + source);
        node.where = sh->location().str();
        for (const usd::Attribute* a : sh->attributes()) {
            if (a->name().rfind("inputs:", 0) != 0) continue;
            Token input(stripNamespace(a->name(), "inputs:"));
            // A value blocked at this time (a None time sample) is as if unauthored: the
            // shader's fallback applies, with no complaint about the value.
            if (a->hasValue())
                if (const usd::Value v = a->get(_time); !v.isNone()) node.parameters[input] = toHdValue(v);
            if (const usd::Value* cs = a->metadata("colorSpace"))  // MaterialX image colour space
                if (auto name = cs->getString())
                    node.parameters[Token("colorSpace:" + input.str())] = Value(Token(*name));
            for (const std::string& c : a->connections()) {
                Value iface;
                std::string ifaceColorSpace;
                auto [up, output] = resolve(c, &iface, &ifaceColorSpace);
                if (!up.empty()) {
                    node.inputConnections[input].push_back({Path(up), Token(output)});
                    stack.push_back(up);
                } else if (!isEmpty(iface)) {
                    node.parameters[input] = iface;
                }
                Token csKey("colorSpace:" + input.str());  // the shader's own metadata wins
                if (!ifaceColorSpace.empty() && !node.parameters.count(csKey))
                    node.parameters[csKey] = Value(Token(ifaceColorSpace));
            }
        }
        ordered.push_back(std::move(node));
    }
    // Upstream nodes first.
    net.nodes.assign(ordered.rbegin(), ordered.rend());
    return net;
}

Value UsdSceneDelegate::getLightParamValue(const Path& id, const Token& param) const {
    const usd::Prim* p = prim(id);
    if (!p) return {};
    if (param.str() == "lightLink" || param.str() == "shadowLink") {
        std::string collection = p->path() + ".collection:" + param.str();
        if (_lightLinks.count(collection)) return Value(std::move(collection));
        return {};
    }
    Value v = attributeValue(*p, "inputs:" + param.str());
    return isEmpty(v) ? attributeValue(*p, param.str()) : v;  // pre-2021 names had no prefix
}

std::vector<Token> UsdSceneDelegate::getCategories(const Path& id) const {
    std::vector<Token> out;
    const usd::Prim* p = prim(id);
    if (!p || _lightLinks.empty()) return out;
    // A PointInstancer's prototype may live outside it: its instances are the instancer's, so a
    // link holding the instancer holds them.
    const usd::Prim* instancer = nullptr;
    if (const Entry* e = entry(id); e && !e->instancer.empty())
        if (const usd::Prim* ip = _stage.prim(e->instancer.str()); ip && ip->typeName() == "PointInstancer")
            instancer = ip;
    for (const auto& [collection, link] : _lightLinks)
        if (link->includes(p->path()) || (instancer && link->includes(instancer->path()))) out.emplace_back(collection);
    return out;
}

std::string UsdSceneDelegate::lightLinkKey(const usd::Prim& root) const {
    // Which link collections hold each prim of the subtree: instances whose subtrees are held
    // alike may share a prototype (its rprims' categories are read at the first instance's paths).
    std::string key;
    if (_lightLinks.empty()) return key;
    std::vector<const usd::Prim*> stack{&root};
    while (!stack.empty()) {
        const usd::Prim* p = stack.back();
        stack.pop_back();
        for (const auto& [collection, link] : _lightLinks) key += link->includes(p->path()) ? '1' : '0';
        key += '/';
        for (auto it = p->children().rbegin(); it != p->children().rend(); ++it) stack.push_back(*it);
    }
    return key;
}

void UsdSceneDelegate::readLightLinks() {
    _lightLinks.clear();
    auto warnFn = [this](const std::string& where, const std::string& message) { warn(where, message); };
    for (const usd::Prim* light : _stage.traverse()) {
        const Token t = lightTypeOf(light->typeName());  // a portal emits nothing to link
        if (!light->isActive() || light->isAbstract() || !light->isDefined() || t.empty() || t == tokens::portalLight())
            continue;
        for (const char* kind : {".collection:lightLink", ".collection:shadowLink"}) {
            const std::string collection = light->path() + kind;
            if (!CollectionMembership::holdsEverything(_stage, collection))
                _lightLinks[collection] =
                    std::make_shared<const CollectionMembership>(_stage, collection, warnFn, /*includeRootFallback=*/true);
        }
    }
}

Value UsdSceneDelegate::getCameraParamValue(const Path& id, const Token& param) const {
    const std::string& k = param.str();
    bool isLength = k == "focalLength" || k == "horizontalAperture" || k == "verticalAperture" ||
                    k == "horizontalApertureOffset" || k == "verticalApertureOffset";
    // Not a camera attribute: the stage's unit, which the lens needs (Camera::lensRadius).
    if (k == "metersPerUnit") return Value(static_cast<float>(_stage.metersPerUnit()));
    if (id == _defaultCamera) {
        if (k == "focalLength") return Value(_defaultCameraFocal);
        if (k == "clippingRange") return Value(_defaultCameraClip);
        return {};
    }
    const usd::Prim* p = prim(id);
    if (!p) return {};
    // UsdRenderSettings disableDepthOfField: "as if the F-stop were infinite"; 0 means the same.
    if (k == "fStop" && _options.disableDepthOfField) return Value(0.0f);
    Value v = attributeValue(*p, k);
    if (isLength)
        if (auto f = getFloat(v)) return Value(static_cast<float>(*f * kCameraUnit));
    return v;
}

Path UsdSceneDelegate::addDefaultCamera(RenderIndex* index, double aspect) {
    hd::Framing framing;
    return addDefaultCamera(index, 1000000, std::max(1, int(std::lround(1000000.0 / std::clamp(aspect, 1e-3, 1e3)))), framing);
}

Path UsdSceneDelegate::addDefaultCamera(RenderIndex* index, int width, int height, const hd::Framing& framing) {
    if (!_defaultCamera.empty()) return _defaultCamera;
    // The image-plane window the framing gives the fallback apertures with this lens.
    hd::Camera probe{hd::Path("/__principled/probe")};
    probe.set(glm::dmat4(1.0), _defaultCameraFocal, 2.0955f, 1.52908f);
    const glm::vec4 window = probe.screenWindow(width, height, framing);
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    auto grow = [&](const glm::dmat4& m, const glm::dvec3& p) {
        glm::dvec3 w = glm::dvec3(m * glm::dvec4(p, 1.0));
        if (std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z)) {
            lo = glm::min(lo, w);
            hi = glm::max(hi, w);
        }
    };
    // Only what renders frames the view (as UsdGeomBBoxCache counts only imageable prims):
    // invisible prims are left out unless nothing is visible.
    bool anyVisible = false;
    for (const auto& [id, e] : _entries) anyVisible |= e.visible && (e.type == tokens::mesh() ||
        e.type == tokens::pointsPrim() || e.type == tokens::basisCurves() || e.type == tokens::sphere());
    for (const auto& [id, e] : _entries) {
        if (anyVisible && !e.visible) continue;
        if (!e.instancer.empty()) {
            growInstancedBounds(id, e, grow);
        } else if (e.type == tokens::mesh() || e.type == tokens::pointsPrim() || e.type == tokens::basisCurves()) {
            Value v = get(id, tokens::points());
            if (auto* pts = getIf<std::vector<glm::vec3>>(v))
                for (const auto& p : *pts) grow(e.world, glm::dvec3(p));
        } else if (e.type == tokens::sphere()) {
            double r = getFloat(get(id, tokens::radius())).value_or(1.0f);
            for (int c = 0; c < 8; ++c)
                grow(e.world, glm::dvec3(c & 1 ? r : -r, c & 2 ? r : -r, c & 4 ? r : -r));
        }
    }
    if (lo.x > hi.x) lo = glm::dvec3(-1.0), hi = glm::dvec3(1.0);
    glm::dvec3 center = 0.5 * (lo + hi);
    double radius = std::max(1e-6, 0.5 * glm::length(hi - lo));
    bool zUp = _stage.upAxis() == "Z";
    glm::dvec3 up = zUp ? glm::dvec3(0, 0, 1) : glm::dvec3(0, 1, 0);
    // From the front (+Z for Y-up, -Y for Z-up), raised by about 20 degrees.
    glm::dvec3 dir = glm::normalize(zUp ? glm::dvec3(0, -1, 0.35) : glm::dvec3(0, 0.35, 1));
    // Fit the bounding sphere inside the narrower field of view (the window's half angles; an
    // off-centre window cannot happen: the fallback aperture has no offset).
    double vHalf = std::atan(0.5 * std::max(1e-6, double(window.w - window.z)));
    double hHalf = std::atan(0.5 * std::max(1e-6, double(window.y - window.x)));
    if (!std::isfinite(vHalf) || !std::isfinite(hHalf)) vHalf = hHalf = std::atan(0.5 * 1.52908 / 5.0);
    double half = std::min(vHalf, hHalf);
    double dist = 1.1 * radius / std::sin(half);
    glm::dvec3 eye = center + dir * dist;
    _defaultCameraClip = glm::vec2(float(dist * 1e-3), float((dist + radius) * 100.0));
    _defaultCameraXform = glm::inverse(glm::lookAt(eye, center, up));
    _defaultCamera = Path("/__principled/defaultCamera");
    Entry e;
    e.type = tokens::camera();
    e.world = _defaultCameraXform;
    _entries[_defaultCamera] = e;
    index->insertSprim(tokens::camera(), this, _defaultCamera);
    return _defaultCamera;
}

}  // namespace principled::adapter
