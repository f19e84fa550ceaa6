// SPDX-License-Identifier: Apache-2.0
// MaterialProgram: a UsdPreviewSurface (or MaterialX Standard Surface) network compiled into a
// flat list of operations over a small register file, evaluated per shading point without
// allocation.
#pragma once

#include <cstdint>
#include <memory>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "delegate/hd/materialNetwork.h"
#include "delegate/shading/previewSurfaceParams.h"
#include "delegate/shading/shadedMaterial.h"
#include "delegate/shading/shadingContext.h"
#include "delegate/shading/transform2d.h"
#include "delegate/shading/uvTexture.h"

namespace principled::shading {

/// A compiled material. Built once per material sync by compile(); afterwards immutable, so
/// evaluate() may run on any number of threads at once.
///
/// Every UsdPreviewSurface input is a constant or the output of a small graph of UsdUVTexture,
/// UsdPrimvarReader_* and UsdTransform2d nodes. Sub-graphs that read no primvar (a texture at a
/// constant st, a transform of a constant) are folded to constants when compiling; a program
/// whose inputs are all constant is evaluated once (isConstant()).
///
/// The program keeps a pointer to the TextureCache it was compiled with: the cache must
/// outlive it.
class MaterialProgram {
  public:
    /// Registers per program (each a vec4); networks needing more are truncated with a note.
    static constexpr int kMaxRegisters = 64;

    /// The default program: UsdPreviewSurface fallbacks.
    MaterialProgram();

    /// Compiles the network's surface shader: UsdPreviewSurface (also as MaterialX
    /// ND_UsdPreviewSurface_surfaceshader) or Autodesk Standard Surface
    /// (ND_standard_surface_surfaceshader, mapped by standardSurface.h), fed by UsdPreviewSurface
    /// or MaterialX texture nodes (docs/materials.md). Unknown nodes, unknown inputs and outputs, cycles,
    /// missing files (once per file) and ignored inputs (displacement, occlusion) are each
    /// described by one line in *notes; the affected input uses its authored value or fallback.
    static MaterialProgram compile(const hd::MaterialNetwork& network, TextureCache& cache,
                                   std::vector<std::string>* notes);

    /// False when the network has no surface shader this renderer reads (none, or MDL/OSL
    /// only): geometry bound to it is shaded as if unbound, with its displayColor (as Storm does).
    bool hasSurface() const { return _hasSurface; }

    /// True when no input depends on the shading point: evaluate() returns a stored result.
    bool isConstant() const { return _ops.empty(); }

    /// The material at one shading point. Thread-safe, no heap allocation; every output is
    /// finite and clamped to its range.
    ShadedMaterial evaluate(const ShadingContext& context) const;

    /// The result when isConstant() (otherwise the mapping of the constant inputs alone).
    const ShadedMaterial& constantResult() const { return _constant; }

    /// False when every shading point is fully present (opacity 1, or a cutout that always
    /// passes): shadow rays may then treat the surface as opaque without evaluating it.
    bool mayBePartlyPresent() const;
    /// Whether the material can emit anywhere: a non-zero constant emission, or a texture or
    /// primvar bound to emissiveColor (its value then varies over the surface).
    bool mayEmit() const;
    /// evaluate(context).presence(), running only the operations the opacity input depends on
    /// (shadow rays through cutouts need nothing else: no normal map, no roughness texture).
    float presence(const ShadingContext& context) const;
    /// Primvar names the program reads (e.g. {"st"}): the mesh must keep them.
    const std::vector<hd::Token>& primvarsRead() const { return _primvarsRead; }

    /// The UsdPreviewSurface inputs the program can drive (for tests and diagnostics).
    enum class Slot : uint8_t {
        DiffuseColor,
        EmissiveColor,
        SpecularColor,
        Normal,
        Metallic,
        Roughness,
        Clearcoat,
        ClearcoatRoughness,
        Opacity,
        Ior,
        Subsurface,
        Specular,
        SpecularTint,
        Anisotropic,
        Sheen,
        SheenTint,
        ClearcoatGloss,
        SpecTrans,
        Count
    };

  private:
    /// A value read from a register: `count` components starting at `offset`.
    struct Operand {
        int16_t reg = -1;
        uint8_t offset = 0;
        uint8_t count = 4;
    };
    struct Op {
        /// MulAdd: in * in2 + in3 per component; Dot: dot(in, in2) in every component.
        enum class Kind : uint8_t { Texture, Primvar, Transform, MulAdd, Dot, Binary } kind;
        int16_t out;    ///< register written
        Operand in;     ///< st (Texture), in (Transform), the first factor (MulAdd, Dot)
        int16_t index;  ///< into _textures, _primvars or _transforms; Binary: the BinaryFn; else -1
        Operand in2{};  ///< the second factor (MulAdd, Dot)
        Operand in3{};  ///< the addend (MulAdd)
    };
    /// Componentwise functions of the Binary op (MaterialX divide, power, min, max); results that
    /// are not finite (x / 0, a negative base to a fractional power) are 0.
    enum class BinaryFn : int16_t { Divide, Power, Min, Max };
    static glm::vec4 applyBinary(BinaryFn fn, const glm::vec4& a, const glm::vec4& b);
    struct TextureOp {
        UvTexture texture;
        hd::Token footprintPrimvar;         ///< the primvar st derives from (empty: constant st)
        glm::mat2 footprintJacobian{1.0f};  ///< d st / d primvar along the graph
    };
    struct PrimvarOp {
        hd::Token name;
        int components = 2;
        glm::vec4 fallback{0.0f};
    };
    struct Binding {
        Slot slot;
        Operand source;
    };

    class Compiler;

    static glm::vec4 read(const glm::vec4* regs, const Operand& o);
    void run(const Op& op, const ShadingContext& context, glm::vec4* regs) const;
    std::vector<uint16_t> opsFeeding(Slot slot) const;
    void findPresenceOps();
    void findNormalMapUv();

    std::vector<glm::vec4> _initial;  ///< register file before the ops run (constants)
    std::vector<Op> _ops;
    std::vector<TextureOp> _textures;
    std::vector<PrimvarOp> _primvars;
    std::vector<Transform2d> _transforms;
    std::vector<Binding> _bindings;
    std::vector<uint16_t> _presenceOps;  ///< indices into _ops that opacity depends on, in order
    std::vector<hd::Token> _primvarsRead;
    /// Where the normal map's st comes from (ShadedMaterial::normalMapUv points at it: on the
    /// heap, so copies of the program keep the pointers of their results valid).
    std::shared_ptr<const NormalMapUv> _normalMapUv;
    PreviewSurfaceParams _base;  ///< constant inputs; bindings overwrite the rest
    ShadedMaterial _constant;
    const TextureCache* _cache = nullptr;
    bool _hasSurface = true;
};

}  // namespace principled::shading
