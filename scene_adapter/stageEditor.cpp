// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/stageEditor.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>

#include "delegate/hd/renderIndex.h"
#include "scene_adapter/collectionMembership.h"
#include "scene_adapter/usdSceneDelegate.h"
#include "scene_adapter/usda/stage.h"
#include "scene_adapter/usda/stageEdit.h"
#include "scene_adapter/usda/valueType.h"

namespace principled::adapter {

namespace {

using Code = EditError::Code;

bool validName(const std::string& n) {
    if (n.empty() || !(std::isalpha(static_cast<unsigned char>(n[0])) || n[0] == '_')) return false;
    return std::all_of(n.begin(), n.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
    });
}

std::string pathProblem(const std::string& p) {
    if (p.size() < 2 || p[0] != '/' || p.back() == '/')
        return "prim path '" + p + "' must be absolute, like /World/Mesh";
    for (size_t start = 1; start <= p.size();) {
        size_t end = std::min(p.find('/', start), p.size());
        if (!validName(p.substr(start, end - start)))
            return "prim path '" + p + "' has an invalid name '" + p.substr(start, end - start) +
                   "'";
        start = end + 1;
    }
    return "";
}

// A relationship target: a prim path, or a prim path and a namespaced property
// ("/World/Set.collection:metal").
std::string targetProblem(const std::string& t) {
    const size_t dot = t.find('.');
    if (dot == std::string::npos) return pathProblem(t);
    if (std::string why = pathProblem(t.substr(0, dot)); !why.empty()) return why;
    const std::string prop = t.substr(dot + 1);
    for (size_t start = 0; start <= prop.size();) {
        const size_t end = std::min(prop.find(':', start), prop.size());
        if (!validName(prop.substr(start, end - start)))
            return "property path '" + t + "' has an invalid property name '" + prop + "'";
        start = end + 1;
    }
    return "";
}

std::string countText(size_t n) {
    return std::to_string(n) + (n == 1 ? " number" : " numbers");
}

/// Builds a usd::Value of `type` (isArray) from host input, or explains what was expected.
usd::Value toUsdValue(const std::string& where, const std::string& type, bool isArray,
                      const EditValue& in) {
    const usd::ValueType* vt = usd::findValueType(type);
    std::string expected = type + (isArray ? "[]" : "");
    auto bad = [&](const std::string& why) {
        return EditError(Code::BadValue, where + ": expected " + expected + ", " + why);
    };
    if (!vt) throw EditError(Code::Unsupported, where + ": unknown value type '" + type + "'");
    usd::SourceLocation loc = usd::StageEdit::location();
    bool textual = vt->isStringLike() || vt->scalar == usd::ScalarType::Asset;
    if (textual != in.isText)
        throw bad(in.isText ? "got text" : "got " + countText(in.numbers.size()));
    if (textual) {
        if (!isArray && in.texts.size() != 1)
            throw bad("got " + std::to_string(in.texts.size()) + " strings");
        if (isArray) return usd::Value::stringArray(type, in.texts, loc);
        if (vt->scalar == usd::ScalarType::Asset)
            return usd::Value::asset({in.texts[0], in.texts[0]}, loc);
        return usd::Value::string(type, in.texts[0], loc);
    }
    if (!vt->isNumeric())
        throw EditError(Code::Unsupported,
                        where + ": values of type '" + type + "' cannot be edited");
    const auto& n = in.numbers;
    size_t c = size_t(vt->components);
    if (!isArray && n.size() != c) throw bad("got " + countText(n.size()));
    if (isArray && n.size() % c != 0)
        throw bad("got " + countText(n.size()) + " (not a multiple of " + std::to_string(c) + ")");
    for (size_t i = 0; i < n.size(); ++i) {
        if (!std::isfinite(n[i])) throw bad("element " + std::to_string(i) + " is not finite");
        if ((vt->isInteger() || vt->scalar == usd::ScalarType::Bool) && n[i] != std::floor(n[i]))
            throw bad("element " + std::to_string(i) + " (" + std::to_string(n[i]) +
                      ") is not an integer");
        if (vt->isUnsigned() && n[i] < 0)
            throw bad("element " + std::to_string(i) + " is negative");
    }
    if (isArray) return usd::Value::numberArray(type, int(c), n, loc);
    if (c == 1) return usd::Value::number(type, n[0], loc);
    return usd::Value::tuple(type, n, loc);
}

bool isLightType(const std::string& t) {
    return t == "DistantLight" || t == "DomeLight" || t == "SphereLight" || t == "RectLight" ||
           t == "DiskLight" || t == "CylinderLight" || t == "PortalLight";
}

}  // namespace

