// SPDX-License-Identifier: Apache-2.0
// StageEdit: changes to a composed stage after it was opened, as if authored in a session layer
// (the strongest layer): an edited attribute's value wins at every time (the layers' time
// samples stay as parsed but no longer win, USD's rule for a stronger default), relationships
// get new targets, prims are defined or removed. The layers themselves are never changed.
// Edits must not run while another thread reads the stage (the render index syncs between
// edits). Validation (types, paths) is the caller's job; see adapter::StageEditor.
#pragma once

#include <string>
#include <vector>

#include "scene_adapter/usda/stage.h"

namespace principled::usd {

class StageEdit {
  public:
    explicit StageEdit(Stage& stage) : _stage(stage) {}

    /// The location edits report ("<host edit>").
    static SourceLocation location();

    /// Sets `name` on the prim at `primPath` to `value` at every time, creating the attribute
    /// with `typeName` (without []) and `isArray` when it does not exist. Returns it, nullptr
    /// when there is no such prim.
    const Attribute* setAttribute(const std::string& primPath, const std::string& name,
                                  const std::string& typeName, bool isArray, Value value);
    /// Replaces the connection sources of attribute `name` ("/Mat/Shader.outputs:surface"),
    /// creating it with `typeName` when absent.
    const Attribute* connect(const std::string& primPath, const std::string& name,
                             const std::string& typeName, std::vector<std::string> sources);
    /// Replaces the targets of relationship `name` (created when absent).
    const Relationship* setRelationship(const std::string& primPath, const std::string& name,
                                        std::vector<std::string> targets);
    /// Defines a prim (`def typeName`) at `path`, appended to its parent's children. The parent
    /// must exist and the path must be free; returns nullptr otherwise.
    const Prim* definePrim(const std::string& path, const std::string& typeName);
    /// Removes the prim and its subtree from the namespace (it disappears from prim() and its
    /// parent's children). The objects stay allocated until the stage is destroyed, so
    /// pointers a reader still holds never dangle.
    bool removePrim(const std::string& path);

  private:
    Prim* mutablePrim(const std::string& path);
    void unindex(Prim& prim);

    Stage& _stage;
};

}  // namespace principled::usd
