// SPDX-License-Identifier: Apache-2.0
// Primvars as the stage authors them: their interpolation metadata and their inheritance
// (UsdGeomPrimvarsAPI::FindInheritablePrimvars: a constant primvar authored on a prim reaches
// its descendants that author none of that name).
#pragma once

#include <string>
#include <vector>

#include "delegate/hd/primvar.h"
#include "scene_adapter/usda/stage.h"

namespace principled::adapter {

struct InheritedPrimvar {
    const usd::Prim* owner = nullptr;           ///< the prim that authors it
    const usd::Attribute* attribute = nullptr;  ///< "primvars:NAME"
};

/// "constant", "uniform", ... as an Interpolation; `fallback` for other text.
hd::Interpolation parseInterpolation(const std::string& s, hd::Interpolation fallback);
/// The "interpolation" metadata of an attribute, or `fallback` when it is missing or unknown.
hd::Interpolation attributeInterpolation(const usd::Attribute& a, hd::Interpolation fallback);

/// The constant primvars authored on `from` and its ancestors, nearest first: a nearer primvar
/// of the same name (constant or not) hides farther ones. UsdSkel's primvars and index arrays
/// are left out.
std::vector<InheritedPrimvar> inheritablePrimvars(const usd::Prim* from);

/// The constant primvar `attrName` ("primvars:NAME") that `prim` inherits from its ancestors
/// (attribute null: none, or the nearest ancestor authoring it is not constant).
InheritedPrimvar inheritedPrimvar(const usd::Prim& prim, const std::string& attrName);

/// What `prim` passes down: the inheritable primvars of it and its ancestors with their values
/// at `time`, as text (instances whose keys differ cannot share one prototype).
std::string inheritablePrimvarKey(const usd::Prim& prim, double time);

}  // namespace principled::adapter
