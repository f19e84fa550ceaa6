// SPDX-License-Identifier: Apache-2.0
#include "plugins/embree/editableSceneDelegate.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include "delegate/hd/tokens.h"
#include "scene_adapter/usda/stage.h"
#include "scene_adapter/valueConvert.h"
#include "scene_adapter/xformOps.h"

namespace principled::plugins {

using namespace hd;

namespace {

// 0.1: camera lengths are authored in tenths of a scene unit (the adapter's kCameraUnit).
constexpr double kCameraUnit = 0.1;
constexpr double kDefaultTimeNaN = std::numeric_limits<double>::quiet_NaN();

/// Records what a scene delegate inserts, so the same prims can be inserted into the real
/// index with another scene delegate. Supports exactly the types of the real delegate.
class RecordingRenderDelegate : public RenderDelegate {
  public:
    struct NullRprim : Rprim {
        using Rprim::Rprim;
        void sync(SceneDelegate*, RenderParam*, DirtyBits* bits) override { *bits = 0; }
    };
    struct NullSprim : Sprim {
        using Sprim::Sprim;
        void sync(SceneDelegate*, RenderParam*, DirtyBits* bits) override { *bits = 0; }
    };

    RecordingRenderDelegate(RenderDelegate* real, std::vector<std::pair<bool, Token>>* log,
                            std::vector<Path>* ids)
        : _real(real), _log(log), _ids(ids) {}

    const std::vector<Token>& supportedRprimTypes() const override {
        return _real->supportedRprimTypes();
    }
    const std::vector<Token>& supportedSprimTypes() const override {
        return _real->supportedSprimTypes();
    }
    const std::vector<Token>& supportedBprimTypes() const override {
        return _real->supportedBprimTypes();
    }
    std::unique_ptr<Rprim> createRprim(const Token& t, const Path& id) override {
        _log->push_back({true, t});
        _ids->push_back(id);
        return std::make_unique<NullRprim>(id);
    }
    std::unique_ptr<Sprim> createSprim(const Token& t, const Path& id) override {
        _log->push_back({false, t});
        _ids->push_back(id);
        return std::make_unique<NullSprim>(id);
    }
    std::unique_ptr<Bprim> createBprim(const Token&, const Path&) override { return nullptr; }
    std::unique_ptr<RenderPass> createRenderPass(RenderIndex*) override { return nullptr; }
    RenderParam* renderParam() override { return nullptr; }
    void commitResources(ChangeTracker*) override {}
    AovDescriptor defaultAovDescriptor(const Token&) const override { return {}; }
    std::vector<RenderSettingDescriptor> renderSettingDescriptors() const override { return {}; }
    void setRenderSetting(const Token&, const Value&) override {}
    Value renderSetting(const Token&) const override { return {}; }
    unsigned renderSettingsVersion() const override { return 0; }
    std::map<std::string, double> renderStats() const override { return {}; }

