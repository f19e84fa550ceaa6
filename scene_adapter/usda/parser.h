// SPDX-License-Identifier: Apache-2.0
// USDA 1.0 text -> Layer. Recursive descent over the Lexer's tokens; every spec and value keeps
// its file:line:col. Errors throw ParseError "FILE:LINE:COL: expected X, found Y".
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "scene_adapter/usda/layer.h"

namespace principled::usd {

/// Deepest nesting of prims, variants, dictionaries, arrays and tuples the parser accepts.
inline constexpr int kMaxNestingDepth = 128;

/// Parses `text` (display name `file`, used in every location). Relative asset paths are
/// resolved against `anchorDir`. Throws ParseError on a syntax error and Error on binary input.
std::unique_ptr<Layer> parseLayer(std::string_view text, const std::string& file,
                                  const std::string& anchorDir);

/// Reads and parses a file (anchor: its directory).
std::unique_ptr<Layer> parseLayerFile(const std::string& file);

}  // namespace principled::usd
