// SPDX-License-Identifier: Apache-2.0
// Implicit UsdGeom shapes (Cube, Cylinder, Cone, Capsule, Plane) as polygon meshes, served to the
// render index through the mesh pull API (subdivisionScheme none, face-varying normals: smooth
// on curved parts, flat on caps and cube faces). Sphere is not here: it is ray traced exactly.
//
// Tessellation: kShapeSegments = 72 segments around the axis (5 degrees each), so the
// silhouette of a curved part is off the true surface by at most r (1 - cos(2.5 deg)) =
// 9.5e-4 r, below 0.1% of the radius. Capsule hemispheres use kCapsuleRings = 36 latitude
// steps of 2.5 degrees (profile error r (1 - cos(1.25 deg)) = 2.4e-4 r).
#pragma once

#include <string>
#include <vector>

#include <glm/glm.hpp>

namespace principled::adapter {

inline constexpr int kShapeSegments = 72;
inline constexpr int kCapsuleRings = 36;  ///< latitude steps per hemisphere (pole to equator)

/// USD attribute values of a shape with the schema fallbacks (UsdGeom generatedSchema.usda).
struct ShapeParams {
    double size = 2.0;    ///< Cube edge length
    double radius = 1.0;  ///< Cylinder, Cone, Capsule (fallback 0.5)
    double height = 2.0;  ///< Cylinder, Cone; Capsule (fallback 1): the cylinder part, caps excluded
    double width = 2.0;   ///< Plane: along x (axis Z or Y) or z (axis X)
    double length = 2.0;  ///< Plane: along y (axis Z or X) or z (axis Y)
    char axis = 'Z';      ///< 'X', 'Y' or 'Z' (Plane: its normal)
};

struct ShapeMesh {
    std::vector<glm::vec3> points;
    std::vector<int> faceVertexCounts;
    std::vector<int> faceVertexIndices;
    std::vector<glm::vec3> normals;  ///< face-varying: one per face-vertex index, outward
    glm::vec3 extentMin{0.0f}, extentMax{0.0f};
};

/// The schema fallbacks of a shape type: those above, except Capsule (radius 0.5, height 1).
ShapeParams shapeFallbacks(const std::string& typeName);

/// True for "Cube", "Cylinder", "Cone", "Capsule", "Plane" (UsdGeomPlane, USD 22.11).
bool isImplicitShape(const std::string& typeName);

/// Builds the mesh of the shape; false (with *error) for non-finite or negative sizes.
bool buildImplicitShape(const std::string& typeName, const ShapeParams& params, ShapeMesh* out,
                        std::string* error);

}  // namespace principled::adapter