  private:
    RenderDelegate* _real;
    std::vector<std::pair<bool, Token>>* _log;
    std::vector<Path>* _ids;
};

bool isLightType(const Token& t) {
    return t == tokens::distantLight() || t == tokens::domeLight() || t == tokens::sphereLight() ||
           t == tokens::rectLight() || t == tokens::diskLight();
}

std::string stripPrefix(const std::string& s, const std::string& prefix) {
    return s.rfind(prefix, 0) == 0 ? s.substr(prefix.size()) : s;
}

bool isAtOrBelow(const std::string& path, const std::string& root) {
    if (root == "/") return true;
    return path == root ||
           (path.rfind(root, 0) == 0 && path.size() > root.size() && path[root.size()] == '/');
}

/// Shapes host numbers or text like `current` (the value the adapter reports today); an
/// unauthored value takes its shape from the count (1 float, 2-4 vector, 16 matrix).
std::optional<Value> shapeLike(const Value& current, const EditValue& v, std::string* why) {
    const auto& n = v.numbers;
    auto need = [&](size_t count, const char* what) -> bool {
        if (n.size() == count) return true;
        *why = std::string("expected ") + std::to_string(count) + " number" +
               (count == 1 ? "" : "s") + " for a " + what + ", got " + std::to_string(n.size());
        return false;
    };
    auto flat = [&](size_t k, const char* what) -> bool {
        if (!n.empty() && n.size() % k == 0) return true;
        *why = std::string("expected a non-empty multiple of ") + std::to_string(k) +
               " numbers for a " + what + ", got " + std::to_string(n.size());
        return false;
    };
    if (v.isText) {
        if (std::holds_alternative<Token>(current)) return Value(Token(v.text));
        if (std::holds_alternative<std::string>(current) || isEmpty(current)) return Value(v.text);
        *why = "the attribute is numeric; use prdSetAttributeNumbers";
        return std::nullopt;
    }
    if (std::holds_alternative<Token>(current) || std::holds_alternative<std::string>(current)) {
        *why = "the attribute is a string or token; use prdSetAttributeString";
        return std::nullopt;
    }
    if (std::holds_alternative<float>(current) && need(1, "float")) return Value(float(n[0]));
    if (std::holds_alternative<double>(current) && need(1, "double")) return Value(n[0]);
    if (std::holds_alternative<int>(current) && need(1, "int"))
        return Value(int(std::lround(n[0])));
    if (std::holds_alternative<bool>(current) && need(1, "bool")) return Value(n[0] != 0.0);
    if (std::holds_alternative<glm::vec2>(current) && need(2, "2-vector"))
        return Value(glm::vec2(n[0], n[1]));
    if (std::holds_alternative<glm::vec3>(current) && need(3, "3-vector or color"))
        return Value(glm::vec3(n[0], n[1], n[2]));
    if (std::holds_alternative<glm::vec4>(current) && need(4, "4-vector"))
        return Value(glm::vec4(n[0], n[1], n[2], n[3]));
    if (std::holds_alternative<glm::dmat4>(current) && need(16, "matrix")) {
        glm::dmat4 m;
        for (int i = 0; i < 16; ++i) (&m[0][0])[i] = n[i];  // USD row-major = glm column layout
        return Value(m);
    }
    if (std::holds_alternative<std::vector<float>>(current) && flat(1, "float array"))
        return Value(std::vector<float>(n.begin(), n.end()));
    if (std::holds_alternative<std::vector<int>>(current) && flat(1, "int array")) {
        std::vector<int> out;
        for (double x : n) out.push_back(int(std::lround(x)));
        return Value(out);
    }
    if (std::holds_alternative<std::vector<glm::vec2>>(current) && flat(2, "float2 array")) {
        std::vector<glm::vec2> out;
        for (size_t i = 0; i < n.size(); i += 2) out.emplace_back(n[i], n[i + 1]);
        return Value(out);
    }
    if (std::holds_alternative<std::vector<glm::vec3>>(current) && flat(3, "float3 array")) {
        std::vector<glm::vec3> out;
        for (size_t i = 0; i < n.size(); i += 3) out.emplace_back(n[i], n[i + 1], n[i + 2]);
        return Value(out);
    }
    if (std::holds_alternative<std::vector<glm::vec4>>(current) && flat(4, "float4 array")) {
        std::vector<glm::vec4> out;
        for (size_t i = 0; i < n.size(); i += 4)
            out.emplace_back(n[i], n[i + 1], n[i + 2], n[i + 3]);
        return Value(out);
    }
    if (isEmpty(current)) {
        switch (n.size()) {
            case 1:
                return Value(float(n[0]));
            case 2:
                return Value(glm::vec2(n[0], n[1]));
            case 3:
                return Value(glm::vec3(n[0], n[1], n[2]));
            case 4:
                return Value(glm::vec4(n[0], n[1], n[2], n[3]));
            default:
                *why = "the attribute has no authored value; give 1-4 numbers";
                return std::nullopt;
        }
    }
    if (why->empty()) *why = "this attribute's type cannot be edited";
    return std::nullopt;
}

}  // namespace

EditableSceneDelegate::EditableSceneDelegate(const usd::Stage& stage,
                                             const adapter::AdapterOptions& options)
    : _stage(stage), _base(stage, options) {
    _time = std::isnan(options.time) ? stage.defaultTime() : options.time;
}

EditableSceneDelegate::~EditableSceneDelegate() = default;

void EditableSceneDelegate::populate(RenderIndex* index) {
    std::vector<std::pair<bool, Token>> log;
    std::vector<Path> ids;
    {
        RecordingRenderDelegate recorder(index->renderDelegate(), &log, &ids);
        RenderIndex scratch(&recorder);
        _base.populate(&scratch);
        scratch.clear();
    }
    // Same order as the adapter's own populate, so primIds come out identical.
    for (size_t i = 0; i < ids.size(); ++i) {
        bool ok = log[i].first ? index->insertRprim(log[i].second, this, ids[i])
                               : index->insertSprim(log[i].second, this, ids[i]);
        if (ok) _inserted.push_back({log[i].first, log[i].second, ids[i]});
    }
}

Path EditableSceneDelegate::addDefaultCamera(RenderIndex* index, double aspect) {
    std::vector<std::pair<bool, Token>> log;
    std::vector<Path> ids;
    RecordingRenderDelegate recorder(index->renderDelegate(), &log, &ids);
    RenderIndex scratch(&recorder);
    Path id = _base.addDefaultCamera(&scratch, aspect);
    scratch.clear();
    if (index->insertSprim(tokens::camera(), this, id))
        _inserted.push_back({false, tokens::camera(), id});
    return id;
}

const Value* EditableSceneDelegate::override(const Path& id, const std::string& attribute) const {
    auto p = _overrides.find(id);
    if (p == _overrides.end()) return nullptr;
    auto a = p->second.find(attribute);
    return a == p->second.end() ? nullptr : &a->second;
}

EditResult EditableSceneDelegate::setAttribute(RenderIndex* index, const std::string& primPath,
                                               const std::string& attribute,
                                               const EditValue& value) {
    using Code = EditResult::Code;
    const usd::Prim* prim = _stage.prim(primPath);
    if (!prim) return {Code::NotFound, "no prim at '" + primPath + "'"};
    if (attribute.rfind("xformOp:", 0) == 0) return setXformOp(index, primPath, attribute, value);
    Path id(primPath);
    std::string why;
    auto store = [&](const Value& current, const std::string& key) -> std::optional<EditResult> {
        auto v = shapeLike(current, value, &why);
        if (!v) return EditResult{Code::BadValue, "'" + primPath + "." + attribute + "': " + why};
        _overrides[id][key] = *v;
        return std::nullopt;
    };

    // A shader input of a material network in the index.
    if (prim->typeName() == "Shader") {
        if (attribute.rfind("inputs:", 0) != 0)
            return {Code::Unsupported,
                    "'" + attribute + "': only shader inputs (inputs:*) are editable"};
        Token input(stripPrefix(attribute, "inputs:"));
        std::vector<Path> materials;
        Value current;
        for (const Inserted& e : _inserted) {
            if (e.isRprim || e.type != tokens::material()) continue;
            MaterialNetwork net = _base.getMaterialResource(e.id);
            if (const MaterialNode* node = net.node(id)) {
                materials.push_back(e.id);
                if (auto it = node->parameters.find(input); it != node->parameters.end())
                    current = it->second;
            }
        }
        if (materials.empty())
            return {Code::NotFound, "shader '" + primPath + "' is not part of any material in use"};
        if (auto bad = store(current, "inputs:" + input.str())) return *bad;
        for (const Path& m : materials)
            index->changeTracker().markSprimDirty(m, SprimDirty::MaterialParams);
        return {};
    }

    const Inserted* entry = nullptr;
    for (const Inserted& e : _inserted)
        if (e.id == id) entry = &e;
    if (!entry)
        return {Code::Unsupported, "prim '" + primPath + "' (" + prim->typeName() +
                                       ") is not rendered, so it has nothing to edit"};
    if (isLightType(entry->type)) {
        Token param(stripPrefix(attribute, "inputs:"));
        if (auto bad = store(_base.getLightParamValue(id, param), "inputs:" + param.str()))
            return *bad;
        index->changeTracker().markSprimDirty(id, SprimDirty::Params);
        return {};
    }
    if (entry->type == tokens::camera()) {
        static const char* kParams[] = {"focalLength",
                                        "horizontalAperture",
                                        "verticalAperture",
                                        "horizontalApertureOffset",
                                        "verticalApertureOffset",
                                        "clippingRange",
                                        "fStop",
                                        "focusDistance"};
        bool known = false;
        for (const char* p : kParams) known |= attribute == p;
        if (!known)
            return {Code::Unsupported, "camera attribute '" + attribute + "' is not editable"};
        Value current = _base.getCameraParamValue(id, Token(attribute));
        if (isEmpty(current) && attribute == "clippingRange") current = Value(glm::vec2(0.0f));
        if (auto bad = store(current, attribute)) return *bad;
        index->changeTracker().markSprimDirty(id, SprimDirty::Params);
        return {};
    }
    if (entry->isRprim) {
        DirtyBits bits = 0;
        std::string key;
        if (attribute == "points")
            bits = RprimDirty::Points, key = "points";
        else if (attribute == "radius")
            bits = RprimDirty::Points, key = "radius";
        else if (attribute == "normals" || attribute == "primvars:normals")
            bits = RprimDirty::Normals, key = "normals";
        else if (attribute.rfind("primvars:", 0) == 0)
            bits = RprimDirty::Primvar, key = stripPrefix(attribute, "primvars:");
        else if (attribute == "doubleSided")
            bits = RprimDirty::DoubleSided, key = "doubleSided";
        if (!bits)
            return {Code::Unsupported, "'" + attribute + "' of " + prim->typeName() +
                                           " is not editable yet (points, normals, primvars:*, "
                                           "radius and doubleSided are)"};
        Value current =
            key == "doubleSided" ? Value(_base.getDoubleSided(id)) : _base.get(id, Token(key));
        if (auto bad = store(current, key)) return *bad;
        index->changeTracker().markRprimDirty(id, bits);
        return {};
    }
    return {Code::Unsupported, "prim '" + primPath + "' cannot be edited"};
}

glm::dmat4 EditableSceneDelegate::worldTransform(const std::string& primPath) const {
    std::vector<const usd::Prim*> chain;
    for (const usd::Prim* p = _stage.prim(primPath); p && p != _stage.pseudoRoot(); p = p->parent())
        chain.push_back(p);
    glm::dmat4 world(1.0);
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
        std::string warning;
        adapter::LocalTransform local = adapter::computeLocalTransform(**it, _time, &warning);
        if (auto o = _localOverrides.find((*it)->path()); o != _localOverrides.end())
            local.matrix = o->second;
        world = local.resetsXformStack ? local.matrix : world * local.matrix;
    }
    return world;
}

