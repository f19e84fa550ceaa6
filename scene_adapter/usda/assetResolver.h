// SPDX-License-Identifier: Apache-2.0
// Asset paths and layer files: resolve `@relative/path@` against the directory of the layer that
// authored it, read files, and refuse binary crate (usdc) and usdz archives.
#pragma once

#include <string>
#include <string_view>

namespace principled::usd {

/// The absolute, lexically normal path of `authored` anchored at `anchorDir`, or "" when no
/// such file exists. Paths with a "<UDIM>" tile pattern resolve without the existence check.
std::string resolveAsset(std::string_view authored, std::string_view anchorDir);
/// The authored path made absolute against anchorDir (lexically normal), existing or not; ""
/// for an empty path.
std::string anchorAsset(std::string_view authored, std::string_view anchorDir);

/// The directory containing `file` as an absolute path ("" -> the current directory).
std::string directoryOf(std::string_view file);

/// The current working directory.
std::string currentDirectory();

/// Reads a layer file. Throws Error naming the file when it cannot be read, or when it is a
/// binary crate file ("PXR-USDC") or a zip (.usdz) archive: only the text format is supported.
std::string readLayerText(const std::string& file);

/// Throws Error if `text` starts with the usdc or zip magic (used for in-memory text too).
void refuseBinary(std::string_view text, const std::string& file);

}  // namespace principled::usd
