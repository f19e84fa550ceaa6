// SPDX-License-Identifier: Apache-2.0
#include "delegate/shading/materialProgram.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <string_view>

#include "delegate/shading/programCompiler.h"
#include "delegate/shading/standardSurface.h"

namespace principled::shading {

using namespace hd;

namespace {

using Slot = MaterialProgram::Slot;

struct SlotInfo {
    const char* name;
    Slot slot;
    bool color;
};

// UsdPreviewSurface inputs (spec 2.5) and the Disney extras (MaterialX Disney BSDF names).
constexpr SlotInfo kSlots[] = {
    {"diffuseColor", Slot::DiffuseColor, true},
    {"emissiveColor", Slot::EmissiveColor, true},
    {"specularColor", Slot::SpecularColor, true},
    {"normal", Slot::Normal, true},
    {"metallic", Slot::Metallic, false},
    {"roughness", Slot::Roughness, false},
    {"clearcoat", Slot::Clearcoat, false},
    {"clearcoatRoughness", Slot::ClearcoatRoughness, false},
    {"opacity", Slot::Opacity, false},
    {"ior", Slot::Ior, false},
    {"subsurface", Slot::Subsurface, false},
    {"specular", Slot::Specular, false},
    {"specularTint", Slot::SpecularTint, false},
    {"anisotropic", Slot::Anisotropic, false},
    {"sheen", Slot::Sheen, false},
    {"sheenTint", Slot::SheenTint, false},
    {"clearcoatGloss", Slot::ClearcoatGloss, false},
    {"specTrans", Slot::SpecTrans, false},
};

// Inputs read as constants only (interfaceOnly in the spec, or tokens) and inputs ignored.
constexpr const char* kOtherInputs[] = {"useSpecularWorkflow", "opacityThreshold", "opacityMode",
                                        "displacement", "occlusion"};

// Components of a UsdPrimvarReader_TYPE result; 0 for types a surface cannot consume.
int primvarComponents(std::string_view type) {
    if (type == "float" || type == "int") return 1;
    if (type == "float2") return 2;
    if (type == "float3" || type == "normal" || type == "point" || type == "vector") return 3;
    if (type == "float4") return 4;
    return 0;
}

// MaterialX spellings of the UsdPreviewSurface nodes (MaterialX libraries/bxdf/usd_*.mtlx).
constexpr std::pair<const char*, const char*> kMaterialXAliases[] = {
    {"ND_UsdPreviewSurface_surfaceshader", "UsdPreviewSurface"},
    {"ND_UsdUVTexture", "UsdUVTexture"},
    {"ND_UsdUVTexture_23", "UsdUVTexture"},
    {"ND_UsdPrimvarReader_float", "UsdPrimvarReader_float"},
    {"ND_UsdPrimvarReader_vector2", "UsdPrimvarReader_float2"},
    {"ND_UsdPrimvarReader_vector", "UsdPrimvarReader_float3"},
    {"ND_UsdPrimvarReader_vector4", "UsdPrimvarReader_float4"},
    {"ND_UsdPrimvarReader_integer", "UsdPrimvarReader_int"},
    {"ND_UsdTransform2d", "UsdTransform2d"}};

// The UsdPreviewSurface node name of id (its MaterialX spelling mapped), else id itself.
Token usdIdentifier(const Token& id) {
    for (const auto& [mtlx, usd] : kMaterialXAliases)
        if (id.str() == mtlx) return Token(usd);
    return id;
}

}  // namespace

namespace program {

// v holds `count` meaningful components; a scalar feeding a colour is splatted. A non-finite
// scalar keeps the current (authored or fallback) value, as the constant mapping does; colours
// are sanitised per component by mapPreviewSurface().
void setSlot(PreviewSurfaceParams& p, Slot slot, const glm::vec4& v, int count) {
    glm::vec3 c = count >= 3 ? glm::vec3(v) : glm::vec3(v.x);
    float f = v.x;
    bool colour = slot == Slot::DiffuseColor || slot == Slot::EmissiveColor ||
                  slot == Slot::SpecularColor || slot == Slot::Normal;
    if (!colour && !std::isfinite(f)) return;
    switch (slot) {
        case Slot::DiffuseColor:
            p.diffuseColor = c;
            break;
        case Slot::EmissiveColor:
            p.emissiveColor = c;
            break;
        case Slot::SpecularColor:
            p.specularColor = c;
            break;
        case Slot::Normal:
            p.normal = c;
            break;
        case Slot::Metallic:
            p.metallic = f;
            break;
        case Slot::Roughness:
            p.roughness = f;
            break;
        case Slot::Clearcoat:
            p.clearcoat = f;
            break;
        case Slot::ClearcoatRoughness:
            p.clearcoatRoughness = f;
            break;
        case Slot::Opacity:
            p.opacity = f;
            break;
        case Slot::Ior:
            p.ior = f;
            break;
        case Slot::Subsurface:
            p.subsurface = f;
            break;
        case Slot::Specular:
            p.specular = f;
            break;
        case Slot::SpecularTint:
            p.specularTint = f;
            break;
        case Slot::Anisotropic:
            p.anisotropic = f;
            break;
        case Slot::Sheen:
            p.sheen = f;
            break;
        case Slot::SheenTint:
            p.sheenTint = f;
            break;
        case Slot::ClearcoatGloss:
            p.clearcoatGloss = f;
            break;
        case Slot::SpecTrans:
            p.specTrans = f;
            break;
        case Slot::Count:
            break;
    }
}

std::optional<std::pair<glm::vec4, int>> numeric(const Value& v) {
    if (auto* x = getIf<glm::vec4>(v)) return std::pair{*x, 4};
    if (auto* x = getIf<glm::vec3>(v)) return std::pair{glm::vec4(*x, 0.0f), 3};
    if (auto* x = getIf<glm::vec2>(v)) return std::pair{glm::vec4(x->x, x->y, 0.0f, 0.0f), 2};
    if (auto f = getFloat(v)) return std::pair{glm::vec4(*f, 0.0f, 0.0f, 0.0f), 1};
    return std::nullopt;
}

}  // namespace program

using program::numeric;
using program::setSlot;

std::optional<int16_t> MaterialProgram::Compiler::newRegister(const glm::vec4& init,
                                                              bool constant) {
    if (static_cast<int>(_prog._initial.size()) >= kMaxRegisters) {
        if (!_overflowNoted)
            _notes->push_back("material network needs more than " + std::to_string(kMaxRegisters) +
                              " values; the remaining inputs use their fallbacks");
        _overflowNoted = true;
        return std::nullopt;
    }
    _prog._initial.push_back(init);
    _info.push_back(RegInfo{constant, Token(), glm::mat2(1.0f)});
    return static_cast<int16_t>(_prog._initial.size() - 1);
}

void MaterialProgram::Compiler::note(const MaterialNode& node, const std::string& text) {
    _notes->push_back((node.where.empty() ? "" : node.where + ": ") + node.path.str() + ": " +
                      text);
}

std::optional<MaterialProgram::Operand> MaterialProgram::Compiler::connection(
    const MaterialNode& consumer, const char* input) {
    auto it = consumer.inputConnections.find(Token(input));
    if (it == consumer.inputConnections.end() || it->second.empty()) return std::nullopt;
    const MaterialConnection& c = it->second.front();
    std::optional<int16_t> reg = compileNode(c.upstreamNode);
    if (!reg) return std::nullopt;
    const MaterialNode* up = _net.node(c.upstreamNode);
    const std::string id = usdIdentifier(up->identifier).str();
    const std::string& out = c.upstreamOutput.str();
    Operand o;
    o.reg = *reg;
    if (id == "UsdUVTexture") {
        if (out == "r")
            o = {*reg, 0, 1};
        else if (out == "g")
            o = {*reg, 1, 1};
        else if (out == "b")
            o = {*reg, 2, 1};
        else if (out == "a")
            o = {*reg, 3, 1};
        else if (out == "rgb" || out.empty())
            o = {*reg, 0, 3};
        else if (out == "rgba")
            o = {*reg, 0, 4};  // removed in spec 2.3, still in old files
        else {
            note(consumer, std::string("input '") + input + "' reads unknown output '" + out +
                               "' of " + up->path.str() + "; using its value or fallback");
            return std::nullopt;
        }
    } else if (id == "UsdTransform2d") {
        o = {*reg, 0, 2};
    } else if (id.rfind("UsdPrimvarReader_", 0) == 0) {  // "result"
        o = {*reg, 0, static_cast<uint8_t>(primvarComponents(id.substr(17)))};
    } else if (id.rfind("ND_extract_", 0) == 0) {  // component `index` of its input's register
        const int n = program::materialxComponents(id);
        int index = 0;
        if (auto p = up->parameters.find(Token("index")); p != up->parameters.end())
            index = static_cast<int>(getFloat(p->second).value_or(0.0f));
        o = {*reg, static_cast<uint8_t>(std::clamp(index, 0, n - 1)), 1};
    } else if (id.rfind("ND_separate", 0) == 0) {  // outx/outr, outy/outg, outz/outb, outw/outa
        const std::string comps = "xyzw", colour = "rgba";
        const char last = out.empty() ? 'x' : out.back();
        size_t index = comps.find(last) != std::string::npos ? comps.find(last) : colour.find(last);
        if (index == std::string::npos || int(index) >= program::materialxComponents(id)) {
            note(consumer, std::string("input '") + input + "' reads unknown output '" + out + "' of " +
                               up->path.str() + "; using its value or fallback");
            return std::nullopt;
        }
        o = {*reg, static_cast<uint8_t>(index), 1};
    } else {  // a MaterialX node: its one output, "out"
        o = {*reg, 0, static_cast<uint8_t>(program::materialxComponents(id))};
    }
    return o;
}

std::optional<MaterialProgram::Operand> MaterialProgram::Compiler::vec2Input(
    const MaterialNode& node, const char* input, glm::vec2 fallback) {
    if (auto c = connection(node, input)) return c;
    glm::vec2 v = fallback;
    if (auto it = node.parameters.find(Token(input)); it != node.parameters.end())
        if (auto n = numeric(it->second))
            v = n->second == 1 ? glm::vec2(n->first.x) : glm::vec2(n->first);
    auto reg = newRegister(glm::vec4(v, 0.0f, 0.0f), true);
    if (!reg) return std::nullopt;
    return Operand{*reg, 0, 2};
}

std::optional<int16_t> MaterialProgram::Compiler::compileNode(const Path& path) {
    if (auto it = _compiled.find(path); it != _compiled.end()) return it->second;
    const MaterialNode* node = _net.node(path);
    if (!node) {
        _notes->push_back("connection to missing node " + path.str() + "; using the fallback");
        _compiled[path] = std::nullopt;
        return std::nullopt;
    }
    if (!_inProgress.insert(path).second) {
        note(*node, "connection cycle; using the fallback");
        return std::nullopt;
    }
    std::optional<int16_t> reg;
    const std::string id = usdIdentifier(node->identifier).str();
    bool handled = false;
    if (id == "UsdUVTexture") {
        reg = compileTexture(*node);
    } else if (id.rfind("UsdPrimvarReader_", 0) == 0) {
        int n = primvarComponents(std::string_view(id).substr(17));
        if (n > 0)
            reg = compilePrimvarReader(*node, n);
        else
            note(*node, "'" + id + "' cannot feed a surface input; using the fallback");
    } else if (id == "UsdTransform2d") {
        reg = compileTransform(*node);
    } else if (reg = compileMaterialXNode(*node, &handled); !handled) {
        note(*node, "node '" + id +
                        "' not supported; inputs it feeds use their authored value or default");
    }
    _inProgress.erase(path);
    _compiled[path] = reg;
    return reg;
}

std::optional<int16_t> MaterialProgram::Compiler::compileTexture(const MaterialNode& node) {
    UvTexture tex = UvTexture::resolve(node, _cache, _notes);
    if (!tex.texture) return newRegister(tex.fallback, true);
    std::optional<Operand> st = vec2Input(node, "st", glm::vec2(0.0f));
    if (!st) return std::nullopt;
    return sampleTexture(tex, *st);
}

std::optional<int16_t> MaterialProgram::Compiler::sampleTexture(const UvTexture& tex,
                                                                const Operand& stIn) {
    const Operand* st = &stIn;
    if (isConstant(*st))  // no primvar upstream: one lookup now, a constant afterwards
        return newRegister(tex.sample(_cache, glm::vec2(constantValue(*st))), true);
    auto reg = newRegister(glm::vec4(0.0f), false);
    if (!reg) return std::nullopt;
    TextureOp op{tex, Token(), glm::mat2(1.0f)};
    const RegInfo& in = _info[st->reg];
    if (st->offset == 0 && st->count >= 2) {
        op.footprintPrimvar = in.root;
        op.footprintJacobian = in.jacobian;
    }
    _prog._textures.push_back(op);
    _prog._ops.push_back(
        {Op::Kind::Texture, *reg, *st, static_cast<int16_t>(_prog._textures.size() - 1)});
    return reg;
}

std::optional<int16_t> MaterialProgram::Compiler::compilePrimvarReader(const MaterialNode& node,
                                                                       int components) {
    PrimvarOp op;
    op.components = components;
    if (auto it = node.parameters.find(Token("fallback")); it != node.parameters.end())
        if (auto n = numeric(it->second)) op.fallback = n->first;
    std::string varname;
    if (auto it = node.parameters.find(Token("varname")); it != node.parameters.end())
        if (auto s = getString(it->second))
            varname = *s;  // a string since spec 2.3, a token before
    if (varname.empty()) {
        note(node, "no varname; using the reader's fallback");
        return newRegister(op.fallback, true);
    }
    return primvarRegister(Token(varname), components, op.fallback);
}

std::optional<int16_t> MaterialProgram::Compiler::primvarRegister(const Token& name, int components,
                                                                  const glm::vec4& fallback) {
    PrimvarOp op{name, components, fallback};
    auto reg = newRegister(op.fallback, false);
    if (!reg) return std::nullopt;
    if (components == 2) _info[*reg].root = op.name;
    if (std::find(_prog._primvarsRead.begin(), _prog._primvarsRead.end(), op.name) ==
        _prog._primvarsRead.end())
        _prog._primvarsRead.push_back(op.name);
    _prog._primvars.push_back(op);
    _prog._ops.push_back(
        {Op::Kind::Primvar, *reg, Operand{}, static_cast<int16_t>(_prog._primvars.size() - 1)});
    return reg;
}

std::optional<int16_t> MaterialProgram::Compiler::compileTransform(const MaterialNode& node) {
    auto scalar = [&](const char* name, float fallback) {
        if (auto it = node.parameters.find(Token(name)); it != node.parameters.end())
            if (auto f = getFloat(it->second); f && std::isfinite(*f)) return *f;
        return fallback;
    };
    auto vec2 = [&](const char* name, glm::vec2 fallback) {
        if (auto it = node.parameters.find(Token(name)); it != node.parameters.end())
            if (auto* v = getIf<glm::vec2>(it->second);
                v && std::isfinite(v->x) && std::isfinite(v->y))
                return *v;
        return fallback;
    };
    if (node.inputConnections.count(Token("rotation")) ||
        node.inputConnections.count(Token("scale")) ||
        node.inputConnections.count(Token("translation")))
        note(node, "only 'in' is connectable; rotation, scale and translation use their values");
    Transform2d t = Transform2d::make(scalar("rotation", 0.0f), vec2("scale", glm::vec2(1.0f)),
                                      vec2("translation", glm::vec2(0.0f)));
    std::optional<Operand> in = vec2Input(node, "in", glm::vec2(0.0f));
    if (!in) return std::nullopt;
    return transformRegister(t, *in);
}

std::optional<int16_t> MaterialProgram::Compiler::transformRegister(const Transform2d& t,
                                                                    const Operand& inOperand) {
    const Operand* in = &inOperand;
    if (isConstant(*in))
        return newRegister(glm::vec4(t.apply(glm::vec2(constantValue(*in))), 0.0f, 0.0f), true);
    auto reg = newRegister(glm::vec4(0.0f), false);
    if (!reg) return std::nullopt;
    if (in->offset == 0 && in->count >= 2) {
        _info[*reg].root = _info[in->reg].root;
        _info[*reg].jacobian = t.linear * _info[in->reg].jacobian;  // chain rule
    }
    _prog._transforms.push_back(t);
    _prog._ops.push_back(
        {Op::Kind::Transform, *reg, *in, static_cast<int16_t>(_prog._transforms.size() - 1)});
    return reg;
}

void MaterialProgram::Compiler::compileSurface(const MaterialNode& surface) {
    PreviewSurfaceParams& base = _prog._base;
    for (const SlotInfo& s : kSlots) {
        // The authored value first: it stays when a connection is unusable or yields NaN.
        if (auto it = surface.parameters.find(Token(s.name)); it != surface.parameters.end()) {
            if (auto n = numeric(it->second)) {
                setSlot(base, s.slot, n->first, s.color ? n->second : 1);
            } else {
                note(surface,
                     std::string("input '") + s.name + "' has a non-numeric value; ignored");
            }
        }
        if (auto c = connection(surface, s.name)) {
            if (isConstant(*c)) {
                setSlot(base, s.slot, constantValue(*c), c->count);
            } else {
                _prog._bindings.push_back({s.slot, *c});
                if (s.slot == Slot::Normal) base.normalVaries = true;
            }
        }
    }
    auto constant = [&](const char* name) -> const Value* {
        if (surface.inputConnections.count(Token(name)))
            note(surface,
                 std::string("input '") + name + "' is interfaceOnly; its connection is ignored");
        auto it = surface.parameters.find(Token(name));
        return it == surface.parameters.end() ? nullptr : &it->second;
    };
    if (const Value* v = constant("useSpecularWorkflow"))
        if (auto f = getFloat(*v)) base.useSpecularWorkflow = *f > 0.5f;
    if (const Value* v = constant("opacityThreshold"))
        if (auto f = getFloat(*v)) base.opacityThreshold = *f;
    if (const Value* v = constant("opacityMode")) {
        auto mode = getString(*v).value_or("");
        if (mode == "presence")
            base.opacityMode = OpacityMode::Presence;
        else if (mode != "transparent")
            note(surface, "opacityMode '" + mode + "' is not transparent|presence; ignored");
    }
    std::string ignored;
    for (const char* name : {"displacement", "occlusion"})
        if (surface.parameters.count(Token(name)) || surface.inputConnections.count(Token(name)))
            ignored += ignored.empty() ? name : std::string(" and ") + name;
    if (!ignored.empty()) note(surface, ignored + " ignored (not supported by the path tracer)");
    std::string unknown;
    auto known = [](const std::string& n) {
        for (const SlotInfo& s : kSlots)
            if (n == s.name) return true;
        for (const char* o : kOtherInputs)
            if (n == o) return true;
        return false;
    };
    std::set<std::string> names;
    for (const auto& [k, v] : surface.parameters)
        if (k.str().rfind("colorSpace:", 0) != 0) names.insert(k.str());  // an input's metadata
    for (const auto& [k, v] : surface.inputConnections) names.insert(k.str());
    for (const std::string& n : names)
        if (!known(n)) unknown += (unknown.empty() ? "" : ", ") + n;
    if (!unknown.empty()) note(surface, "inputs not used: " + unknown);
}

MaterialProgram::MaterialProgram() : _constant(mapPreviewSurface(_base)) {}

MaterialProgram MaterialProgram::compile(const MaterialNetwork& network, TextureCache& cache,
                                         std::vector<std::string>* notes) {
    MaterialProgram prog;
    prog._cache = &cache;
    const MaterialNode* surface = network.node(network.surfaceTerminal);
    if (!surface) {
        notes->push_back("no surface shader; the geometry bound to it keeps its displayColor");
        prog._hasSurface = false;
        return prog;
    }
    Token id = usdIdentifier(surface->identifier);
    if (id == Token("UsdPreviewSurface")) {
        Compiler(network, cache, notes, prog).compileSurface(*surface);
    } else if (isStandardSurface(id)) {
        Compiler(network, cache, notes, prog).compileStandardSurface(*surface);
    } else {
        prog._hasSurface = false;
        notes->push_back((surface->where.empty() ? "" : surface->where + ": ") +
                         surface->path.str() + ": surface shader '" + surface->identifier.str() +
                         "' is not UsdPreviewSurface or Standard Surface; the geometry bound to "
                         "it keeps its displayColor");
        return prog;
    }
    prog._constant = mapPreviewSurface(prog._base);
    prog.findPresenceOps();
    prog.findNormalMapUv();
    prog._constant.normalMapUv = prog._normalMapUv.get();
    return prog;
}

glm::vec4 MaterialProgram::read(const glm::vec4* regs, const Operand& o) {
    const glm::vec4& r = regs[o.reg];
    if (o.count == 1) return glm::vec4(r[o.offset]);
    glm::vec4 v(0.0f);
    for (int i = 0; i < o.count && o.offset + i < 4; ++i) v[i] = r[o.offset + i];
    return v;
}

void MaterialProgram::run(const Op& op, const ShadingContext& context, glm::vec4* regs) const {
    switch (op.kind) {
        case Op::Kind::Primvar: {
            const PrimvarOp& pv = _primvars[op.index];
            float v[4] = {0.0f, 0.0f, 0.0f, 0.0f};
            glm::vec4 out = pv.fallback;
            if (context.primvar(pv.name, pv.components, v))
                for (int i = 0; i < pv.components; ++i)
                    out[i] = std::isfinite(v[i]) ? v[i] : pv.fallback[i];
            regs[op.out] = out;
            break;
        }
        case Op::Kind::Transform: {
            glm::vec2 in(read(regs, op.in));
            regs[op.out] = glm::vec4(_transforms[op.index].apply(in), 0.0f, 0.0f);
            break;
        }
        case Op::Kind::MulAdd:
            regs[op.out] = read(regs, op.in) * read(regs, op.in2) + read(regs, op.in3);
            break;
        case Op::Kind::Dot:
            regs[op.out] = glm::vec4(glm::dot(read(regs, op.in), read(regs, op.in2)));
            break;
        case Op::Kind::Binary:
            regs[op.out] = applyBinary(BinaryFn(op.index), read(regs, op.in), read(regs, op.in2));
            break;
        case Op::Kind::Texture: {
            const TextureOp& t = _textures[op.index];
            glm::vec2 st(read(regs, op.in));
            glm::vec4 footprint(0.0f);
            glm::vec2 dx, dy;
            if (!t.footprintPrimvar.empty() &&
                context.primvarDerivatives(t.footprintPrimvar, &dx, &dy)) {
                dx = t.footprintJacobian * dx;
                dy = t.footprintJacobian * dy;
                footprint = glm::vec4(dx.x, dx.y, dy.x, dy.y);
            }
            regs[op.out] = t.texture.sample(*_cache, st, footprint);
            break;
        }
    }
}

ShadedMaterial MaterialProgram::evaluate(const ShadingContext& context) const {
    if (_ops.empty()) return _constant;
    glm::vec4 regs[kMaxRegisters];
    std::copy(_initial.begin(), _initial.end(), regs);
    for (const Op& op : _ops) run(op, context, regs);
    PreviewSurfaceParams p = _base;
    for (const Binding& b : _bindings) setSlot(p, b.slot, read(regs, b.source), b.source.count);
    ShadedMaterial m = mapPreviewSurface(p);
    m.normalMapUv = _normalMapUv.get();
    return m;
}

// Walks the ops backwards from a slot's binding register: an op is needed when it writes a
// needed register, and then its input register is needed too (a superset if a register is
// written twice). In execution order.
std::vector<uint16_t> MaterialProgram::opsFeeding(Slot slot) const {
    std::vector<uint16_t> ops;
    std::vector<bool> needed(kMaxRegisters, false);
    bool any = false;
    for (const Binding& b : _bindings)
        if (b.slot == slot && b.source.reg >= 0) needed[size_t(b.source.reg)] = any = true;
    if (!any) return ops;
    for (size_t i = _ops.size(); i-- > 0;) {
        const Op& op = _ops[i];
        if (op.out < 0 || !needed[size_t(op.out)]) continue;
        ops.push_back(uint16_t(i));
        if (op.kind == Op::Kind::Primvar) continue;
        for (const Operand* in : {&op.in, &op.in2, &op.in3})
            if (in->reg >= 0) needed[size_t(in->reg)] = true;
    }
    std::reverse(ops.begin(), ops.end());
    return ops;
}

void MaterialProgram::findPresenceOps() { _presenceOps = opsFeeding(Slot::Opacity); }

void MaterialProgram::findNormalMapUv() {
    // The texture nearest the normal input whose st follows a primvar: its tangent frame is the
    // one the map's x and y were painted in.
    _normalMapUv.reset();
    const std::vector<uint16_t> ops = opsFeeding(Slot::Normal);
    for (auto it = ops.rbegin(); it != ops.rend(); ++it) {
        const Op& op = _ops[*it];
        if (op.kind != Op::Kind::Texture) continue;
        const TextureOp& t = _textures[size_t(op.index)];
        if (t.footprintPrimvar.empty()) continue;
        _normalMapUv = std::make_shared<const NormalMapUv>(NormalMapUv{t.footprintPrimvar, t.footprintJacobian});
        return;
    }
}

float MaterialProgram::presence(const ShadingContext& context) const {
    if (_ops.empty()) return _constant.presence();
    glm::vec4 regs[kMaxRegisters];
    std::copy(_initial.begin(), _initial.end(), regs);
    for (uint16_t i : _presenceOps) run(_ops[i], context, regs);
    PreviewSurfaceParams p = _base;
    for (const Binding& b : _bindings)
        if (b.slot == Slot::Opacity) setSlot(p, b.slot, read(regs, b.source), b.source.count);
    return mapPreviewSurface(p).presence();
}

glm::vec4 MaterialProgram::applyBinary(BinaryFn fn, const glm::vec4& a, const glm::vec4& b) {
    glm::vec4 r(0.0f);
    for (int i = 0; i < 4; ++i) {
        float x = 0.0f;
        switch (fn) {
            case BinaryFn::Divide: x = a[i] / b[i]; break;
            case BinaryFn::Power: x = std::pow(a[i], b[i]); break;
            case BinaryFn::Min: x = std::min(a[i], b[i]); break;
            case BinaryFn::Max: x = std::max(a[i], b[i]); break;
        }
        r[i] = std::isfinite(x) ? x : 0.0f;
    }
    return r;
}

bool MaterialProgram::mayEmit() const {
    if (_constant.emission != glm::vec3(0.0f)) return true;
    for (const Binding& b : _bindings)
        if (b.slot == Slot::EmissiveColor) return true;
    return false;
}

bool MaterialProgram::mayBePartlyPresent() const {
    if (_constant.presence() < 1.0f) return true;
    for (const Binding& b : _bindings)
        if (b.slot == Slot::Opacity) return true;
    return false;
}

}  // namespace principled::shading
