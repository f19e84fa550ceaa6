// SPDX-License-Identifier: Apache-2.0
// Path: an absolute prim path ("/World/Sphere") or property path ("/World/Mat.inputs:x").
#pragma once

#include <string>
#include <string_view>

#include "delegate/hd/token.h"

namespace principled::hd {

/// A prim or property path. Backed by an interned token, so copies and comparisons are cheap.
class Path {
public:
    Path() = default;
    explicit Path(std::string_view text) : _token(text) {}

    static const Path& absoluteRoot();

    const std::string& str() const { return _token.str(); }
    bool empty() const { return _token.empty(); }
    bool isAbsoluteRoot() const { return str() == "/"; }
    bool isPropertyPath() const;

    /// Last element: "Sphere" for "/World/Sphere", "inputs:x" for "/World/Mat.inputs:x".
    std::string name() const;
    /// "/World" for "/World/Sphere"; the prim for a property path; empty for the root.
    Path parent() const;
    Path appendChild(std::string_view name) const;
    Path appendProperty(std::string_view name) const;
    /// The prim part of a property path (the path itself for a prim path).
    Path primPath() const;
    /// True if this path equals prefix or lies below it.
    bool hasPrefix(const Path& prefix) const;

    bool operator==(const Path& o) const { return _token == o._token; }
    bool operator!=(const Path& o) const { return _token != o._token; }
    bool operator<(const Path& o) const { return str() < o.str(); }
    size_t hash() const { return _token.hash(); }

private:
    Token _token;
};

}  // namespace principled::hd

template <>
struct std::hash<principled::hd::Path> {
    size_t operator()(const principled::hd::Path& p) const { return p.hash(); }
};
