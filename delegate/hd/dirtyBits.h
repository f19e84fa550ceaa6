// SPDX-License-Identifier: Apache-2.0
// Dirty bits: what changed on a prim since its last sync. Values follow Hydra's HdChangeTracker
// so tests and logs read like Hydra's (hydra.md section 2.4).
#pragma once

#include <cstdint>

namespace principled::hd {

using DirtyBits = uint32_t;

namespace RprimDirty {
inline constexpr DirtyBits Clean = 0;
inline constexpr DirtyBits InitRepr = 1u << 0;
inline constexpr DirtyBits Varying = 1u << 1;
inline constexpr DirtyBits PrimId = 1u << 2;
inline constexpr DirtyBits Extent = 1u << 3;
inline constexpr DirtyBits DisplayStyle = 1u << 4;  ///< refine level
inline constexpr DirtyBits Points = 1u << 5;
inline constexpr DirtyBits Primvar = 1u << 6;
inline constexpr DirtyBits MaterialId = 1u << 7;
inline constexpr DirtyBits Topology = 1u << 8;
inline constexpr DirtyBits Transform = 1u << 9;
inline constexpr DirtyBits Visibility = 1u << 10;
inline constexpr DirtyBits Normals = 1u << 11;
inline constexpr DirtyBits DoubleSided = 1u << 12;
inline constexpr DirtyBits CullStyle = 1u << 13;
inline constexpr DirtyBits SubdivTags = 1u << 14;
inline constexpr DirtyBits Widths = 1u << 15;
inline constexpr DirtyBits Instancer = 1u << 16;
inline constexpr DirtyBits InstanceIndex = 1u << 17;
inline constexpr DirtyBits AllSceneDirtyBits = (1u << 23) - 1;
inline constexpr DirtyBits AllDirty = ~Varying;
}  // namespace RprimDirty

namespace SprimDirty {
inline constexpr DirtyBits Clean = 0;
inline constexpr DirtyBits Transform = 1u << 0;  ///< camera, light
inline constexpr DirtyBits Params = 1u << 1;     ///< camera, light (material: 1<<2 in Hydra)
inline constexpr DirtyBits MaterialParams = 1u << 2;
inline constexpr DirtyBits Resource = 1u << 3;   ///< material network topology, light texture
inline constexpr DirtyBits Visibility = 1u << 4;
inline constexpr DirtyBits AllDirty = 0xffffffffu;
}  // namespace SprimDirty

namespace BprimDirty {
inline constexpr DirtyBits Clean = 0;
inline constexpr DirtyBits Description = 1u << 0;  ///< render buffer size or format
inline constexpr DirtyBits AllDirty = 0xffffffffu;
}  // namespace BprimDirty

}  // namespace principled::hd
