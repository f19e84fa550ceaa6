// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/path.h"

#include <vector>

namespace principled::usd::path {

std::string parent(std::string_view p) {
    if (p.size() <= 1) return {};
    auto slash = p.rfind('/');
    if (slash == std::string_view::npos) return {};
    if (slash == 0) return "/";
    return std::string(p.substr(0, slash));
}

std::string_view name(std::string_view p) {
    auto slash = p.rfind('/');
    return slash == std::string_view::npos ? p : p.substr(slash + 1);
}

std::string child(std::string_view p, std::string_view childName) {
    std::string out(p);
    if (out.empty() || out.back() != '/') out += '/';
    out += childName;
    return out;
}

std::string stripVariants(std::string_view p) {
    if (p.find('{') == std::string_view::npos) return std::string(p);
    std::string out;
    out.reserve(p.size());
    int depth = 0;
    for (char c : p) {
        if (c == '{') {
            ++depth;
        } else if (c == '}') {
            --depth;
        } else if (depth == 0) {
            out += c;
        }
    }
    return out;
}

bool hasPrefix(std::string_view p, std::string_view prefix) {
    if (prefix == "/") return !p.empty() && p[0] == '/';
    if (p.size() < prefix.size() || p.compare(0, prefix.size(), prefix) != 0) return false;
    if (p.size() == prefix.size()) return true;
    char c = p[prefix.size()];
    return c == '/' || c == '.';
}

std::string replacePrefix(std::string_view p, std::string_view prefix,
                          std::string_view replacement) {
    if (prefix == "/") return child(replacement, p.substr(1));
    std::string out(replacement);
    out += p.substr(prefix.size());
    return out;
}

std::pair<std::string_view, std::string_view> splitProperty(std::string_view p) {
    auto slash = p.rfind('/');
    std::size_t start = slash == std::string_view::npos ? 0 : slash + 1;
    std::string_view last = p.substr(start);
    if (last == "." || last == "..") return {p, {}};
    auto dot = last.find('.');
    if (dot == std::string_view::npos) return {p, {}};
    return {p.substr(0, start + dot), p.substr(start + dot + 1)};
}

std::string makeAbsolute(std::string_view target, std::string_view anchor) {
    if (!target.empty() && target[0] == '/') return std::string(target);
    auto [primPart, prop] = splitProperty(target);
    std::vector<std::string> parts;
    std::string_view a = anchor;
    std::size_t i = 1;
    while (i < a.size()) {
        auto j = a.find('/', i);
        if (j == std::string_view::npos) j = a.size();
        parts.emplace_back(a.substr(i, j - i));
        i = j + 1;
    }
    std::string_view r = primPart;
    i = 0;
    while (i < r.size()) {
        auto j = r.find('/', i);
        if (j == std::string_view::npos) j = r.size();
        std::string_view seg = r.substr(i, j - i);
        if (seg == "..") {
            if (!parts.empty()) parts.pop_back();
        } else if (!seg.empty() && seg != ".") {
            parts.emplace_back(seg);
        }
        i = j + 1;
    }
    std::string out;
    for (const std::string& s : parts) {
        out += '/';
        out += s;
    }
    if (out.empty()) out.push_back('/');
    if (!prop.empty()) {
        out += '.';
        out += prop;
    }
    return out;
}

}  // namespace principled::usd::path