EditResult EditableSceneDelegate::setLocalTransform(RenderIndex* index, const std::string& primPath,
                                                    const double matrix[16]) {
    using Code = EditResult::Code;
    if (!_stage.prim(primPath) || primPath == "/")
        return {Code::NotFound, "no prim at '" + primPath + "'"};
    glm::dmat4 m;
    for (int i = 0; i < 16; ++i) {
        if (!std::isfinite(matrix[i]))
            return {Code::BadValue, "the matrix has a non-finite element"};
        (&m[0][0])[i] = matrix[i];
    }
    _localOverrides[primPath] = m;
    _opOverrides.erase(primPath);  // the whole matrix wins over earlier op edits
    markTransformDirty(index, primPath);
    return {};
}

void EditableSceneDelegate::markTransformDirty(RenderIndex* index, const std::string& primPath) {
    for (const Inserted& e : _inserted) {
        if (!isAtOrBelow(e.id.str(), primPath)) continue;
        if (e.isRprim)
            index->changeTracker().markRprimDirty(e.id, RprimDirty::Transform);
        else if (e.type == tokens::camera() || isLightType(e.type))
            index->changeTracker().markSprimDirty(e.id, SprimDirty::Transform);
    }
}

namespace {

/// USDA text for a value of an xform op (scalars, tuples, quaternions, matrices).
std::optional<std::string> usdaText(const Value& v) {
    char buf[64];
    auto num = [&](double x) {
        std::snprintf(buf, sizeof buf, "%.17g", x);
        return std::string(buf);
    };
    auto tuple = [&](const float* p, int n) {
        std::string out = "(";
        for (int i = 0; i < n; ++i) out += (i ? ", " : "") + num(p[i]);
        return out + ")";
    };
    if (auto f = getFloat(v); f && !std::holds_alternative<double>(v)) return num(*f);
    if (auto* d = std::get_if<double>(&v)) return num(*d);
    if (auto* x = std::get_if<glm::vec2>(&v)) return tuple(&x->x, 2);
    if (auto* x = std::get_if<glm::vec3>(&v)) return tuple(&x->x, 3);
    if (auto* x = std::get_if<glm::vec4>(&v)) return tuple(&x->x, 4);
    if (auto* m = std::get_if<glm::dmat4>(&v)) {
        std::string out = "(";
        for (int r = 0; r < 4; ++r) {  // USD rows = glm columns (see shapeLike)
            out += r ? ", (" : "(";
            for (int c = 0; c < 4; ++c) out += (c ? ", " : "") + num((*m)[r][c]);
            out += ")";
        }
        return out + ")";
    }
    return std::nullopt;
}

}  // namespace