const std::vector<std::string>& StageEditor::supportedPrimTypes() {
    static const std::vector<std::string> t{
        "Xform",     "Scope",       "Mesh",      "Sphere",         "Points",  "BasisCurves", "Cube",
        "Cylinder",  "Cone",        "Capsule",   "Plane",     "PointInstancer", "Camera",
        "Material",  "Shader",      "NodeGraph", "GeomSubset",     "DistantLight",
        "DomeLight", "SphereLight", "RectLight", "DiskLight",      "CylinderLight", "PortalLight"};
    return t;
}

std::string StageEditor::schemaType(const std::string& primType, const std::string& a) {
    // Types from the USD schemas (UsdGeom, UsdLux, UsdShade, UsdPreviewSurface) for the
    // attributes this renderer reads, so a host can author them on a new prim without a type.
    static const std::map<std::string, std::string> common{
        {"visibility", "token"},          {"purpose", "token"},
        {"xformOpOrder", "token[]"},      {"xformOp:transform", "matrix4d"},
        {"xformOp:translate", "double3"}, {"xformOp:scale", "float3"},
        {"xformOp:rotateXYZ", "float3"},  {"doubleSided", "bool"},
        {"extent", "float3[]"},           {"principled:refineLevel", "int"}};
    static const std::map<std::string, std::string> mesh{
        {"points", "point3f[]"},
        {"normals", "normal3f[]"},
        {"faceVertexCounts", "int[]"},
        {"faceVertexIndices", "int[]"},
        {"holeIndices", "int[]"},
        {"orientation", "token"},
        {"subdivisionScheme", "token"},
        {"interpolateBoundary", "token"},
        {"faceVaryingLinearInterpolation", "token"},
        {"creaseIndices", "int[]"},
        {"creaseLengths", "int[]"},
        {"creaseSharpnesses", "float[]"},
        {"cornerIndices", "int[]"},
        {"cornerSharpnesses", "float[]"},
        {"primvars:displayColor", "color3f[]"},
        {"primvars:st", "texCoord2f[]"},
        {"primvars:normals", "normal3f[]"}};
    static const std::map<std::string, std::string> shapes{
        {"radius", "double"}, {"size", "double"}, {"height", "double"}, {"axis", "token"},
        {"width", "double"},  {"length", "double"}};
    static const std::map<std::string, std::string> instancer{
        {"positions", "point3f[]"}, {"orientations", "quath[]"}, {"scales", "float3[]"},
        {"protoIndices", "int[]"},  {"ids", "int64[]"},          {"invisibleIds", "int64[]"}};
    static const std::map<std::string, std::string> camera{{"focalLength", "float"},
                                                           {"horizontalAperture", "float"},
                                                           {"verticalAperture", "float"},
                                                           {"horizontalApertureOffset", "float"},
                                                           {"verticalApertureOffset", "float"},
                                                           {"clippingRange", "float2"},
                                                           {"fStop", "float"},
                                                           {"focusDistance", "float"},
                                                           {"exposure", "float"},
                                                           {"exposure:time", "float"},
                                                           {"exposure:iso", "float"},
                                                           {"exposure:fStop", "float"},
                                                           {"exposure:responsivity", "float"},
                                                           {"projection", "token"}};
    static const std::map<std::string, std::string> light{{"inputs:intensity", "float"},
                                                          {"inputs:exposure", "float"},
                                                          {"inputs:color", "color3f"},
                                                          {"inputs:normalize", "bool"},
                                                          {"inputs:enableColorTemperature", "bool"},
                                                          {"inputs:colorTemperature", "float"},
                                                          {"inputs:angle", "float"},
                                                          {"inputs:radius", "float"},
                                                          {"inputs:width", "float"},
                                                          {"inputs:height", "float"},
                                                          {"inputs:length", "float"},
                                                          {"inputs:texture:file", "asset"},
                                                          {"inputs:texture:format", "token"}};
    static const std::map<std::string, std::string> shader{{"info:id", "token"},
                                                           {"inputs:diffuseColor", "color3f"},
                                                           {"inputs:emissiveColor", "color3f"},
                                                           {"inputs:specularColor", "color3f"},
                                                           {"inputs:metallic", "float"},
                                                           {"inputs:roughness", "float"},
                                                           {"inputs:clearcoat", "float"},
                                                           {"inputs:clearcoatRoughness", "float"},
                                                           {"inputs:opacity", "float"},
                                                           {"inputs:opacityThreshold", "float"},
                                                           {"inputs:ior", "float"},
                                                           {"inputs:useSpecularWorkflow", "int"},
                                                           {"inputs:sheen", "float"},
                                                           {"inputs:sheenTint", "float"},
                                                           {"inputs:specularTint", "float"},
                                                           {"inputs:anisotropic", "float"},
                                                           {"inputs:subsurface", "float"},
                                                           {"inputs:file", "asset"}};
    static const std::map<std::string, std::string> curves{
        {"points", "point3f[]"}, {"widths", "float[]"}, {"curveVertexCounts", "int[]"},
        {"type", "token"},       {"basis", "token"},    {"wrap", "token"}};
    static const std::map<std::string, std::string> subset{
        {"indices", "int[]"}, {"elementType", "token"}, {"familyName", "token"}};
    auto find = [&](const std::map<std::string, std::string>& m) -> std::string {
        auto it = m.find(a);
        return it == m.end() ? "" : it->second;
    };
    std::string t = find(common);
    if (t.empty() && primType == "Mesh") t = find(mesh);
    if (t.empty() && (primType == "Sphere" || primType == "Cube" || primType == "Cylinder" ||
                      primType == "Cone" || primType == "Capsule" || primType == "Plane"))
        t = find(shapes);
    if (t.empty() && (primType == "Points" || primType == "BasisCurves")) t = find(curves);
    if (t.empty() && primType == "PointInstancer") t = find(instancer);
    if (t.empty() && primType == "Camera") t = find(camera);
    if (t.empty() && isLightType(primType)) t = find(light);
    if (t.empty() && (primType == "Shader" || primType == "Material")) t = find(shader);
    if (t.empty() && primType == "GeomSubset") t = find(subset);
    return t;
}

