// SPDX-License-Identifier: Apache-2.0
#include "plugins/registry/pluginRegistry.h"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace principled::plugins {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

constexpr const char* kManifest = "plugInfo.json";
/// The base a type lists in "bases" to be a render delegate (USD's is "HdRendererPlugin").
constexpr const char* kBase = "RenderDelegate";

bool equalsIgnoreCase(std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) ==
                      std::tolower(static_cast<unsigned char>(y));
           });
}

std::string normalized(const fs::path& p) {
    std::error_code ec;
    fs::path c = fs::weakly_canonical(p, ec);
    return (ec ? p.lexically_normal() : c).string();
}

bool isDirectory(const fs::path& p) {
    std::error_code ec;
    return fs::is_directory(p, ec);
}

bool isFile(const fs::path& p) {
    std::error_code ec;
    return fs::is_regular_file(p, ec);
}

}  // namespace

PluginRegistry& PluginRegistry::instance() {
    static PluginRegistry registry(defaultSearchPaths());
    return registry;
}

PluginRegistry::PluginRegistry(std::vector<std::string> searchPaths)
    : _searchPaths(std::move(searchPaths)) {}

PluginRegistry::~PluginRegistry() = default;

std::vector<std::string> PluginRegistry::builtinPluginDirs() {
    std::vector<std::string> dirs;
    auto add = [&](const fs::path& p) {
        std::string n = normalized(p);
        if (std::find(dirs.begin(), dirs.end(), n) == dirs.end()) dirs.push_back(n);
    };
    std::error_code ec;
    fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) add(exe.parent_path() / ".." / "lib" / "principled" / "plugins");
    // The shared object holding this code (libprincipled_c.so loaded by Python, say).
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&PluginRegistry::builtinPluginDirs), &info) &&
        info.dli_fname) {
        fs::path self = fs::absolute(info.dli_fname, ec);
        if (!ec && normalized(self) != normalized(exe))
            add(self.parent_path() / "principled" / "plugins");
    }
    return dirs;
}

std::vector<std::string> PluginRegistry::defaultSearchPaths() {
    std::vector<std::string> paths;
    if (const char* env = std::getenv("PRINCIPLED_PLUGIN_PATH")) {
        std::stringstream ss(env);
        std::string dir;
        while (std::getline(ss, dir, ':'))
            if (!dir.empty()) paths.push_back(dir);
    }
    for (auto& d : builtinPluginDirs()) paths.push_back(std::move(d));
    return paths;
}

std::vector<RendererEntry> PluginRegistry::renderers() {
    std::lock_guard lock(_mutex);
    ensureScannedLocked();
    return _renderers;
}

std::vector<std::string> PluginRegistry::diagnostics() {
    std::lock_guard lock(_mutex);
    ensureScannedLocked();
    return _diagnostics;
}

void PluginRegistry::rescan() {
    std::lock_guard lock(_mutex);
    scanLocked();
}

void PluginRegistry::ensureScannedLocked() {
    if (!_scanned) scanLocked();
}

void PluginRegistry::scanLocked() {
    _scanned = true;
    _renderers.clear();
    _diagnostics.clear();
    _manifestsRead.clear();
    std::vector<std::string> builtin = builtinPluginDirs();
    for (const std::string& dir : _searchPaths) {
        if (!isDirectory(dir)) {
            // The built-in folder is optional; a directory the user named is worth a word.
            if (std::find(builtin.begin(), builtin.end(), normalized(dir)) == builtin.end())
                _diagnostics.push_back(dir + ": plugin search path is not a directory");
            continue;
        }
        if (isFile(fs::path(dir) / kManifest))
            readManifestLocked((fs::path(dir) / kManifest).string());
        std::vector<fs::path> subdirs;
        std::error_code ec;
        for (const auto& e : fs::directory_iterator(dir, ec))
            if (isDirectory(e.path()) && isFile(e.path() / kManifest)) subdirs.push_back(e.path());
        std::sort(subdirs.begin(), subdirs.end());  // deterministic order
        for (const auto& s : subdirs) readManifestLocked((s / kManifest).string());
    }
    std::stable_sort(_renderers.begin(), _renderers.end(),
                     [](const RendererEntry& a, const RendererEntry& b) {
                         if (a.priority != b.priority) return a.priority > b.priority;
                         return a.displayName < b.displayName;
                     });
}

