// SPDX-License-Identifier: Apache-2.0
// Helpers shared by the usda tests: temporary directories with layer files, error capture.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "scene_adapter/usda/error.h"

namespace principled::usd::test {

/// A fresh directory under the build tree (or /tmp), removed on destruction.
class TempDir {
public:
    explicit TempDir(std::string_view name) {
        _path = std::filesystem::temp_directory_path() /
                ("principled_usda_" + std::string(name) + "_" + std::to_string(::getpid()));
        std::filesystem::remove_all(_path);
        std::filesystem::create_directories(_path);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(_path, ec);
    }
    /// Writes `text` to `relative` (creating folders) and returns the absolute path.
    std::string write(const std::string& relative, std::string_view text) const {
        std::filesystem::path p = _path / relative;
        std::filesystem::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << text;
        return p.string();
    }
    std::string path(const std::string& relative = {}) const {
        return relative.empty() ? _path.string() : (_path / relative).string();
    }

private:
    std::filesystem::path _path;
};

/// Runs `f` and returns the what() of the ParseError it throws ("" if none).
template <class F>
std::string parseErrorOf(F&& f) {
    try {
        f();
    } catch (const ParseError& e) {
        return e.what();
    }
    return {};
}

inline std::string corpusDir() {
    return PRINCIPLED_SOURCE_DIR "/../shared/usd-wg";
}

}  // namespace principled::usd::test
