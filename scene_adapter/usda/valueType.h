// SPDX-License-Identifier: Apache-2.0
// The table of USDA attribute value type names (Sdf value types): scalar kind, components per
// element, matrix rows, whether values interpolate over time.
#pragma once

#include <cstdint>
#include <string_view>

namespace principled::usd {

enum class ScalarType : std::uint8_t {
    Bool,
    UChar,
    Int,
    UInt,
    Int64,
    UInt64,
    Half,
    Float,
    Double,
    TimeCode,
    String,
    Token,
    Asset,
    Opaque,  ///< opaque and group: declared, never given a value
    PathExpression,
};

struct ValueType {
    std::string_view name;
    ScalarType scalar;
    int components;  ///< numbers per element (float3 -> 3, matrix4d -> 16)
    int rows;        ///< matrices: rows (written as nested tuples); 0 otherwise
    bool quaternion;

    bool isNumeric() const { return scalar <= ScalarType::TimeCode; }
    bool isInteger() const { return scalar >= ScalarType::UChar && scalar <= ScalarType::UInt64; }
    bool isUnsigned() const {
        return scalar == ScalarType::UChar || scalar == ScalarType::UInt ||
               scalar == ScalarType::UInt64;
    }
    bool isStringLike() const {
        return scalar == ScalarType::String || scalar == ScalarType::Token ||
               scalar == ScalarType::PathExpression;
    }
    /// Floating types interpolate linearly (quaternions by slerp); the rest are held.
    bool interpolates() const {
        return scalar == ScalarType::Half || scalar == ScalarType::Float ||
               scalar == ScalarType::Double || scalar == ScalarType::TimeCode;
    }
};

/// The type named `name` (without []), or nullptr for an unknown name. A legacy alias
/// ("Vec3f", "Color", "Transform", ...) gives the type it stands for (its name is the Sdf one).
const ValueType* findValueType(std::string_view name);

}  // namespace principled::usd
