// SPDX-License-Identifier: Apache-2.0
// MaterialProgram::Compiler: turns a material network into a MaterialProgram, node by node. Its
// UsdPreviewSurface part is in materialProgram.cpp, its MaterialX part in materialxNodes.cpp.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "delegate/shading/materialProgram.h"

namespace principled::shading {

namespace program {

/// An authored value as vec4 plus its component count; nullopt for non-numeric values.
std::optional<std::pair<glm::vec4, int>> numeric(const hd::Value& v);

/// Writes v (`count` meaningful components; a scalar feeding a colour is splatted) into the
/// input `slot`. A non-finite scalar keeps the current value.
void setSlot(PreviewSurfaceParams& p, MaterialProgram::Slot slot, const glm::vec4& v, int count);

/// Components of the output of MaterialX node `id` (ND_image_color3 -> 3, ND_image_float -> 1,
/// ND_normalmap -> 3); 4 when the type suffix is unknown (materialxNodes.cpp).
int materialxComponents(const std::string& id);

}  // namespace program

// Builds a program node by node; each node is compiled once into one register.
class MaterialProgram::Compiler {
  public:
    Compiler(const hd::MaterialNetwork& net, TextureCache& cache, std::vector<std::string>* notes,
             MaterialProgram& prog)
        : _net(net), _cache(cache), _notes(notes), _prog(prog) {}

    /// UsdPreviewSurface (and ND_UsdPreviewSurface_surfaceshader).
    void compileSurface(const hd::MaterialNode& surface);
    /// Autodesk Standard Surface (ND_standard_surface_surfaceshader), materialxNodes.cpp.
    void compileStandardSurface(const hd::MaterialNode& surface);

  private:
    struct RegInfo {
        bool constant = true;
        hd::Token root;            ///< primvar the value derives from linearly (st chains)
        glm::mat2 jacobian{1.0f};  ///< d value.xy / d root
    };

    std::optional<int16_t> newRegister(const glm::vec4& init, bool constant);
    bool isConstant(const Operand& o) const { return _info[o.reg].constant; }
    glm::vec4 constantValue(const Operand& o) const {
        return MaterialProgram::read(_prog._initial.data(), o);
    }
    /// "file:line:col: /path: text" (the location when the scene gave one).
    void note(const hd::MaterialNode& node, const std::string& text);

    /// The operand an input is connected to, or nullopt (unconnected or unusable).
    std::optional<Operand> connection(const hd::MaterialNode& consumer, const char* input);
    /// An operand for a vec2 input: its connection, else a constant of its authored value.
    std::optional<Operand> vec2Input(const hd::MaterialNode& node, const char* input,
                                     glm::vec2 fallback);
    std::optional<int16_t> compileNode(const hd::Path& path);
    std::optional<int16_t> compileTexture(const hd::MaterialNode& node);
    /// One lookup per shading point of `tex` at st (folded when st is constant).
    std::optional<int16_t> sampleTexture(const UvTexture& tex, const Operand& st);
    std::optional<int16_t> compilePrimvarReader(const hd::MaterialNode& node, int components);
    /// A register holding primvar `name` (components, fallback) at each shading point.
    std::optional<int16_t> primvarRegister(const hd::Token& name, int components,
                                           const glm::vec4& fallback);
    std::optional<int16_t> compileTransform(const hd::MaterialNode& node);
    /// t applied to `in` (folded when constant; tracks the st footprint chain).
    std::optional<int16_t> transformRegister(const Transform2d& t, const Operand& in);

    // Arithmetic used to lower MaterialX nodes; all fold when their operands are constant.
    std::optional<Operand> constant(const glm::vec4& v, uint8_t count);
    /// a * b + c per component (c absent: 0); `count` components are meaningful.
    std::optional<Operand> mulAdd(const Operand& a, const Operand& b,
                                  const std::optional<Operand>& c, uint8_t count);
    /// dot(a, b) as a scalar.
    std::optional<Operand> dot(const Operand& a, const Operand& b);
    /// fn(a, b) componentwise (folded when both are constant).
    std::optional<Operand> binary(BinaryFn fn, const Operand& a, const Operand& b, uint8_t count);

    // MaterialX nodes (materialxNodes.cpp).
    std::optional<int16_t> compileMaterialXNode(const hd::MaterialNode& node, bool* handled);
    /// MaterialX constant, dot (pass-through), add, subtract, multiply, mix and invert nodes of
    /// any numeric type, on the MulAdd op; std::nullopt with *handled false for other ids.
    std::optional<int16_t> compileMaterialXArithmetic(const hd::MaterialNode& node, int components,
                                                      bool* handled);
    std::optional<int16_t> compileImage(const hd::MaterialNode& node, bool tiled);
    std::optional<int16_t> compileGeomprop(const hd::MaterialNode& node, const hd::Token& name,
                                           int components);
    std::optional<int16_t> compileNormalMap(const hd::MaterialNode& node);
    std::optional<int16_t> compilePlace2d(const hd::MaterialNode& node);
    /// A MaterialX `texcoord` input: its connection, its authored value, else the "st" primvar
    /// (MaterialX's default UV0 geometric property).
    std::optional<Operand> texcoordOperand(const hd::MaterialNode& node);
    /// An input's operand: its connection, else a constant of its authored value or `fallback`.
    std::optional<Operand> inputOperand(const hd::MaterialNode& node, const char* input,
                                        const glm::vec4& fallback, uint8_t count);

    const hd::MaterialNetwork& _net;
    TextureCache& _cache;
    std::vector<std::string>* _notes;
    MaterialProgram& _prog;
    std::vector<RegInfo> _info;
    std::map<hd::Path, std::optional<int16_t>> _compiled;
    std::set<hd::Path> _inProgress;
    bool _overflowNoted = false;
};

}  // namespace principled::shading
