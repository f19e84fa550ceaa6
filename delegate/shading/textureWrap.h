// SPDX-License-Identifier: Apache-2.0
// Texture wrap modes, shared by the texture cache and the resident images it holds.
#pragma once

#include <cstdint>

namespace principled::shading {

/// How lookups outside [0,1] behave (UsdUVTexture wrapS/wrapT, without useMetadata, which is
/// resolved against the file when a program is compiled).
enum class Wrap : uint8_t { Black, Clamp, Repeat, Mirror };

}  // namespace principled::shading
