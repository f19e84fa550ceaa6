// SPDX-License-Identifier: Apache-2.0
// The MaterialX part of MaterialProgram::Compiler: Standard Surface lowered onto the principled
// inputs, and the MaterialX texture nodes lowered onto the texture, primvar and arithmetic ops.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <string>

#include "delegate/shading/materialxImage.h"
#include "delegate/shading/programCompiler.h"
#include "delegate/shading/standardSurface.h"

namespace principled::shading {

using namespace hd;
using Slot = MaterialProgram::Slot;
using program::numeric;

namespace {

bool startsWith(const std::string& s, const char* prefix) {
    return s.rfind(prefix, 0) == 0;
}

}  // namespace

namespace program {

int materialxComponents(const std::string& id) {
    if (startsWith(id, "ND_normalmap")) return 3;
    std::string type = id.substr(id.rfind('_') + 1);
    if (type.size() > 2 && type.compare(type.size() - 2, 2, "FA") == 0) type.resize(type.size() - 2);
    if (type == "float" || type == "integer" || type == "boolean") return 1;
    if (type == "vector2") return 2;
    if (type == "color3" || type == "vector3") return 3;
    return 4;
}

}  // namespace program

std::optional<MaterialProgram::Operand> MaterialProgram::Compiler::constant(const glm::vec4& v,
                                                                            uint8_t count) {
    auto reg = newRegister(v, true);
    if (!reg) return std::nullopt;
    return Operand{*reg, 0, count};
}

std::optional<MaterialProgram::Operand> MaterialProgram::Compiler::mulAdd(
    const Operand& a, const Operand& b, const std::optional<Operand>& c, uint8_t count) {
    if (isConstant(a) && isConstant(b) && (!c || isConstant(*c)))
        return constant(
            constantValue(a) * constantValue(b) + (c ? constantValue(*c) : glm::vec4(0.0f)), count);
    std::optional<Operand> addend = c ? c : constant(glm::vec4(0.0f), count);
    if (!addend) return std::nullopt;
    auto reg = newRegister(glm::vec4(0.0f), false);
    if (!reg) return std::nullopt;
    _prog._ops.push_back({Op::Kind::MulAdd, *reg, a, -1, b, *addend});
    return Operand{*reg, 0, count};
}

std::optional<MaterialProgram::Operand> MaterialProgram::Compiler::dot(const Operand& a,
                                                                       const Operand& b) {
    if (isConstant(a) && isConstant(b))
        return constant(glm::vec4(glm::dot(constantValue(a), constantValue(b))), 1);
    auto reg = newRegister(glm::vec4(0.0f), false);
    if (!reg) return std::nullopt;
    _prog._ops.push_back({Op::Kind::Dot, *reg, a, -1, b, Operand{}});
    return Operand{*reg, 0, 1};
}

std::optional<MaterialProgram::Operand> MaterialProgram::Compiler::binary(BinaryFn fn, const Operand& a,
                                                                          const Operand& b, uint8_t count) {
    if (isConstant(a) && isConstant(b))
        return constant(applyBinary(fn, constantValue(a), constantValue(b)), count);
    auto reg = newRegister(glm::vec4(0.0f), false);
    if (!reg) return std::nullopt;
    _prog._ops.push_back({Op::Kind::Binary, *reg, a, int16_t(fn), b, Operand{}});
    return Operand{*reg, 0, count};
}

std::optional<MaterialProgram::Operand> MaterialProgram::Compiler::inputOperand(
    const MaterialNode& node, const char* input, const glm::vec4& fallback, uint8_t count) {
    if (node.inputConnections.count(Token(input)))
        if (auto c = connection(node, input)) return c;
    glm::vec4 v = fallback;
    if (auto it = node.parameters.find(Token(input)); it != node.parameters.end())
        if (auto n = numeric(it->second))
            // A float for a wider input is spread (MaterialX's FA forms): over all four for a
            // color4/vector4, over xyz otherwise (w unused).
            v = n->second == 1 && count > 1
                    ? (count == 4 ? glm::vec4(n->first.x) : glm::vec4(glm::vec3(n->first.x), fallback.w))
                    : n->first;
    return constant(v, count);
}

std::optional<int16_t> MaterialProgram::Compiler::compileMaterialXNode(const MaterialNode& node,
                                                                       bool* handled) {
    const std::string& id = node.identifier.str();
    *handled = true;
    if (startsWith(id, "ND_image_")) return compileImage(node, false);
    if (startsWith(id, "ND_tiledimage_")) return compileImage(node, true);
    if (startsWith(id, "ND_normalmap")) return compileNormalMap(node);
    if (id == "ND_place2d_vector2") return compilePlace2d(node);
    int components = program::materialxComponents(id);
    if (id == "ND_texcoord_vector2" || id == "ND_texcoord_vector3") {
        // MaterialX texcoord index 0 is the default UV set, "st" in USD.
        int index = 0;
        if (auto it = node.parameters.find(Token("index")); it != node.parameters.end())
            index = static_cast<int>(getFloat(it->second).value_or(0.0f));
        return compileGeomprop(node, Token(index > 0 ? "st" + std::to_string(index) : "st"),
                               components);
    }
    if (auto reg = compileMaterialXArithmetic(node, components, handled); *handled) return reg;
    *handled = true;
    if (startsWith(id, "ND_geompropvalue_")) {
        std::string name;
        if (auto it = node.parameters.find(Token("geomprop")); it != node.parameters.end())
            name = getString(it->second).value_or("");
        if (name.empty()) note(node, "no geomprop; using the default");
        return compileGeomprop(node, Token(name), components);
    }
    *handled = false;
    return std::nullopt;
}

std::optional<int16_t> MaterialProgram::Compiler::compileMaterialXArithmetic(const MaterialNode& node,
                                                                             int components,
                                                                             bool* handled) {
    // MaterialX 1.38 standard library (stdlib_defs.mtlx): the node's inputs and defaults. The
    // "FA" variants take a float second input, which the ops broadcast.
    const std::string& id = node.identifier.str();
    *handled = false;
    if (id.size() < 4 || !startsWith(id, "ND_")) return std::nullopt;  // not a MaterialX node id
    const std::string op = id.substr(3, id.find('_', 3) - 3);  // ND_<op>_<type>
    *handled = true;
    const auto n = uint8_t(components);
    auto in = [&](const char* name, float fallback) {
        return inputOperand(node, name, glm::vec4(fallback), n);
    };
    auto result = [](const std::optional<Operand>& o) -> std::optional<int16_t> {
        if (!o) return std::nullopt;
        return o->reg;
    };
    auto scalar = [&](float v) { return constant(glm::vec4(v), n); };
    if (op == "constant") return result(in("value", 0.0f));
    if (op == "extract" || startsWith(op, "separate")) {
        // The input's register; the consumer's connection() picks the component (MaterialX
        // ND_extract_<type> index, ND_separate<N>_<type> outputs).
        auto x = in("in", 0.0f);
        if (!x) return std::nullopt;
        if (x->offset == 0) return x->reg;
        auto one = scalar(1.0f);  // a component of another register: copied to a register of its own
        if (!one) return std::nullopt;
        return result(mulAdd(*x, *one, std::nullopt, n));
    }
    if (op == "dot") return result(in("in", 0.0f));  // MaterialX "dot": a pass-through
    if (op == "multiply") {  // in1 * in2
        auto a = in("in1", 0.0f), b = in("in2", 1.0f);
        if (!a || !b) return std::nullopt;
        return result(mulAdd(*a, *b, std::nullopt, n));
    }
    if (op == "add" || op == "subtract") {  // in1 + in2, in1 - in2
        auto a = in("in1", 0.0f), b = in("in2", 0.0f), sign = scalar(op == "add" ? 1.0f : -1.0f);
        if (!a || !b || !sign) return std::nullopt;
        return result(mulAdd(*b, *sign, a, n));
    }
    if (op == "invert") {  // amount - in
        auto x = in("in", 0.0f), amount = in("amount", 1.0f), minus = scalar(-1.0f);
        if (!x || !amount || !minus) return std::nullopt;
        return result(mulAdd(*x, *minus, amount, n));
    }
    const std::map<std::string, std::pair<BinaryFn, float>> binaries = {
        {"divide", {BinaryFn::Divide, 1.0f}}, {"power", {BinaryFn::Power, 1.0f}},
        {"min", {BinaryFn::Min, 0.0f}}, {"max", {BinaryFn::Max, 0.0f}}};
    if (auto it = binaries.find(op); it != binaries.end()) {  // fn(in1, in2)
        auto a = in("in1", 0.0f), b = in("in2", it->second.second);
        if (!a || !b) return std::nullopt;
        return result(binary(it->second.first, *a, *b, n));
    }
    if (op == "clamp") {  // min(max(in, low), high)
        auto x = in("in", 0.0f), low = in("low", 0.0f), high = in("high", 1.0f);
        if (!x || !low || !high) return std::nullopt;
        auto lowered = binary(BinaryFn::Max, *x, *low, n);
        if (!lowered) return std::nullopt;
        return result(binary(BinaryFn::Min, *lowered, *high, n));
    }
    if (op == "mix") {  // bg + (fg - bg) * mix
        auto fg = in("fg", 0.0f), bg = in("bg", 0.0f), minus = scalar(-1.0f);
        // ND_mix_<type> blends by a float; ND_mix_<type>_<type> per component.
        const bool perComponent = std::count(id.begin(), id.end(), '_') >= 3;
        auto t = inputOperand(node, "mix", glm::vec4(0.0f), perComponent ? n : uint8_t(1));
        if (!fg || !bg || !minus || !t) return std::nullopt;
        auto diff = mulAdd(*bg, *minus, fg, n);
        if (!diff) return std::nullopt;
        return result(mulAdd(*diff, *t, bg, n));
    }
    *handled = false;
    return std::nullopt;
}

std::optional<int16_t> MaterialProgram::Compiler::compileGeomprop(const MaterialNode& node,
                                                                  const Token& name,
                                                                  int components) {
    glm::vec4 fallback(0.0f);
    if (auto it = node.parameters.find(Token("default")); it != node.parameters.end())
        if (auto n = numeric(it->second)) fallback = n->first;
    if (name.empty()) return newRegister(fallback, true);
    return primvarRegister(name, components, fallback);
}

std::optional<int16_t> MaterialProgram::Compiler::compileImage(const MaterialNode& node,
                                                               bool tiled) {
    UvTexture tex = resolveMaterialXImage(node, _cache, _notes);
    if (!tex.texture) return newRegister(tex.fallback, true);
    std::optional<Operand> st = texcoordOperand(node);
    if (!st) return std::nullopt;
    if (tiled) {
        auto reg = transformRegister(tiledImageTransform(node), *st);
        if (!reg) return std::nullopt;
        st = Operand{*reg, 0, 2};
    }
    return sampleTexture(tex, *st);
}

std::optional<MaterialProgram::Operand> MaterialProgram::Compiler::texcoordOperand(
    const MaterialNode& node) {
    std::optional<Operand> st;
    if (node.inputConnections.count(Token("texcoord"))) st = connection(node, "texcoord");
    if (!st && node.parameters.count(Token("texcoord"))) {
        st = vec2Input(node, "texcoord", glm::vec2(0.0f));
    } else if (!st) {  // MaterialX texcoord default: the UV0 geometric property ("st")
        auto reg = primvarRegister(Token("st"), 2, glm::vec4(0.0f));
        if (reg) st = Operand{*reg, 0, 2};
    }
    return st;
}

std::optional<int16_t> MaterialProgram::Compiler::compilePlace2d(const MaterialNode& node) {
    for (const char* input : {"pivot", "scale", "rotate", "offset", "operationorder"})
        if (node.inputConnections.count(Token(input)))
            note(node, std::string("a connected '") + input +
                           "' is not supported; using its authored value or default");
    std::optional<Operand> st = texcoordOperand(node);
    if (!st) return std::nullopt;
    return transformRegister(place2dTransform(node), *st);
}

std::optional<int16_t> MaterialProgram::Compiler::compileNormalMap(const MaterialNode& node) {
    std::optional<Operand> in = inputOperand(node, "in", glm::vec4(0.5f, 0.5f, 1.0f, 0.0f), 3);
    if (!in) return std::nullopt;
    glm::vec2 s(1.0f);
    if (auto it = node.parameters.find(Token("scale")); it != node.parameters.end())
        if (auto n = numeric(it->second))
            s = n->second == 1 ? glm::vec2(n->first.x) : glm::vec2(n->first);
    if (!std::isfinite(s.x) || !std::isfinite(s.y)) s = glm::vec2(1.0f);
    if (node.inputConnections.count(Token("scale")))
        note(node, "a connected 'scale' is not supported; using its value");
    if (auto it = node.parameters.find(Token("space")); it != node.parameters.end())
        if (getString(it->second).value_or("tangent") != "tangent")
            note(node, "only tangent-space normal maps are supported; read as tangent space");
    // MaterialX ND_normalmap: tangent-space n = (2 in - 1) with x and y times scale.
    auto mul = constant(glm::vec4(2.0f * s.x, 2.0f * s.y, 2.0f, 0.0f), 3);
    auto add = constant(glm::vec4(-s.x, -s.y, -1.0f, 0.0f), 3);
    if (!mul || !add) return std::nullopt;
    auto out = mulAdd(*in, *mul, add, 3);
    if (!out) return std::nullopt;
    return out->reg;
}

void MaterialProgram::Compiler::compileStandardSurface(const MaterialNode& surface) {
    StandardSurfaceParams s = StandardSurfaceParams::defaults(surface.identifier);
    std::set<std::string> names;
    for (const auto& [k, v] : surface.parameters)
        if (!startsWith(k.str(), "colorSpace:")) names.insert(k.str());
    for (const auto& [k, v] : surface.inputConnections) names.insert(k.str());
    std::map<std::string, Operand> varying;
    std::optional<Operand> constantNormal;  // a normal map folded to one value
    std::string unused;
    for (const std::string& name : names) {
        if (name != "normal" && !StandardSurfaceParams().set(name, glm::vec4(0.0f), 1)) {
            unused += (unused.empty() ? "" : ", ") + name;
            continue;
        }
        // The authored value first: it stays when a connection is unusable.
        if (auto it = surface.parameters.find(Token(name)); it != surface.parameters.end())
            if (auto n = numeric(it->second)) s.set(name, n->first, n->second);
        if (!surface.inputConnections.count(Token(name))) continue;
        if (auto c = connection(surface, name.c_str())) {
            if (!isConstant(*c))
                varying[name] = *c;
            else if (name == "normal")
                constantNormal = c;
            else
                s.set(name, constantValue(*c), c->count);
        }
    }
    if (!unused.empty()) note(surface, "inputs not used: " + unused);
    for (auto [name, colour] :
         {std::pair{"specular_color", s.specularColor}, std::pair{"sheen_color", s.sheenColor}})
        if (colour.x != colour.y || colour.y != colour.z)
            note(surface, std::string(name) + " only scales by its luminance (hue ignored)");

    PreviewSurfaceParams& base = _prog._base;
    base = mapStandardSurface(s);
    auto bind = [&](Slot slot, const std::optional<Operand>& o) {
        if (!o) return;
        if (isConstant(*o))
            program::setSlot(base, slot, constantValue(*o), o->count);
        else
            _prog._bindings.push_back({slot, *o});
    };
    auto take = [&](const char* name) -> std::optional<Operand> {
        auto it = varying.find(name);
        if (it == varying.end()) return std::nullopt;
        Operand o = it->second;
        varying.erase(it);
        return o;
    };
    // A varying colour or weight: the product with its (constant or varying) partner.
    auto product = [&](Slot slot, const char* colourName, glm::vec3 colour, const char* weightName,
                       float weight) {
        std::optional<Operand> c = take(colourName), w = take(weightName);
        if (!c && !w) return;
        if (!c) c = constant(glm::vec4(colour, 0.0f), 3);
        if (!w) w = constant(glm::vec4(weight), 1);
        if (c && w) bind(slot, mulAdd(*c, *w, std::nullopt, 3));
    };
    auto scaled = [&](Slot slot, const char* name, float k) {
        if (auto o = take(name))
            if (auto kc = constant(glm::vec4(k), 1)) bind(slot, mulAdd(*o, *kc, std::nullopt, 1));
    };
    // The same mapping as mapStandardSurface(), per shading point (standardSurface.cpp cites it).
    product(Slot::DiffuseColor, "base_color", s.baseColor, "base", s.base);
    product(Slot::EmissiveColor, "emission_color", s.emissionColor, "emission", s.emission);
    scaled(Slot::Specular, "specular", disneySpecularPerWeight(s));
    scaled(Slot::Sheen, "sheen", disneySheenPerWeight(s));
    for (auto [name, slot] :
         {std::pair{"metalness", Slot::Metallic}, std::pair{"specular_roughness", Slot::Roughness},
          std::pair{"specular_anisotropy", Slot::Anisotropic},
          std::pair{"transmission", Slot::SpecTrans}, std::pair{"subsurface", Slot::Subsurface},
          std::pair{"coat", Slot::Clearcoat},
          std::pair{"coat_roughness", Slot::ClearcoatRoughness}})
        bind(slot, take(name));
    if (auto o = take("opacity"))
        if (auto third = constant(glm::vec4(glm::vec3(1.0f / 3.0f), 0.0f), 3))
            bind(Slot::Opacity, dot(*o, *third));
    bind(Slot::Normal, constantNormal);
    if (auto o = take("normal")) {
        bind(Slot::Normal, o);
        base.normalVaries = true;
    }
    for (const auto& [name, o] : varying)
        note(surface, "input '" + name +
                          "' varies per shading point, which is not supported; using its "
                          "authored value or default");
}

}  // namespace principled::shading
