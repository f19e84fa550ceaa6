// SPDX-License-Identifier: Apache-2.0
// Converts authored USD values into the renderer-facing hd::Value types.
#pragma once

#include "delegate/hd/value.h"

namespace principled::usd {
class Value;
}

namespace principled::adapter {

/// float/double/half scalars -> float, ints -> int, bool -> bool, 2/3/4-tuples -> vec2/3/4,
/// matrix4d -> dmat4 (column-vector convention), token -> Token, string/asset -> std::string
/// (assets: resolved path, else authored), numeric arrays -> vector<int|float|vec2|vec3|vec4>,
/// token/string arrays -> vector<Token>. None or unsupported shapes -> empty Value.
hd::Value toHdValue(const usd::Value& v);

}  // namespace principled::adapter
