// SPDX-License-Identifier: Apache-2.0
// Helpers for the shading tests: small images written with OpenImageIO into a per-process
// temporary directory.
#pragma once

#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

namespace principled::shading::test {

/// A fresh directory under the system temp dir, removed when the object dies.
class TempDir {
  public:
    TempDir() {
        _path = std::filesystem::temp_directory_path() /
                ("principled_shading_" + std::to_string(::getpid()) + "_" +
                 std::to_string(counter()++));
        std::filesystem::create_directories(_path);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(_path, ec);
    }
    std::string file(const std::string& name) const { return (_path / name).string(); }

  private:
    static int& counter() {
        static int n = 0;
        return n;
    }
    std::filesystem::path _path;
};

/// Writes pixels (row 0 = top row, as files store them) of `channels` floats each. The file
/// type follows the extension; `format` is the stored type (UINT8, UINT16, FLOAT, HALF).
inline bool writeImage(const std::string& path, int width, int height, int channels,
                       const std::vector<float>& pixels, OIIO::TypeDesc format,
                       const std::vector<std::pair<std::string, std::string>>& attributes = {}) {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) return false;
    OIIO::ImageSpec spec(width, height, channels, format);
    for (const auto& [k, v] : attributes) spec.attribute(k, v);
    if (!out->open(path, spec)) return false;
    bool ok = out->write_image(OIIO::TypeDesc::FLOAT, pixels.data());
    return out->close() && ok;
}

}  // namespace principled::shading::test