EditResult EditableSceneDelegate::setXformOp(RenderIndex* index, const std::string& primPath,
                                             const std::string& attribute, const EditValue& value) {
    using Code = EditResult::Code;
    const usd::Prim* prim = _stage.prim(primPath);
    if (!prim) return {Code::NotFound, "no prim at '" + primPath + "'"};
    const usd::Attribute* orderAttr = prim->attribute("xformOpOrder");
    const std::vector<std::string>* order = nullptr;
    usd::Value orderValue;
    if (orderAttr) {
        orderValue = orderAttr->get(_time);
        order = orderValue.strings();
    }
    auto inOrder = [&](const std::string& name) {
        if (!order) return false;
        for (const std::string& op : *order)
            if (op == name || op == "!invert!" + name) return true;
        return false;
    };
    if (!inOrder(attribute))
        return {Code::Unsupported, "'" + attribute + "' is not in the xformOpOrder of '" +
                                       primPath +
                                       "' (adding ops is not supported; use prdSetLocalTransform)"};
    const usd::Attribute* attr = prim->attribute(attribute);
    Value current = attr && attr->hasValue() ? adapter::toHdValue(attr->get(_time)) : Value();
    std::string why;
    auto v = shapeLike(current, value, &why);
    if (!v) return {Code::BadValue, "'" + primPath + "." + attribute + "': " + why};
    if (!attr) return {Code::Unsupported, "'" + attribute + "' has no authored type"};

    // Re-evaluate the op stack with the adapter's own evaluator on a one-prim stage that holds
    // the ops with the edited values.
    auto ops = _opOverrides[primPath];
    ops[attribute] = *v;
    std::string text = "#usda 1.0\ndef Xform \"P\"\n{\n";
    std::string orderText;
    for (const std::string& entry : *order) {
        orderText += (orderText.empty() ? "\"" : ", \"") + entry + "\"";
        if (entry == "!resetXformStack!") continue;
        std::string name = entry.rfind("!invert!", 0) == 0 ? entry.substr(8) : entry;
        const usd::Attribute* a = prim->attribute(name);
        if (!a || !a->hasValue()) continue;  // the evaluator warns and skips it, as the adapter did
        auto it = ops.find(name);
        Value opValue = it != ops.end() ? it->second : adapter::toHdValue(a->get(_time));
        auto valueText = usdaText(opValue);
        if (!valueText)
            return {Code::Unsupported,
                    "xform op '" + name + "' has a value type that cannot be edited"};
        text += "    " + a->typeName() + " " + name + " = " + *valueText + "\n";
    }
    text += "    uniform token[] xformOpOrder = [" + orderText + "]\n}\n";
    std::unique_ptr<usd::Stage> scratch;
    try {
        scratch = usd::Stage::openString(text, primPath + " (edited xform ops)");
    } catch (const std::exception& e) {
        return {Code::BadValue, "'" + primPath + "." + attribute + "': " + e.what()};
    }
    std::string warning;
    adapter::LocalTransform local =
        adapter::computeLocalTransform(*scratch->prim("/P"), kDefaultTimeNaN, &warning);
    _opOverrides[primPath] = std::move(ops);
    _localOverrides[primPath] = local.matrix;
    markTransformDirty(index, primPath);
    return {};
}

