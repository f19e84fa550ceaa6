// SPDX-License-Identifier: Apache-2.0
// Value: the type-erased value the scene delegate hands to prims (Hydra's VtValue, reduced to
// the types a renderer consumes). Geometry arrays are float; transforms are double.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include <glm/glm.hpp>

#include "delegate/hd/token.h"

namespace principled::hd {

using Value = std::variant<std::monostate, bool, int, float, double, Token, std::string, glm::vec2,
                           glm::vec3, glm::vec4, glm::dmat4, std::vector<int>, std::vector<float>,
                           std::vector<glm::vec2>, std::vector<glm::vec3>, std::vector<glm::vec4>,
                           std::vector<glm::dmat4>, std::vector<Token>>;

inline bool isEmpty(const Value& v) { return std::holds_alternative<std::monostate>(v); }

/// Returns the held T, or nullptr. Numeric scalars are not converted; see getFloat().
template <typename T>
const T* getIf(const Value& v) {
    return std::get_if<T>(&v);
}

/// A scalar as float from bool, int, float or double.
inline std::optional<float> getFloat(const Value& v) {
    if (auto* f = std::get_if<float>(&v)) return *f;
    if (auto* d = std::get_if<double>(&v)) return static_cast<float>(*d);
    if (auto* i = std::get_if<int>(&v)) return static_cast<float>(*i);
    if (auto* b = std::get_if<bool>(&v)) return *b ? 1.0f : 0.0f;
    return std::nullopt;
}

/// A colour or vector as vec3 (a scalar is splatted).
inline std::optional<glm::vec3> getVec3(const Value& v) {
    if (auto* x = std::get_if<glm::vec3>(&v)) return *x;
    if (auto* x = std::get_if<glm::vec4>(&v)) return glm::vec3(*x);
    if (auto f = getFloat(v)) return glm::vec3(*f);
    return std::nullopt;
}

/// A token or string as std::string.
inline std::optional<std::string> getString(const Value& v) {
    if (auto* t = std::get_if<Token>(&v)) return t->str();
    if (auto* s = std::get_if<std::string>(&v)) return *s;
    return std::nullopt;
}

}  // namespace principled::hd
