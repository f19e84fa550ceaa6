// SPDX-License-Identifier: Apache-2.0
// A composed USD stage read from .usda text: open a file (or text), compose its layers and arcs
// (composer.h), then read prims, attributes and relationships. Problems that do not prevent
// loading (missing references, bad variants, cycles) are collected as diagnostics.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "scene_adapter/usda/error.h"
#include "scene_adapter/usda/prim.h"

namespace principled::usd {

struct StageOptions {
    /// prim path -> variant set -> selection; beats authored selections.
    std::map<std::string, std::map<std::string, std::string>> variantOverrides;
    /// Most distinct layer files one stage may load.
    std::size_t maxLayers = 4096;
    /// Most composed prims (about 1-2 KB each): references can multiply a small file into an
    /// exponential namespace, so composition stops here with an error diagnostic.
    std::size_t maxPrims = 2'000'000;
    /// Compose payload arcs (false: prims with payloads are composed without them).
    bool loadPayloads = true;
};

struct Diagnostic {
    enum class Severity { Warning, Error };
    SourceLocation where;
    std::string message;
    Severity severity = Severity::Warning;
    /// "file:line:col: warning: message".
    std::string str() const;
};

class Stage {
public:
    /// Reads and composes `path`. Throws Error (ParseError for syntax) when the root layer cannot
    /// be read or parsed; problems in other layers become diagnostics.
    static std::unique_ptr<Stage> open(const std::string& path, const StageOptions& options = {});
    /// Composes in-memory text; relative asset paths resolve against the current directory.
    static std::unique_ptr<Stage> openString(std::string_view text, const std::string& displayName,
                                             const StageOptions& options = {});

    const Prim* pseudoRoot() const { return _root; }
    /// The prim at an absolute path, nullptr if none.
    const Prim* prim(std::string_view path) const;
    /// Active, defined, non-abstract prims in depth-first order (the pseudo-root excluded);
    /// subtrees below a skipped prim are skipped too. This is what a renderer draws.
    std::vector<const Prim*> traverse() const;

    std::string defaultPrim() const { return _defaultPrim; }
    std::string upAxis() const { return _upAxis; }                     ///< "Y" fallback
    double metersPerUnit() const { return _metersPerUnit; }            ///< 0.01 fallback
    double startTimeCode() const { return _startTimeCode; }            ///< 0 fallback
    double endTimeCode() const { return _endTimeCode; }                ///< 0 fallback
    double timeCodesPerSecond() const { return _timeCodesPerSecond; }  ///< 24 fallback
    double framesPerSecond() const { return _framesPerSecond; }        ///< 24 fallback
    /// Both startTimeCode and endTimeCode are authored.
    bool hasTimeCodes() const { return _hasStart && _hasEnd; }
    /// startTimeCode when authored, else kDefaultTime (NaN: default values).
    double defaultTime() const;
    /// Root layer metadata (customLayerData, doc, ...), nullptr when absent.
    const Value* layerMetadata(std::string_view key) const;

    /// Non-fatal problems, errors included (severity Error: cycles, unparsable layers).
    const std::vector<Diagnostic>& warnings() const { return _warnings; }
    /// Every file that contributed, root first.
    std::vector<std::string> layerFiles() const { return _layerFiles; }

private:
    friend class Composer;
    friend class StageEdit;
    Stage() = default;
    std::vector<std::unique_ptr<Prim>> _prims;
    std::unordered_map<std::string, const Prim*> _index;
    const Prim* _root = nullptr;
    std::string _defaultPrim, _upAxis = "Y";
    double _metersPerUnit = 0.01, _startTimeCode = 0.0, _endTimeCode = 0.0;
    double _timeCodesPerSecond = 24.0, _framesPerSecond = 24.0;
    bool _hasStart = false, _hasEnd = false;
    Dictionary _layerMetadata;
    std::vector<Diagnostic> _warnings;
    std::vector<std::string> _layerFiles;
};

}  // namespace principled::usd