// ---- Pulls: overrides first, then the adapter. -------------------------------------------

MeshTopology EditableSceneDelegate::getMeshTopology(const Path& id) const {
    return _base.getMeshTopology(id);
}
SubdivTags EditableSceneDelegate::getSubdivTags(const Path& id) const {
    return _base.getSubdivTags(id);
}

glm::dmat4 EditableSceneDelegate::getTransform(const Path& id) const {
    // Instanced prototypes are placed relative to their instancer: not a world transform.
    if (!_base.getInstancerId(id).empty()) return _base.getTransform(id);
    for (const auto& [path, m] : _localOverrides)
        if (isAtOrBelow(id.str(), path)) return worldTransform(id.str());
    return _base.getTransform(id);
}

bool EditableSceneDelegate::getVisible(const Path& id) const {
    return _base.getVisible(id);
}

bool EditableSceneDelegate::getDoubleSided(const Path& id) const {
    if (const Value* v = override(id, "doubleSided"))
        if (auto* b = std::get_if<bool>(v)) return *b;
    return _base.getDoubleSided(id);
}

Value EditableSceneDelegate::get(const Path& id, const Token& key) const {
    if (const Value* v = override(id, key.str())) return *v;
    return _base.get(id, key);
}

Value EditableSceneDelegate::getIndexedPrimvar(const Path& id, const Token& key,
                                               std::vector<int>* indices) const {
    Value base = _base.getIndexedPrimvar(id, key, indices);
    if (const Value* v = override(id, key.str())) return *v;  // indices stay as authored
    return base;
}

