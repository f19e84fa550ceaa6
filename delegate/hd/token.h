// SPDX-License-Identifier: Apache-2.0
// Token: an interned string compared by pointer, for prim types, attribute and AOV names.
#pragma once

#include <functional>
#include <string>
#include <string_view>

namespace principled::hd {

/// An immutable interned string. Equal text gives the same pointer, so comparison and hashing
/// are O(1). Interning is thread-safe; tokens live until the process ends.
class Token {
public:
    Token();  ///< The empty token.
    explicit Token(std::string_view text);
    Token(const char* text) : Token(std::string_view(text)) {}  // NOLINT: literals read naturally

    const std::string& str() const { return *_text; }
    const char* c_str() const { return _text->c_str(); }
    bool empty() const { return _text->empty(); }

    bool operator==(const Token& o) const { return _text == o._text; }
    bool operator!=(const Token& o) const { return _text != o._text; }
    bool operator<(const Token& o) const { return *_text < *o._text; }
    size_t hash() const { return std::hash<const void*>()(_text); }

private:
    const std::string* _text;
};

}  // namespace principled::hd

template <>
struct std::hash<principled::hd::Token> {
    size_t operator()(const principled::hd::Token& t) const { return t.hash(); }
};