void PluginRegistry::readManifestLocked(const std::string& path) {
    // The same manifest reached twice (a PRINCIPLED_PLUGIN_PATH entry inside the built-in
    // folder) is read once.
    if (!_manifestsRead.insert(normalized(path)).second) return;
    auto problem = [&](const std::string& why) { _diagnostics.push_back(path + ": " + why); };
    std::ifstream in(path, std::ios::binary);
    if (!in) return problem("cannot be read");
    std::stringstream text;
    text << in.rdbuf();
    json doc;
    try {
        // USD's plugInfo.json files may hold comments; accept // and /* */.
        doc = json::parse(text.str(), nullptr, true, true);
    } catch (const json::parse_error& e) {
        return problem(std::string("malformed JSON: ") + e.what());
    }
    if (!doc.is_object() || !doc.contains("Plugins") || !doc["Plugins"].is_array())
        return problem("expected an object with a \"Plugins\" array");
    const fs::path base = fs::path(path).parent_path();
    int index = -1;
    for (const json& plugin : doc["Plugins"]) {
        ++index;
        std::string where = "plugin #" + std::to_string(index);
        if (!plugin.is_object()) {
            problem(where + ": expected an object");
            continue;
        }
        if (plugin.contains("Name") && plugin["Name"].is_string())
            where = "plugin '" + plugin["Name"].get<std::string>() + "'";
        const json* types = nullptr;
        if (auto info = plugin.find("Info"); info != plugin.end() && info->is_object())
            if (auto t = info->find("Types"); t != info->end()) types = &*t;
        if (!types) continue;  // no types: not ours (resources, schemas)
        if (!types->is_object()) {
            problem(where + ": \"Info\".\"Types\" must be an object");
            continue;
        }
        std::vector<RendererEntry> found;
        for (auto it = types->begin(); it != types->end(); ++it) {
            const json& t = it.value();
            if (!t.is_object() || !t.contains("bases") || !t["bases"].is_array()) continue;
            bool isRenderer = false;
            for (const json& b : t["bases"])
                isRenderer |= b.is_string() && b.get<std::string>() == kBase;
            if (!isRenderer) continue;
            RendererEntry e;
            e.typeName = it.key();
            e.displayName = e.typeName;
            if (auto d = t.find("displayName"); d != t.end()) {
                if (!d->is_string()) {
                    problem(where + ": type '" + e.typeName +
                            "': \"displayName\" must be a string");
                    continue;
                }
                e.displayName = d->get<std::string>();
            }
            if (auto p = t.find("priority"); p != t.end()) {
                if (!p->is_number_integer()) {
                    problem(where + ": type '" + e.typeName + "': \"priority\" must be an integer");
                    continue;
                }
                e.priority = p->get<int>();
            }
            found.push_back(std::move(e));
        }
        if (found.empty()) continue;
        if (!plugin.contains("Type") || plugin["Type"] != "library") {
            problem(where + ": \"Type\" must be \"library\" for a render delegate");
            continue;
        }
        if (!plugin.contains("LibraryPath") || !plugin["LibraryPath"].is_string() ||
            plugin["LibraryPath"].get<std::string>().empty()) {
            problem(where + ": missing \"LibraryPath\"");
            continue;
        }
        fs::path lib = plugin["LibraryPath"].get<std::string>();
        std::string libPath = (lib.is_absolute() ? lib : base / lib).lexically_normal().string();
        std::string name = plugin.value("Name", std::string());
        for (RendererEntry& e : found) {
            auto dup =
                std::find_if(_renderers.begin(), _renderers.end(),
                             [&](const RendererEntry& r) { return r.typeName == e.typeName; });
            if (dup != _renderers.end()) {
                problem(where + ": renderer '" + e.typeName + "' ignored: already declared by " +
                        dup->plugInfoPath);
                continue;
            }
            e.pluginName = name;
            e.libraryPath = libPath;
            e.plugInfoPath = path;
            _renderers.push_back(std::move(e));
        }
    }
}

std::optional<RendererEntry> PluginRegistry::find(std::string_view name) {
    std::lock_guard lock(_mutex);
    ensureScannedLocked();
    return findLocked(name);
}

std::optional<RendererEntry> PluginRegistry::findLocked(std::string_view name) const {
    if (name.empty()) {
        if (_renderers.empty()) return std::nullopt;
        return _renderers.front();
    }
    for (const auto& r : _renderers)
        if (r.typeName == name) return r;
    for (const auto& r : _renderers)
        if (equalsIgnoreCase(r.displayName, name)) return r;
    return std::nullopt;
}