StageEditor::StageEditor(usd::Stage& stage, UsdSceneDelegate& delegate, hd::RenderIndex& index)
    : _stage(stage), _delegate(delegate), _index(index) {}

const usd::Prim* StageEditor::existingPrim(const std::string& primPath, const char* what) const {
    const usd::Prim* p = primPath == "/" ? nullptr : _stage.prim(primPath);
    if (!p) throw EditError(Code::NotFound, std::string(what) + ": no prim at '" + primPath + "'");
    return p;
}

void StageEditor::checkNotInstanceProxy(const std::string& primPath) const {
    std::string inst = _delegate.enclosingInstance(primPath);
    if (!inst.empty())
        throw EditError(Code::Unsupported, "'" + primPath + "' is inside the instance '" + inst +
                                               "': instance proxies are read-only (as in USD); "
                                               "edit the instance or its prototype's source");
}

void StageEditor::setAttribute(const std::string& primPath, const std::string& name,
                               const EditValue& value, const std::string& typeName) {
    const usd::Prim* prim = existingPrim(primPath, "setAttribute");
    checkNotInstanceProxy(primPath);
    std::string where = primPath + "." + name;
    if (name.rfind("xformOp:", 0) == 0) {
        // USD ignores ops missing from xformOpOrder; an edit that would change nothing is an error.
        const usd::Attribute* o = prim->attribute("xformOpOrder");
        const std::vector<std::string>* ops = o ? o->get(usd::kDefaultTime).strings() : nullptr;
        bool listed = ops && std::any_of(ops->begin(), ops->end(), [&](const std::string& op) {
                          return op == name || op == "!invert!" + name;
                      });
        if (!listed)
            throw EditError(Code::Unsupported,
                            "'" + name + "' is not in the xformOpOrder of '" + primPath +
                                "' (author xformOpOrder first, or replace the whole transform)");
    }
    std::string type;
    bool isArray = false;
    if (const usd::Attribute* a = prim->attribute(name)) {
        type = a->typeName();
        isArray = a->isArray();
        std::string given = typeName;
        if (!given.empty() && given != type + (isArray ? "[]" : ""))
            throw EditError(Code::BadValue, where + ": the attribute is " + type +
                                                (isArray ? "[]" : "") + ", not " + given);
    } else {
        type = typeName.empty() ? schemaType(prim->typeName(), name) : typeName;
        if (type.empty())
            throw EditError(Code::NotFound, where + ": " + prim->typeName() +
                                                " prim has no attribute '" + name +
                                                "'; give its type to create it");
        if (type.size() > 2 && type.compare(type.size() - 2, 2, "[]") == 0) {
            isArray = true;
            type.resize(type.size() - 2);
        }
    }
    usd::Value v = toUsdValue(where, type, isArray, value);
    if (name == "visibility" && !isArray) {
        auto s = v.getString();
        if (!s || (*s != "inherited" && *s != "invisible"))
            throw EditError(Code::BadValue, where + ": expected token 'inherited' or 'invisible'");
    }
    if (name == "purpose" && !isArray) {
        auto s = v.getString();
        if (!s || (*s != "default" && *s != "render" && *s != "proxy" && *s != "guide"))
            throw EditError(Code::BadValue,
                            where + ": expected token 'default', 'render', 'proxy' or 'guide'");
    }
    usd::StageEdit(_stage).setAttribute(primPath, name, type, isArray, std::move(v));
    _delegate.attributeChanged(primPath, name, &_index);
}

