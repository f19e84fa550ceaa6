// SPDX-License-Identifier: Apache-2.0
// Helpers for USD scene paths as strings: "/World/Cube", "/World/Cube.points",
// "/Model{geo=quad}/mesh" (a site path inside a variant; used by composition only).
#pragma once

#include <string>
#include <string_view>

namespace principled::usd::path {

/// The parent prim path ("/" for root prims, "" for "/").
std::string parent(std::string_view p);
/// The last prim name ("Cube" for "/World/Cube").
std::string_view name(std::string_view p);
/// p + "/" + child, handling the root "/".
std::string child(std::string_view p, std::string_view childName);
/// Removes variant selections: "/A{v=x}/B" -> "/A/B".
std::string stripVariants(std::string_view p);
/// True when `p` equals `prefix` or lies below it (prim children "/..." or properties ".x").
bool hasPrefix(std::string_view p, std::string_view prefix);
/// Replaces `prefix` of `p` (which must satisfy hasPrefix) with `replacement`.
std::string replacePrefix(std::string_view p, std::string_view prefix,
                          std::string_view replacement);
/// Makes a possibly relative target path ("../X", "Child", ".prop") absolute against the prim
/// path `anchor`; absolute paths are returned unchanged.
std::string makeAbsolute(std::string_view target, std::string_view anchor);
/// Splits "/A/B.prop" into prim path and property name ("" when none).
std::pair<std::string_view, std::string_view> splitProperty(std::string_view p);

}  // namespace principled::usd::path
