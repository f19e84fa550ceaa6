// SPDX-License-Identifier: Apache-2.0
// UsdGeomImageable purpose: which prims a final render draws.
#pragma once

namespace principled::usd {
class Prim;
}

namespace principled::adapter {

/// Whether `prim` is drawn for the render purpose: its purpose is its own authored value, else
/// its nearest ancestor's, else "default" (UsdGeomImageable::ComputePurposeInfo); "guide" and
/// "proxy" are not drawn. Materials, cameras and lights are never filtered (a material kept
/// under a guide group still shades what binds it).
bool renderPurpose(const usd::Prim& prim, double time);

}  // namespace principled::adapter