void StageEditor::setTransform(const std::string& primPath, const double matrix[16]) {
    const usd::Prim* prim = existingPrim(primPath, "setTransform");
    checkNotInstanceProxy(primPath);
    std::vector<double> m(matrix, matrix + 16);
    for (size_t i = 0; i < 16; ++i)
        if (!std::isfinite(m[i]))
            throw EditError(Code::BadValue, primPath + ": expected a finite matrix4d, element " +
                                                std::to_string(i) + " is not finite");
    std::vector<std::string> order{"xformOp:transform"};
    if (const usd::Attribute* o = prim->attribute("xformOpOrder"))
        if (const auto* ops = o->get(usd::kDefaultTime).strings())
            if (!ops->empty() && ops->front() == "!resetXformStack!")
                order.insert(order.begin(), "!resetXformStack!");
    if (const usd::Attribute* t = prim->attribute("xformOp:transform");
        t && (t->typeName() != "matrix4d" || t->isArray()))
        throw EditError(Code::BadValue, primPath + ".xformOp:transform is authored as " +
                                            t->typeName() + ", not matrix4d");
    usd::StageEdit edit(_stage);
    auto loc = usd::StageEdit::location();
    edit.setAttribute(primPath, "xformOp:transform", "matrix4d", false,
                      usd::Value::tuple("matrix4d", m, loc));
    edit.setAttribute(primPath, "xformOpOrder", "token", true,
                      usd::Value::stringArray("token", order, loc));
    _delegate.attributeChanged(primPath, "xformOpOrder", &_index);
}

void StageEditor::addPrim(const std::string& primPath, const std::string& typeName) {
    if (std::string why = pathProblem(primPath); !why.empty())
        throw EditError(Code::BadValue, "addPrim: " + why);
    const auto& types = supportedPrimTypes();
    if (std::find(types.begin(), types.end(), typeName) == types.end()) {
        std::string list;
        for (const auto& t : types) list += (list.empty() ? "" : ", ") + t;
        throw EditError(Code::Unsupported, "addPrim '" + primPath + "': type '" + typeName +
                                               "' is not supported; supported: " + list);
    }
    if (_stage.prim(primPath))
        throw EditError(Code::BadValue, "addPrim: a prim already exists at '" + primPath + "'");
    size_t slash = primPath.rfind('/');
    std::string parent = slash == 0 ? "/" : primPath.substr(0, slash);
    if (!_stage.prim(parent))
        throw EditError(Code::NotFound, "addPrim '" + primPath + "': the parent '" + parent +
                                            "' does not exist (add it first)");
    if (parent != "/") checkNotInstanceProxy(primPath.substr(0, slash) + "/x");
    if (parent != "/" && _stage.prim(parent)->isInstance())
        throw EditError(Code::Unsupported, "addPrim '" + primPath + "': '" + parent +
                                               "' is an instance; its children are read-only");
    usd::StageEdit(_stage).definePrim(primPath, typeName);
    _delegate.primAdded(primPath, &_index);
}

