// SPDX-License-Identifier: Apache-2.0
// Shading normals that a path tracer can use: interpolated and mapped normals tilt away from
// the geometric normal, and at grazing views their mirror direction can point into the surface
// (black rims, light leaks, too-bright retro-reflection). The rule that keeps them usable is
// the one Cycles applies to every closure normal, so both renderers shade such views alike.
#pragma once

#include <glm/glm.hpp>

namespace principled::embree {

/// The normal closest to n, in the plane of n and ng, whose mirror direction of wo stays above
/// the geometric surface: reflect(wo, n) . ng >= min(0.9 (wo . ng), 0.01). n itself when it
/// already does. ng, wo and n are unit vectors with wo . ng > 0 (ng faces the viewer).
/// The rule and its threshold: Cycles (Blender 3.4), kernel/closure/bsdf_util.h,
/// ensure_valid_reflection; the closed form below is derived in shadingNormal.cpp.
glm::vec3 bendToValidReflection(const glm::vec3& ng, const glm::vec3& wo, const glm::vec3& n);
inline glm::vec3 validReflectionNormal(const glm::vec3& ng, const glm::vec3& wo, const glm::vec3& n) {
    if (n == ng) return n;  // flat shading: the mirror direction is above the surface
    return bendToValidReflection(ng, wo, n);
}

}  // namespace principled::embree
