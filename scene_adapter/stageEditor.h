// SPDX-License-Identifier: Apache-2.0
// StageEditor: the edits a host makes to an open stage (a DCC pushing its changes), checked,
// applied to the composed stage as session-layer opinions (usd::StageEdit), then handed to the
// UsdSceneDelegate, which marks exactly the dirty bits each implies (usdSceneDelegateEdits.cpp)
// so the next RenderIndex::sync() re-reads only what changed.
//
// Every edit is all-or-nothing: a bad one throws EditError naming the prim path and what was
// expected, and leaves the stage and the index untouched.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace principled::usd {
class Prim;
class Stage;
}  // namespace principled::usd
namespace principled::hd {
class RenderIndex;
}

namespace principled::adapter {

class UsdSceneDelegate;

class EditError : public std::runtime_error {
  public:
    enum class Code { NotFound, BadValue, Unsupported };
    EditError(Code code, const std::string& message) : std::runtime_error(message), code(code) {}
    Code code;
};

/// A value from a host: numbers (a scalar, a tuple, a matrix in USD row order, or an array's
/// elements flattened) or text (a token, string or asset; several for token[]/string[]).
struct EditValue {
    std::vector<double> numbers;
    std::vector<std::string> texts;
    bool isText = false;

    static EditValue of(std::vector<double> n) {
        EditValue v;
        v.numbers = std::move(n);
        return v;
    }
    static EditValue text(std::string s) {
        EditValue v;
        v.texts.push_back(std::move(s));
        v.isText = true;
        return v;
    }
};

class StageEditor {
  public:
    /// All three must outlive the editor; the delegate must serve `stage` into `index`.
    StageEditor(usd::Stage& stage, UsdSceneDelegate& delegate, hd::RenderIndex& index);

    /// Sets attribute `name` of the prim at `primPath` (its value at every time; time samples
    /// authored in the layers stay there but no longer win). The attribute's authored type
    /// decides how the value is read; a new attribute takes `typeName` ("point3f[]",
    /// "color3f", "token"), or the schema type of a well-known name (points, inputs:color...).
    void setAttribute(const std::string& primPath, const std::string& name, const EditValue& value,
                      const std::string& typeName = "");
    /// Replaces the prim's local transform (16 numbers in USD order, translation in 12..14):
    /// authors xformOp:transform and makes it the only op.
    void setTransform(const std::string& primPath, const double matrix[16]);
    /// Defines a prim of a supported type (see supportedPrimTypes()); its parent must exist.
    void addPrim(const std::string& primPath, const std::string& typeName);
    /// Removes the prim and its subtree. Prims bound to a removed material use the default
    /// material; an instancer whose prototype is removed keeps drawing its other prototypes.
    void removePrim(const std::string& primPath);
    /// Connects input or output `name` ("outputs:surface", "inputs:diffuseColor") of a shading
    /// prim to `source` ("/Mat/Tex.outputs:rgb"; "" disconnects). The source prim must exist.
    void connect(const std::string& primPath, const std::string& name, const std::string& source,
                 const std::string& typeName = "token");
    /// Sets the targets of relationship `name` (material:binding, prototypes, ...).
    void setRelationship(const std::string& primPath, const std::string& name,
                         const std::vector<std::string>& targets);
    /// Binds `materialPath` (a Material prim; "" unbinds) to a prim or a GeomSubset.
    void bindMaterial(const std::string& primPath, const std::string& materialPath);

    /// The prim types addPrim accepts.
    static const std::vector<std::string>& supportedPrimTypes();
    /// The type of a well-known attribute of a prim type ("" when unknown).
    static std::string schemaType(const std::string& primType, const std::string& attribute);

  private:
    const usd::Prim* existingPrim(const std::string& primPath, const char* what) const;
    void checkNotInstanceProxy(const std::string& primPath) const;

    usd::Stage& _stage;
    UsdSceneDelegate& _delegate;
    hd::RenderIndex& _index;
};

}  // namespace principled::adapter