void StageEditor::removePrim(const std::string& primPath) {
    existingPrim(primPath, "removePrim");
    checkNotInstanceProxy(primPath);
    _delegate.primRemoving(primPath, &_index);
    usd::StageEdit(_stage).removePrim(primPath);
    _delegate.primRemoved(primPath, &_index);
}

void StageEditor::connect(const std::string& primPath, const std::string& name,
                          const std::string& source, const std::string& typeName) {
    const usd::Prim* prim = existingPrim(primPath, "connect");
    checkNotInstanceProxy(primPath);
    std::string where = primPath + "." + name;
    if (name.rfind("inputs:", 0) != 0 && name.rfind("outputs:", 0) != 0)
        throw EditError(Code::BadValue, where + ": only inputs:* and outputs:* can be connected");
    std::vector<std::string> sources;
    if (!source.empty()) {
        size_t dot =
            source.find('.', source.rfind('/') == std::string::npos ? 0 : source.rfind('/'));
        std::string sourcePrim = source.substr(0, dot);
        if (dot == std::string::npos || !_stage.prim(sourcePrim))
            throw EditError(Code::NotFound, where +
                                                ": expected a source like /Mat/Shader.outputs:rgb "
                                                "on an existing prim, got '" +
                                                source + "'");
        sources.push_back(source);
    }
    if (const usd::Attribute* a = prim->attribute(name); !a && !usd::findValueType(typeName))
        throw EditError(Code::BadValue, where + ": unknown value type '" + typeName + "'");
    usd::StageEdit(_stage).connect(primPath, name, typeName, std::move(sources));
    _delegate.attributeChanged(
        primPath, name.rfind("inputs:", 0) == 0 ? "connection:" + name : name, &_index);
}

void StageEditor::setRelationship(const std::string& primPath, const std::string& name,
                                  const std::vector<std::string>& targets) {
    existingPrim(primPath, "setRelationship");
    checkNotInstanceProxy(primPath);
    for (const std::string& t : targets)
        if (std::string why = targetProblem(t); !why.empty())
            throw EditError(Code::BadValue, primPath + "." + name + ": target " + why);
    const bool collectionBinding = name.rfind("material:binding:collection:", 0) == 0;
    if (collectionBinding && !targets.empty()) {
        std::string prim, collection;
        if (targets.size() != 2 || !CollectionMembership::splitCollectionPath(targets[0], &prim, &collection))
            throw EditError(Code::BadValue, primPath + "." + name +
                                                ": expected two targets, a collection (</Prim.collection:name>) and a Material");
        if (!_stage.prim(prim))
            throw EditError(Code::BadValue, primPath + "." + name + ": the collection's prim '" + prim + "' does not exist");
    }
    if (name.rfind("material:binding", 0) == 0)
        for (size_t i = collectionBinding ? 1 : 0; i < targets.size(); ++i) {
            const std::string& t = targets[i];
            const usd::Prim* m = _stage.prim(t);
            if (!m || m->typeName() != "Material")
                throw EditError(Code::BadValue, primPath + "." + name +
                                                    ": expected a Material, but '" + t + "' is " +
                                                    (m ? m->typeName() : "not a prim"));
        }
    usd::StageEdit(_stage).setRelationship(primPath, name, targets);
    _delegate.relationshipChanged(primPath, name, &_index);
}

void StageEditor::bindMaterial(const std::string& primPath, const std::string& materialPath) {
    std::vector<std::string> targets;
    if (!materialPath.empty()) targets.push_back(materialPath);
    setRelationship(primPath, "material:binding", targets);
}

}  // namespace principled::adapter
