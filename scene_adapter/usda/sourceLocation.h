// SPDX-License-Identifier: Apache-2.0
// Where a token, spec or value was authored: file, 1-based line and 1-based byte column.
#pragma once

#include <string>

namespace principled::usd {

struct SourceLocation {
    std::string file;
    int line = 0;
    int column = 0;

    /// "file:line:col", or just "file" when the line is unknown.
    std::string str() const {
        if (line <= 0) return file;
        return file + ":" + std::to_string(line) + ":" + std::to_string(column);
    }
};

}  // namespace principled::usd
