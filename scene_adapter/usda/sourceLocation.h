// SPDX-License-Identifier: Apache-2.0
// Where a token, spec or value was authored: file, 1-based line and 1-based byte column.
#pragma once

#include <ostream>
#include <string>

namespace principled::usd {

/// A file name, interned: every location in a file shares one string (a location is copied
/// into each spec, value and composed property, so a copied std::string cost 32 bytes plus a
/// heap block per copy). Construct it once per file; copies are a pointer.
class FileName {
public:
    FileName() = default;
    FileName(const std::string& name);  // NOLINT: implicit, as the std::string it replaces
    FileName(const char* name) : FileName(std::string(name)) {}  // NOLINT

    const std::string& str() const { return _name ? *_name : emptyName(); }
    operator const std::string&() const { return str(); }  // NOLINT
    bool empty() const { return str().empty(); }

    friend bool operator==(const FileName& a, const FileName& b) { return a._name == b._name || a.str() == b.str(); }
    friend bool operator==(const FileName& a, const std::string& b) { return a.str() == b; }
    friend bool operator==(const std::string& a, const FileName& b) { return a == b.str(); }
    friend bool operator!=(const FileName& a, const FileName& b) { return !(a == b); }
    friend std::string operator+(const std::string& a, const FileName& b) { return a + b.str(); }
    friend std::string operator+(const FileName& a, const std::string& b) { return a.str() + b; }
    friend std::string operator+(const char* a, const FileName& b) { return a + b.str(); }
    friend std::ostream& operator<<(std::ostream& out, const FileName& f) { return out << f.str(); }

private:
    static const std::string& emptyName();
    const std::string* _name = nullptr;  ///< into the process-wide intern table (never freed)
};

struct SourceLocation {
    FileName file;
    int line = 0;
    int column = 0;

    /// "file:line:col", or just "file" when the line is unknown.
    std::string str() const {
        if (line <= 0) return file.str();
        return file + ":" + std::to_string(line) + ":" + std::to_string(column);
    }
};

}  // namespace principled::usd