std::string PluginRegistry::notFoundMessage(std::string_view name) {
    std::lock_guard lock(_mutex);
    ensureScannedLocked();
    return notFoundMessageLocked(name);
}

std::string PluginRegistry::notFoundMessageLocked(std::string_view name) const {
    std::string searched;
    for (const auto& p : _searchPaths) searched += (searched.empty() ? "" : ":") + p;
    if (_renderers.empty())
        return "no renderer plugins found (searched " +
               (searched.empty() ? std::string("nothing") : searched) +
               "; set PRINCIPLED_PLUGIN_PATH)";
    std::string list;
    for (const auto& r : _renderers)
        list += (list.empty() ? "" : ", ") + r.typeName + " (" + r.displayName + ")";
    return "unknown renderer '" + std::string(name) + "'; available: " + list;
}

bool PluginRegistry::isLoaded(std::string_view typeName) {
    std::lock_guard lock(_mutex);
    ensureScannedLocked();
    auto e = findLocked(typeName);
    if (!e) return false;
    auto it = _libraries.find(e->libraryPath);
    return it != _libraries.end() && it->second.api;
}

const PrdRendererApi* PluginRegistry::load(std::string_view name, std::string* error) {
    std::lock_guard lock(_mutex);
    ensureScannedLocked();
    auto fail = [&](std::string message) -> const PrdRendererApi* {
        if (error) *error = std::move(message);
        return nullptr;
    };
    std::optional<RendererEntry> e = findLocked(name);
    if (!e) return fail(notFoundMessageLocked(name));
    auto [it, inserted] = _libraries.try_emplace(e->libraryPath);
    Library& lib = it->second;
    if (!inserted) return lib.api ? lib.api : fail(lib.error);

    const std::string what = "renderer '" + e->typeName + "' (" + e->plugInfoPath + ")";
    auto failLoad = [&](std::string message) {
        lib.error = std::move(message);
        return fail(lib.error);
    };
    dlerror();
    lib.handle = dlopen(e->libraryPath.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!lib.handle) {
        const char* why = dlerror();
        return failLoad(what + ": cannot load plugin library '" + e->libraryPath +
                        "': " + (why ? why : "unknown dlopen error"));
    }
    dlerror();
    void* sym = dlsym(lib.handle, PRD_PLUGIN_ENTRY_POINT);
    if (!sym)
        return failLoad(what + ": plugin library '" + e->libraryPath + "' does not export '" +
                        PRD_PLUGIN_ENTRY_POINT + "'");
    auto entry = reinterpret_cast<PrdRendererPluginFn>(sym);
    const PrdRendererApi* api = entry();
    if (!api)
        return failLoad(what + ": '" + PRD_PLUGIN_ENTRY_POINT + "' in '" + e->libraryPath +
                        "' returned no plugin table");
    if (api->abiVersion != PRD_ABI_VERSION)
        return failLoad(what + ": plugin library '" + e->libraryPath + "' has ABI version " +
                        std::to_string(api->abiVersion) + "; this host needs " +
                        std::to_string(PRD_ABI_VERSION));
    if (api->structSize < sizeof(PrdRendererApi))
        return failLoad(what + ": plugin library '" + e->libraryPath + "' has a plugin table of " +
                        std::to_string(api->structSize) + " bytes; this host needs at least " +
                        std::to_string(sizeof(PrdRendererApi)) + " (an older ABI minor version)");
    lib.api = api;
    return api;
}

std::string describePlugins(PluginRegistry& registry) {
    std::ostringstream out;
    auto list = registry.renderers();
    if (list.empty()) out << "no renderer plugins found\n";
    for (const RendererEntry& e : list) {
        out << (e.pluginName.empty() ? "(unnamed)" : e.pluginName) << ": " << e.typeName << " \""
            << e.displayName << "\" priority " << e.priority
            << (registry.isLoaded(e.typeName) ? " (loaded)" : "") << "\n    " << e.libraryPath
            << "\n";
    }
    out << "search path:";
    for (const std::string& p : registry.searchPaths()) out << "\n    " << p;
    out << "\n";
    for (const std::string& d : registry.diagnostics()) out << "warning: " << d << "\n";
    return out.str();
}

}  // namespace principled::plugins
