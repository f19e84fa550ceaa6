// SPDX-License-Identifier: Apache-2.0
// Well-known tokens: prim types, AOV names and parameter keys shared by adapters and delegates.
#pragma once

#include "delegate/hd/token.h"

namespace principled::hd::tokens {

// Rprim types.
inline const Token& mesh() { static const Token t("mesh"); return t; }
inline const Token& sphere() { static const Token t("sphere"); return t; }
/// UsdGeomPoints' rprim type (Hydra's "points"; the same string as the points attribute).
inline const Token& pointsPrim() { static const Token t("points"); return t; }
inline const Token& basisCurves() { static const Token t("basisCurves"); return t; }
// Sprim types.
inline const Token& camera() { static const Token t("camera"); return t; }
inline const Token& material() { static const Token t("material"); return t; }
inline const Token& distantLight() { static const Token t("distantLight"); return t; }
inline const Token& domeLight() { static const Token t("domeLight"); return t; }
inline const Token& sphereLight() { static const Token t("sphereLight"); return t; }
inline const Token& rectLight() { static const Token t("rectLight"); return t; }
inline const Token& diskLight() { static const Token t("diskLight"); return t; }
inline const Token& cylinderLight() { static const Token t("cylinderLight"); return t; }
inline const Token& portalLight() { static const Token t("portalLight"); return t; }
// Bprim types.
inline const Token& renderBuffer() { static const Token t("renderBuffer"); return t; }

// Geometry keys for SceneDelegate::get().
inline const Token& points() { static const Token t("points"); return t; }
inline const Token& normals() { static const Token t("normals"); return t; }
inline const Token& radius() { static const Token t("radius"); return t; }
inline const Token& widths() { static const Token t("widths"); return t; }
inline const Token& curveVertexCounts() { static const Token t("curveVertexCounts"); return t; }
inline const Token& displayColor() { static const Token t("displayColor"); return t; }

// Instancer keys for SceneDelegate::get(instancerId, ...): per-instance arrays, Hydra's names.
inline const Token& instanceTranslations() { static const Token t("instanceTranslations"); return t; }  ///< vec3[]
inline const Token& instanceRotations() { static const Token t("instanceRotations"); return t; }  ///< vec4[] (real, i, j, k)
inline const Token& instanceScales() { static const Token t("instanceScales"); return t; }  ///< vec3[]
inline const Token& instanceTransforms() { static const Token t("instanceTransforms"); return t; }  ///< dmat4[], applied first

// AOV names.
inline const Token& color() { static const Token t("color"); return t; }
inline const Token& depth() { static const Token t("depth"); return t; }
inline const Token& primId() { static const Token t("primId"); return t; }

}  // namespace principled::hd::tokens
