// SPDX-License-Identifier: Apache-2.0
#include "tools/outputs.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fcntl.h>
#include <unistd.h>

#include "delegate/imageWriter.h"
#include "plugins/renderSession.h"
#include "tools/aovLayers.h"

namespace principled::tools {

namespace fs = std::filesystem;

namespace {

/// DIR/.STEM.tmpPID.EXT: hidden, in the same directory (the rename stays on one file system).
fs::path temporaryName(const fs::path& path, const char* kind) {
    return path.parent_path() /
           ("." + path.stem().string() + "." + kind + std::to_string(getpid()) + path.extension().string());
}

}  // namespace

std::string outputFormat(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".exr" || ext == ".png" ? ext : "";
}

std::string checkWritable(const std::string& path, bool image) {
    if (image && outputFormat(path).empty()) return path + ": output must end in .exr or .png";
    const fs::path p(path);
    std::error_code ec;
    if (fs::is_directory(p, ec)) return path + ": is a directory";
    const fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    if (!fs::exists(dir, ec)) {
        fs::create_directories(dir, ec);
        if (ec) return path + ": cannot create the directory " + dir.string() + ": " + ec.message();
    }
    if (!fs::is_directory(dir, ec)) return path + ": " + dir.string() + " is not a directory";
    // The only reliable test (permissions, read-only and pseudo file systems): create a file there.
    const fs::path probe = temporaryName(p, "check");
    int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd < 0) return path + ": cannot write in " + dir.string() + ": " + std::strerror(errno);
    ::close(fd);
    fs::remove(probe, ec);
    return "";
}

std::vector<std::string> writeOutputs(const host::RenderSession& session, const std::vector<std::string>& outputs,
                                      bool split) {
    AovLayers written = aovLayers(session);
    const std::vector<embree::ImageLayer>& layers = written.layers;
    std::vector<std::string> errors;
    auto atomicWrite = [&](const fs::path& path, const std::vector<embree::ImageLayer>& ls) {
        std::error_code ec;
        if (!path.parent_path().empty()) fs::create_directories(path.parent_path(), ec);
        const fs::path tmp = temporaryName(path, "tmp");
        std::string error;
        if (!embree::writeImage(tmp.string(), session.width(), session.height(), ls, &error,
                                session.pixelAspectRatio())) {
            fs::remove(tmp, ec);
            // The message names the file asked for, not the temporary one.
            for (size_t at; (at = error.find(tmp.string())) != std::string::npos;)
                error.replace(at, tmp.string().size(), path.string());
            errors.push_back(error.rfind(path.string(), 0) == 0 ? error : path.string() + ": " + error);
            return;
        }
        fs::rename(tmp, path, ec);
        if (ec) {
            fs::remove(tmp, ec);
            errors.push_back(path.string() + ": cannot rename into place: " + ec.message());
        }
    };
    for (const auto& out : outputs) {
        const fs::path path(out);
        const bool exr = outputFormat(out) == ".exr";
        if (split && exr) {
            for (const auto& l : layers) {
                // "primvars:st" -> "primvars_st": ':' is not allowed in Windows/SMB file names.
                std::string aov = l.name.empty() ? "color" : l.name;
                std::replace(aov.begin(), aov.end(), ':', '_');
                fs::path p = path;
                p.replace_filename(path.stem().string() + "." + aov + path.extension().string());
                embree::ImageLayer single = l;
                single.name.clear();
                atomicWrite(p, {single});
            }
        } else {
            atomicWrite(path, exr ? layers : std::vector<embree::ImageLayer>{layers[0]});
        }
    }
    return errors;
}

}  // namespace principled::tools
