// SPDX-License-Identifier: Apache-2.0
// One authored USD value: a scalar, tuple, matrix, string/token, asset, path, an array of any of
// these, a dictionary, or None (a value block). Array payloads are shared, so copying a Value is
// cheap even for a million points.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scene_adapter/usda/sourceLocation.h"

namespace principled::usd {

/// An asset reference: the text as authored between @...@ and the absolute path it resolved to
/// (empty when the file was not found, relative to the layer that authored it).
struct AssetPath {
    std::string authored;
    std::string resolved;
    /// The authored path made absolute against the layer's directory whether or not the file
    /// exists ("" for an empty path): where a file that appears later will be looked for.
    std::string anchored;
    bool operator==(const AssetPath&) const = default;
};

class Value;
/// Dictionary values (customData, customLayerData, assetInfo, variants...): key -> value.
using Dictionary = std::map<std::string, Value, std::less<>>;

class Value {
public:
    enum class Kind : std::uint8_t {
        Empty,        ///< nothing authored
        None,         ///< explicitly blocked with `None`
        Number,       ///< bool, integer or floating scalar (stored as double)
        Tuple,        ///< float3, quatf, matrix4d ... (flat doubles)
        String,       ///< string or token
        Asset,        ///< @path@
        Path,         ///< </a/b>
        NumberArray,  ///< numeric arrays, flat with components() per element
        StringArray,  ///< string[], token[], path lists
        AssetArray,   ///< asset[]
        Dictionary,
    };

    Value() = default;

    static Value none(std::string typeName, bool isArray, SourceLocation where);
    static Value number(std::string typeName, double v, SourceLocation where);
    static Value tuple(std::string typeName, std::vector<double> v, SourceLocation where);
    static Value string(std::string typeName, std::string s, SourceLocation where);
    static Value asset(AssetPath a, SourceLocation where);
    static Value path(std::string p, SourceLocation where);
    static Value numberArray(std::string typeName, int components, std::vector<double> v,
                             SourceLocation where);
    static Value stringArray(std::string typeName, std::vector<std::string> v,
                             SourceLocation where);
    static Value assetArray(std::vector<AssetPath> v, SourceLocation where);
    static Value dictionary(Dictionary d, SourceLocation where);

    Kind kind() const { return _kind; }
    bool isEmpty() const { return _kind == Kind::Empty; }
    /// True when explicitly blocked (None) or empty.
    bool isNone() const { return _kind == Kind::None || _kind == Kind::Empty; }
    /// As authored without [] e.g. "point3f", "token", "matrix4d". Untyped metadata values
    /// get "bool", "int", "double", "string", "asset", "path", "dictionary", "token"; an
    /// unregistered metadata field whose value no other kind holds (a tuple of strings, a
    /// nested list...) is a String of typeName "unregistered" holding the text as authored.
    const std::string& typeName() const { return _typeName; }
    bool isArray() const { return _isArray; }

    std::optional<bool> getBool() const;           ///< bool, or an integer 0/1
    std::optional<std::int64_t> getInt() const;    ///< integer types and exact-integer floats
    std::optional<double> getDouble() const;       ///< any numeric scalar
    std::optional<std::string> getString() const;  ///< string or token
    std::optional<AssetPath> getAsset() const;
    std::optional<std::string> getPath() const;
    /// Tuples and matrices as flat doubles: float3 -> 3, matrix4d -> 16 row-major as authored
    /// (USD row-vector convention), quat -> 4 as authored (real, i, j, k).
    std::optional<std::vector<double>> getTuple() const;

    /// Numeric arrays: flat numbers, components() per element. nullptr for other kinds.
    const std::vector<double>* numbers() const;
    /// Components per element (float3[] -> 3, matrix4d[] -> 16, scalars 1).
    int components() const { return _components; }
    /// Element count: arrays their length, scalars 1, None/empty 0.
    std::size_t size() const;
    /// string[], token[], asset[] (as authored), path lists. nullptr for other kinds.
    const std::vector<std::string>* strings() const;
    /// asset[] with resolved paths. nullptr for other kinds.
    const std::vector<AssetPath>* assets() const;
    /// Dictionary entries. nullptr for other kinds.
    const Dictionary* dictionary() const;
    /// A dictionary entry, nullptr when absent or not a dictionary.
    const Value* find(std::string_view key) const;

    const SourceLocation& location() const { return _where; }
    void setLocation(SourceLocation where) { _where = std::move(where); }

    /// Same type and contents (locations are ignored). Shared array payloads compare in O(1).
    bool operator==(const Value& other) const;

    /// Debug text, e.g. "(1, 2, 3)"; arrays longer than 8 elements are abbreviated.
    std::string toString() const;

private:
    struct Storage;
    Kind _kind = Kind::Empty;
    bool _isArray = false;
    int _components = 1;
    double _number = 0.0;
    std::string _typeName;
    std::shared_ptr<const Storage> _data;
    SourceLocation _where;
};

}  // namespace principled::usd
