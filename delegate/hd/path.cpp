// SPDX-License-Identifier: Apache-2.0
#include "delegate/hd/path.h"

namespace principled::hd {

const Path& Path::absoluteRoot() {
    static const Path root("/");
    return root;
}

bool Path::isPropertyPath() const {
    const std::string& s = str();
    size_t slash = s.rfind('/');
    return s.find('.', slash == std::string::npos ? 0 : slash) != std::string::npos;
}

std::string Path::name() const {
    const std::string& s = str();
    size_t slash = s.rfind('/');
    size_t start = slash == std::string::npos ? 0 : slash + 1;
    size_t dot = s.find('.', start);
    if (dot != std::string::npos) return s.substr(dot + 1);
    return s.substr(start);
}

Path Path::primPath() const {
    const std::string& s = str();
    size_t slash = s.rfind('/');
    size_t dot = s.find('.', slash == std::string::npos ? 0 : slash);
    return dot == std::string::npos ? *this : Path(std::string_view(s).substr(0, dot));
}

Path Path::parent() const {
    if (isPropertyPath()) return primPath();
    const std::string& s = str();
    if (s.empty() || s == "/") return Path();
    size_t slash = s.rfind('/');
    if (slash == std::string::npos) return Path();
    if (slash == 0) return absoluteRoot();
    return Path(std::string_view(s).substr(0, slash));
}

Path Path::appendChild(std::string_view name) const {
    if (empty() || isAbsoluteRoot()) return Path("/" + std::string(name));
    return Path(str() + "/" + std::string(name));
}

Path Path::appendProperty(std::string_view name) const {
    return Path(str() + "." + std::string(name));
}

bool Path::hasPrefix(const Path& prefix) const {
    if (prefix.isAbsoluteRoot()) return !empty() && str()[0] == '/';
    const std::string& s = str();
    const std::string& p = prefix.str();
    if (s.size() < p.size() || s.compare(0, p.size(), p) != 0) return false;
    return s.size() == p.size() || s[p.size()] == '/' || s[p.size()] == '.';
}

}  // namespace principled::hd
