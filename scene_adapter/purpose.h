// SPDX-License-Identifier: Apache-2.0
// UsdGeomImageable purpose: which prims a final render draws.
#pragma once

#include <string>
#include <vector>

namespace principled::usd {
class Prim;
}

namespace principled::adapter {

/// Whether `prim` is drawn: its purpose is its own authored value, else its nearest ancestor's,
/// else "default" (UsdGeomImageable::ComputePurposeInfo), and it is drawn when that purpose is
/// one of `included` (UsdRenderSettings includedPurposes; by default "default" and "render",
/// so guide and proxy are not). Materials, cameras and lights are never filtered (a material
/// kept under a guide group still shades what binds it).
bool renderPurpose(const usd::Prim& prim, double time,
                   const std::vector<std::string>& included = {"default", "render"});

}  // namespace principled::adapter
