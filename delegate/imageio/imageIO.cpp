// SPDX-License-Identifier: Apache-2.0
// Finds and loads libprincipled_oiio.so on first use (see imageIO.h for the search order).
#include "delegate/imageio/imageIO.h"

#include "delegate/imageio/pngReader.h"

#include <dlfcn.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <mutex>

namespace principled::imageio {

namespace fs = std::filesystem;

namespace {

constexpr const char* kModule = "libprincipled_oiio.so";

struct State {
    std::mutex mutex;
    std::atomic<Backend*> backend{nullptr};
    bool tried = false;
    std::string error;  // why loading failed (kept: later calls report the same)
    std::string path;
};

State& state() {
    static State* s = new State();  // never destroyed: the backend outlives static destructors
    return *s;
}

std::vector<std::string> candidates() {
    std::vector<std::string> out;
    auto add = [&](const fs::path& p) {
        std::error_code ec;
        fs::path n = fs::weakly_canonical(p, ec);
        std::string s = (ec ? p : n).string();
        for (const auto& c : out)
            if (c == s) return;
        out.push_back(s);
    };
    if (const char* env = std::getenv("PRINCIPLED_IMAGEIO_BACKEND"); env && *env) {
        out.push_back(env);
        return out;  // an explicit choice is the only one tried
    }
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        add(exe.parent_path() / ".." / "lib" / kModule);  // build/bin -> build/lib; bin -> lib
        add(exe.parent_path() / kModule);
    }
    // The shared object holding this code: a plugin in lib/principled/plugins/NAME/, or a
    // library in lib/.
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&candidates), &info) && info.dli_fname) {
        fs::path self = fs::absolute(info.dli_fname, ec);
        if (!ec) {
            add(self.parent_path() / kModule);
            add(self.parent_path() / ".." / ".." / ".." / kModule);
        }
    }
#ifdef PRINCIPLED_IMAGEIO_BUILD_DIR
    add(fs::path(PRINCIPLED_IMAGEIO_BUILD_DIR) / kModule);
#endif
#ifdef PRINCIPLED_IMAGEIO_INSTALL_DIR
    add(fs::path(PRINCIPLED_IMAGEIO_INSTALL_DIR) / kModule);
#endif
    return out;
}

Backend* load(State& s) {
    std::string tried;
    auto attempt = [&](const std::string& name) -> Backend* {
        void* handle = dlopen(name.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char* e = dlerror();
            tried += "\n  " + name + ": " + (e ? e : "cannot be loaded");
            return nullptr;
        }
        auto version = reinterpret_cast<PrincipledImageioAbiVersionFn>(
            dlsym(handle, "principled_imageio_abi_version"));
        auto entry = reinterpret_cast<PrincipledImageioBackendFn>(
            dlsym(handle, "principled_imageio_backend"));
        if (!version || !entry || version() != kAbiVersion) {
            tried += "\n  " + name + ": not a principled image I/O backend of ABI version " +
                     std::to_string(kAbiVersion);
            return nullptr;  // left loaded: dlclose of a module with C++ statics is not worth it
        }
        Backend* b = entry();
        if (b) {
            Dl_info info{};
            s.path = dladdr(reinterpret_cast<void*>(entry), &info) && info.dli_fname
                         ? info.dli_fname
                         : name;
        }
        return b;
    };
    std::error_code ec;
    for (const auto& c : candidates()) {
        if (!std::getenv("PRINCIPLED_IMAGEIO_BACKEND") && !fs::exists(c, ec)) {
            tried += "\n  " + c + ": no such file";
            continue;
        }
        if (Backend* b = attempt(c)) return b;
    }
    if (!std::getenv("PRINCIPLED_IMAGEIO_BACKEND"))
        if (Backend* b = attempt(kModule)) return b;  // LD_LIBRARY_PATH, rpath, ld.so.cache
    s.error = std::string("cannot load the image I/O backend ") + kModule +
              " (textures, light images and checkpoints are read and written with it; set "
              "PRINCIPLED_IMAGEIO_BACKEND to its path). Tried:" + tried;
    return nullptr;
}

}  // namespace

Backend* backend(std::string* error) {
    State& s = state();
    if (Backend* b = s.backend.load(std::memory_order_acquire)) return b;
    std::lock_guard lock(s.mutex);
    if (!s.tried) {
        s.tried = true;
        s.backend.store(load(s), std::memory_order_release);
    }
    Backend* b = s.backend.load(std::memory_order_relaxed);
    if (!b && error) *error = s.error;
    return b;
}

Backend* loadedBackend() {
    return state().backend.load(std::memory_order_acquire);
}

std::string backendPath() {
    State& s = state();
    std::lock_guard lock(s.mutex);
    return s.path;
}

std::unique_ptr<ImageReader> openTexture(const std::string& path, std::string* error,
                                         bool nativePng) {
    if (nativePng) {
        std::string ignored;  // not a PNG, or libpng refuses it: OpenImageIO decides
        if (auto reader = openPng(path, &ignored)) return reader;
    }
    Backend* b = backend(error);
    return b ? b->openTexture(path, error) : nullptr;
}

}  // namespace principled::imageio
