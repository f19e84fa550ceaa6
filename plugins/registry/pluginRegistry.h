// SPDX-License-Identifier: Apache-2.0
// PluginRegistry: finds render-delegate plugins from plugInfo.json manifests (USD's format),
// loads a plugin's library with dlopen on first use, resolves its one C entry point and checks
// the ABI version (Hydra's HdRendererPluginRegistry, hydra.md section 2.8).
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "plugins/abi/principled_plugin.h"

namespace principled::plugins {

/// One renderer type declared by a plugInfo.json.
struct RendererEntry {
    std::string typeName;      ///< key under "Info"/"Types", e.g. "PrincipledEmbreeRenderer"
    std::string displayName;   ///< "displayName", else the type name
    std::string pluginName;    ///< the plugin's "Name"
    std::string libraryPath;   ///< absolute (relative paths resolve against the manifest's folder)
    std::string plugInfoPath;  ///< the manifest that declared it
    int priority = 0;          ///< higher first
};

/// Discovers plugins and loads them. Manifests are read from each search directory and from
/// its immediate subdirectories (`dir/plugInfo.json`, `dir/*/plugInfo.json`); the first
/// declaration of a type name wins, so PRINCIPLED_PLUGIN_PATH overrides the built-in folder.
/// Malformed manifests are reported by diagnostics() and skipped. Thread-safe.
///
/// Libraries are opened with RTLD_NOW | RTLD_LOCAL and never closed: a plugin's threads and
/// static objects may outlive any handle the host holds.
class PluginRegistry {
  public:
    /// The process-wide registry: defaultSearchPaths(), scanned on first use. This is the only
    /// global state of the project.
    static PluginRegistry& instance();

    /// A registry over explicit directories (tests, hosts with their own configuration).
    explicit PluginRegistry(std::vector<std::string> searchPaths);
    ~PluginRegistry();
    PluginRegistry(const PluginRegistry&) = delete;
    PluginRegistry& operator=(const PluginRegistry&) = delete;

    /// PRINCIPLED_PLUGIN_PATH (colon-separated, in order), then builtinPluginDirs().
    static std::vector<std::string> defaultSearchPaths();
    /// `<executable dir>/../lib/principled/plugins` and, when this code lives in a shared
    /// library, `<that library's dir>/principled/plugins` (the build tree puts both at
    /// build/lib/principled/plugins).
    static std::vector<std::string> builtinPluginDirs();

    const std::vector<std::string>& searchPaths() const { return _searchPaths; }

    /// Renderers, highest priority first, then by display name.
    std::vector<RendererEntry> renderers();
    /// One line per problem: "<path>: <reason>".
    std::vector<std::string> diagnostics();
    /// Re-reads every manifest (already loaded libraries stay loaded).
    void rescan();

    /// By type name, then display name (case-insensitive); an empty name is the
    /// highest-priority renderer. nullopt if none matches.
    std::optional<RendererEntry> find(std::string_view name);
    /// The error find() would give for `name` ("unknown renderer 'x'; available: ...").
    std::string notFoundMessage(std::string_view name);

    /// Loads the library of renderer `name` (once) and returns its checked plugin table, or
    /// nullptr with *error set (missing library, missing entry point, ABI mismatch, unknown
    /// renderer).
    const PrdRendererApi* load(std::string_view name, std::string* error);
    bool isLoaded(std::string_view typeName);

  private:
    struct Library {
        void* handle = nullptr;
        const PrdRendererApi* api = nullptr;
        std::string error;  ///< why loading failed (cached: a failed load is not retried)
    };

    void ensureScannedLocked();
    void scanLocked();
    void readManifestLocked(const std::string& path);
    std::optional<RendererEntry> findLocked(std::string_view name) const;
    std::string notFoundMessageLocked(std::string_view name) const;

    std::mutex _mutex;
    std::vector<std::string> _searchPaths;
    bool _scanned = false;
    std::vector<RendererEntry> _renderers;
    std::vector<std::string> _diagnostics;
    std::set<std::string> _manifestsRead;       ///< canonical paths, this scan
    std::map<std::string, Library> _libraries;  ///< by library path
};

/// What `principled plugins` prints: one line per renderer, highest priority first
/// ("hdPrincipled: PrincipledEmbreeRenderer \"Embree\" priority 99 (loaded)\n    <library>"),
/// then the search path and every diagnostic. For CLIs and logs.
std::string describePlugins(PluginRegistry& registry);

}  // namespace principled::plugins
