// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/valueType.h"

#include <array>

namespace principled::usd {

namespace {
using S = ScalarType;
// Sdf value type names (sdf/types.h, SDF_VALUE_TYPES) that the text format can spell.
constexpr std::array kTypes = {
    ValueType{"bool", S::Bool, 1, 0, false},
    ValueType{"uchar", S::UChar, 1, 0, false},
    ValueType{"int", S::Int, 1, 0, false},
    ValueType{"uint", S::UInt, 1, 0, false},
    ValueType{"int64", S::Int64, 1, 0, false},
    ValueType{"uint64", S::UInt64, 1, 0, false},
    ValueType{"half", S::Half, 1, 0, false},
    ValueType{"float", S::Float, 1, 0, false},
    ValueType{"double", S::Double, 1, 0, false},
    ValueType{"timecode", S::TimeCode, 1, 0, false},
    ValueType{"string", S::String, 1, 0, false},
    ValueType{"token", S::Token, 1, 0, false},
    ValueType{"asset", S::Asset, 1, 0, false},
    ValueType{"opaque", S::Opaque, 1, 0, false},
    ValueType{"group", S::Opaque, 1, 0, false},  // valueless, as opaque (SdfOpaqueValue)
    ValueType{"pathExpression", S::PathExpression, 1, 0, false},
    ValueType{"int2", S::Int, 2, 0, false},
    ValueType{"int3", S::Int, 3, 0, false},
    ValueType{"int4", S::Int, 4, 0, false},
    ValueType{"half2", S::Half, 2, 0, false},
    ValueType{"half3", S::Half, 3, 0, false},
    ValueType{"half4", S::Half, 4, 0, false},
    ValueType{"float2", S::Float, 2, 0, false},
    ValueType{"float3", S::Float, 3, 0, false},
    ValueType{"float4", S::Float, 4, 0, false},
    ValueType{"double2", S::Double, 2, 0, false},
    ValueType{"double3", S::Double, 3, 0, false},
    ValueType{"double4", S::Double, 4, 0, false},
    ValueType{"point3h", S::Half, 3, 0, false},
    ValueType{"point3f", S::Float, 3, 0, false},
    ValueType{"point3d", S::Double, 3, 0, false},
    ValueType{"normal3h", S::Half, 3, 0, false},
    ValueType{"normal3f", S::Float, 3, 0, false},
    ValueType{"normal3d", S::Double, 3, 0, false},
    ValueType{"vector3h", S::Half, 3, 0, false},
    ValueType{"vector3f", S::Float, 3, 0, false},
    ValueType{"vector3d", S::Double, 3, 0, false},
    ValueType{"color3h", S::Half, 3, 0, false},
    ValueType{"color3f", S::Float, 3, 0, false},
    ValueType{"color3d", S::Double, 3, 0, false},
    ValueType{"color4h", S::Half, 4, 0, false},
    ValueType{"color4f", S::Float, 4, 0, false},
    ValueType{"color4d", S::Double, 4, 0, false},
    ValueType{"texCoord2h", S::Half, 2, 0, false},
    ValueType{"texCoord2f", S::Float, 2, 0, false},
    ValueType{"texCoord2d", S::Double, 2, 0, false},
    ValueType{"texCoord3h", S::Half, 3, 0, false},
    ValueType{"texCoord3f", S::Float, 3, 0, false},
    ValueType{"texCoord3d", S::Double, 3, 0, false},
    ValueType{"quath", S::Half, 4, 0, true},
    ValueType{"quatf", S::Float, 4, 0, true},
    ValueType{"quatd", S::Double, 4, 0, true},
    ValueType{"matrix2d", S::Double, 4, 2, false},
    ValueType{"matrix3d", S::Double, 9, 3, false},
    ValueType{"matrix4d", S::Double, 16, 4, false},
    ValueType{"frame4d", S::Double, 16, 4, false},
};

// Legacy names Sdf still reads ("Backwards compatibility" in sdf/parserHelpers.cpp) -> the
// type they stand for. As there, NormalFloat/Normal read as vectors and VectorFloat/Vector as
// normals (the roles are swapped in OpenUSD's table; the values are the same three numbers).
struct Alias {
    std::string_view legacy, name;
};
constexpr std::array kAliases = {
    Alias{"Vec2i", "int2"},           Alias{"Vec2h", "half2"},
    Alias{"Vec2f", "float2"},         Alias{"Vec2d", "double2"},
    Alias{"Vec3i", "int3"},           Alias{"Vec3h", "half3"},
    Alias{"Vec3f", "float3"},         Alias{"Vec3d", "double3"},
    Alias{"Vec4i", "int4"},           Alias{"Vec4h", "half4"},
    Alias{"Vec4f", "float4"},         Alias{"Vec4d", "double4"},
    Alias{"PointFloat", "point3f"},   Alias{"Point", "point3d"},
    Alias{"NormalFloat", "vector3f"}, Alias{"Normal", "vector3d"},
    Alias{"VectorFloat", "normal3f"}, Alias{"Vector", "normal3d"},
    Alias{"ColorFloat", "color3f"},   Alias{"Color", "color3d"},
    Alias{"Quath", "quath"},          Alias{"Quatf", "quatf"},
    Alias{"Quatd", "quatd"},          Alias{"Matrix2d", "matrix2d"},
    Alias{"Matrix3d", "matrix3d"},    Alias{"Matrix4d", "matrix4d"},
    Alias{"Frame", "frame4d"},        Alias{"Transform", "matrix4d"},
    Alias{"PointIndex", "int"},       Alias{"EdgeIndex", "int"},
    Alias{"FaceIndex", "int"},        Alias{"Schema", "token"},
};

const ValueType* findCanonical(std::string_view name) {
    for (const ValueType& t : kTypes)
        if (t.name == name) return &t;
    return nullptr;
}
}  // namespace

const ValueType* findValueType(std::string_view name) {
    if (const ValueType* t = findCanonical(name)) return t;
    for (const Alias& a : kAliases)
        if (a.legacy == name) return findCanonical(a.name);
    return nullptr;
}

}  // namespace principled::usd
