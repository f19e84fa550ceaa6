// SPDX-License-Identifier: Apache-2.0
// The composed scene objects a Stage owns: Prim, Attribute and Relationship. They are immutable
// after composition and safe to read from several threads.
#pragma once

#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "scene_adapter/usda/sourceLocation.h"
#include "scene_adapter/usda/value.h"

namespace principled::usd {

class Composer;
class StageEdit;

/// "Default time": the attribute's default value (see Attribute::get).
inline constexpr double kDefaultTime = std::numeric_limits<double>::quiet_NaN();

class Attribute {
public:
    const std::string& name() const { return _name; }
    /// As authored without [] ("point3f", "token", "matrix4d").
    const std::string& typeName() const { return _typeName; }
    bool isArray() const { return _isArray; }
    bool isUniform() const { return _uniform; }
    bool isCustom() const { return _custom; }
    /// A default value (not a None block) or time samples are authored, as
    /// UsdAttribute::HasAuthoredValue. A blocked attribute (`= None`) has no value.
    bool hasValue() const { return (_default && !_default->isNone()) || !_samples.empty(); }
    /// The strongest default opinion, nullptr if none.
    const Value* defaultValue() const { return _default ? &*_default : nullptr; }
    /// The winning time samples (in stage time, layer offsets applied). Empty when none are
    /// authored or a stronger layer authored a default, which then wins at every time.
    const std::map<double, Value>& timeSamples() const { return _samples; }
    /// The value at `time`. Finite time: time samples if they win, else the default. NaN
    /// (kDefaultTime): the default if authored, else the earliest sample. Empty Value if none.
    Value get(double time = kDefaultTime) const;
    /// More than one time sample wins: the value may change over time.
    bool isTimeVarying() const { return _samples.size() > 1; }
    /// Absolute connection targets "/Prim/Path.inputs:name" in stage namespace.
    const std::vector<std::string>& connections() const { return _connections; }
    /// Attribute metadata (interpolation, elementSize, customData, colorSpace, ...).
    const Value* metadata(std::string_view key) const;
    const Dictionary& allMetadata() const { return _metadata; }
    /// The strongest opinion's location.
    const SourceLocation& location() const { return _location; }

private:
    friend class Composer;
    friend class StageEdit;
    std::string _name, _typeName;
    bool _isArray = false, _uniform = false, _custom = false;
    std::optional<Value> _default;
    std::map<double, Value> _samples;
    std::vector<std::string> _connections;
    Dictionary _metadata;
    SourceLocation _location;
};

class Relationship {
public:
    const std::string& name() const { return _name; }
    /// Absolute target paths in stage namespace (composed list ops, remapped through arcs).
    const std::vector<std::string>& targets() const { return _targets; }
    const Value* metadata(std::string_view key) const;
    const SourceLocation& location() const { return _location; }

private:
    friend class Composer;
    friend class StageEdit;
    std::string _name;
    std::vector<std::string> _targets;
    Dictionary _metadata;
    SourceLocation _location;
};

class Prim {
public:
    const std::string& path() const { return _path; }
    const std::string& name() const { return _name; }
    const std::string& typeName() const { return _typeName; }
    /// False when `active = false` (its subtree is not composed) or an ancestor is inactive.
    bool isActive() const { return _active; }
    /// A `class` prim or below one: never rendered.
    bool isAbstract() const { return _abstract; }
    /// Has a `def` (or `class`) opinion; over-only prims are not defined.
    bool isDefined() const { return _defined; }
    const Prim* parent() const { return _parent; }
    /// Composed children in namespace order (inactive and abstract ones included).
    const std::vector<const Prim*>& children() const { return _children; }
    const Attribute* attribute(std::string_view name) const;
    /// Sorted by name.
    const std::vector<const Attribute*>& attributes() const { return _attributes; }
    const Relationship* relationship(std::string_view name) const;
    const std::vector<const Relationship*>& relationships() const { return _relationships; }
    /// Composed prim metadata: kind, instanceable, hidden, documentation, customData, ...
    const Value* metadata(std::string_view key) const;
    const Dictionary& allMetadata() const { return _metadata; }
    const std::vector<std::string>& appliedSchemas() const { return _appliedSchemas; }
    /// `schema` is applied ("MaterialBindingAPI"); for multiple-apply schemas give the instance
    /// ("CollectionAPI:lightLink") or just the schema name to match any instance.
    bool hasAPI(std::string_view schema) const;
    /// Variant set -> the selection used for composition.
    std::map<std::string, std::string> variantSelections() const { return _variantSelections; }
    /// For `instanceable = true` prims: equal keys mean the same composition arcs and variant
    /// selections, so the subtrees below them are identical and a renderer may build their
    /// geometry once (instances are still expanded here, as instance proxies). Empty otherwise.
    const std::string& instanceKey() const { return _instanceKey; }
    bool isInstance() const { return !_instanceKey.empty(); }
    /// The strongest defining spec (or the strongest spec when none defines it).
    const SourceLocation& location() const { return _location; }

private:
    friend class Composer;
    friend class StageEdit;
    std::string _path, _name, _typeName;
    bool _active = true, _abstract = false, _defined = false;
    const Prim* _parent = nullptr;
    std::vector<const Prim*> _children;
    std::vector<std::unique_ptr<Attribute>> _attributeStore;
    std::vector<const Attribute*> _attributes;
    std::vector<std::unique_ptr<Relationship>> _relationshipStore;
    std::vector<const Relationship*> _relationships;
    Dictionary _metadata;
    std::vector<std::string> _appliedSchemas;
    std::map<std::string, std::string> _variantSelections;
    std::string _instanceKey;
    SourceLocation _location;
};

}  // namespace principled::usd
