// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/assetResolver.h"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <system_error>

#include "scene_adapter/usda/error.h"

namespace principled::usd {

namespace fs = std::filesystem;

std::string currentDirectory() {
    std::error_code ec;
    fs::path p = fs::current_path(ec);
    return ec ? std::string(".") : p.string();
}

std::string directoryOf(std::string_view file) {
    std::error_code ec;
    fs::path p = fs::absolute(fs::path(file), ec);
    if (ec) return currentDirectory();
    return p.lexically_normal().parent_path().string();
}

std::string anchorAsset(std::string_view authored, std::string_view anchorDir) {
    if (authored.empty()) return {};
    fs::path p{std::string(authored)};
    if (p.is_relative()) p = fs::path(std::string(anchorDir)) / p;
    return p.lexically_normal().string();
}

std::string resolveAsset(std::string_view authored, std::string_view anchorDir) {
    if (authored.empty()) return {};
    const fs::path p{anchorAsset(authored, anchorDir)};
    if (authored.find("<UDIM>") != std::string_view::npos) return p.string();
    std::error_code ec;
    if (!fs::is_regular_file(p, ec)) return {};
    return p.string();
}

void refuseBinary(std::string_view text, const std::string& file) {
    if (text.substr(0, 8) == "PXR-USDC")
        throw Error({file, 0, 0},
                    "binary USD crate file (usdc) is not supported: the text format (usda) is "
                    "required; convert it with `usdcat -o file.usda`");
    if (text.substr(0, 4) == std::string_view("PK\x03\x04", 4))
        throw Error({file, 0, 0},
                    "USDZ/zip archive is not supported: the text format (usda) is required; "
                    "unzip it and convert its layers with `usdcat -o file.usda`");
}

std::string readLayerText(const std::string& file) {
    std::error_code ec;
    if (fs::is_directory(file, ec)) throw Error({file, 0, 0}, "is a directory, not a layer file");
    // 16 GiB: far above any real text layer; stops reads of huge pseudo-files (/proc/kcore).
    constexpr std::uintmax_t kMaxLayerBytes = std::uintmax_t(16) << 30;
    std::uintmax_t size = fs::file_size(file, ec);
    if (!ec && size > kMaxLayerBytes) throw Error({file, 0, 0}, "layer file is larger than 16 GiB");
    std::ifstream in(file, std::ios::binary);
    if (!in) throw Error({file, 0, 0}, "cannot open layer file");
    std::ostringstream ss;
    ss << in.rdbuf();
    std::string text = std::move(ss).str();
    refuseBinary(text, file);
    return text;
}

}  // namespace principled::usd
