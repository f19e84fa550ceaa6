// SPDX-License-Identifier: Apache-2.0
// The default scene, compiled into the binary from scenes/default.usda at build time.
#pragma once

namespace principled::tools {

/// USDA text of scenes/default.usda.
extern const char* const kDefaultSceneUsda;

}  // namespace principled::tools