std::vector<PrimvarDescriptor> EditableSceneDelegate::getPrimvarDescriptors(
    const Path& id, Interpolation interp) const {
    return _base.getPrimvarDescriptors(id, interp);
}

Path EditableSceneDelegate::getMaterialId(const Path& id) const {
    return _base.getMaterialId(id);
}

std::vector<std::pair<Path, std::vector<int>>> EditableSceneDelegate::getMaterialSubsets(
    const Path& id) const {
    return _base.getMaterialSubsets(id);
}

MaterialNetwork EditableSceneDelegate::getMaterialResource(const Path& materialId) const {
    MaterialNetwork net = _base.getMaterialResource(materialId);
    for (MaterialNode& node : net.nodes) {
        auto it = _overrides.find(node.path);
        if (it == _overrides.end()) continue;
        for (const auto& [attr, v] : it->second)
            node.parameters[Token(stripPrefix(attr, "inputs:"))] = v;
    }
    return net;
}

Value EditableSceneDelegate::getLightParamValue(const Path& id, const Token& param) const {
    if (const Value* v = override(id, "inputs:" + param.str())) return *v;
    return _base.getLightParamValue(id, param);
}

Value EditableSceneDelegate::getCameraParamValue(const Path& id, const Token& param) const {
    if (const Value* v = override(id, param.str())) {
        const std::string& k = param.str();
        bool isLength = k == "focalLength" || k == "horizontalAperture" ||
                        k == "verticalAperture" || k == "horizontalApertureOffset" ||
                        k == "verticalApertureOffset";
        if (isLength)
            if (auto f = getFloat(*v)) return Value(static_cast<float>(*f * kCameraUnit));
        return *v;
    }
    return _base.getCameraParamValue(id, param);
}

}  // namespace principled::plugins
