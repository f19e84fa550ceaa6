// SPDX-License-Identifier: Apache-2.0
// A parsed .usda file: layer metadata and a tree of prim / property / variant specs, each with
// the file:line:col it was authored at. Specs are uncomposed opinions; see composer.h.
#pragma once

#include <cmath>

#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "scene_adapter/usda/listOp.h"
#include "scene_adapter/usda/sourceLocation.h"
#include "scene_adapter/usda/value.h"

namespace principled::usd {

/// Time mapping of a sublayer or reference: stageTime = layerTime * scale + offset.
struct LayerOffset {
    double offset = 0.0;
    double scale = 1.0;
    double apply(double t) const { return t * scale + offset; }
    /// SdfLayerOffset::IsValid and its inverse's: finite, and a scale that is not 0.
    bool valid() const { return std::isfinite(offset) && std::isfinite(scale) && scale != 0.0; }
    std::string str() const { return "offset = " + std::to_string(offset) + "; scale = " + std::to_string(scale); }
    /// `inner` nested inside this offset.
    LayerOffset compose(const LayerOffset& inner) const {
        return {inner.offset * scale + offset, inner.scale * scale};
    }
};

struct SubLayer {
    std::string assetPath;     ///< as authored
    std::string resolvedPath;  ///< absolute, empty when the file was not found
    LayerOffset offset;
    SourceLocation location;
};

/// A reference or payload arc. Equality (for list-op edits) compares asset and prim path.
struct Reference {
    std::string assetPath;     ///< as authored; empty for an internal reference
    std::string resolvedPath;  ///< absolute, empty when not found or internal
    std::string primPath;      ///< empty: the target layer's defaultPrim
    LayerOffset offset;
    SourceLocation location;
    bool operator==(const Reference& o) const {
        return assetPath == o.assetPath && primPath == o.primPath;
    }
};
/// A reference's identity in list operations (ListOp): its asset and prim path.
inline std::string listOpKey(const Reference& r) { return r.assetPath + '\n' + r.primPath; }

/// A path-valued list item (inherits, specializes, targets, connections) with its location.
struct PathItem {
    std::string path;
    SourceLocation location;
    bool operator==(const PathItem& o) const { return path == o.path; }
};
inline const std::string& listOpKey(const PathItem& p) { return p.path; }

enum class Specifier { Def, Over, Class };
enum class Variability { Varying, Uniform, Config };

struct AttributeSpec {
    std::string name;
    std::string typeName;  ///< without []
    bool isArray = false;
    bool custom = false;
    Variability variability = Variability::Varying;
    std::optional<Value> defaultValue;  ///< may hold None (a block)
    /// `= AnimationBlock` (SdfAnimationBlock) in place of a default: weaker time samples are
    /// blocked, weaker defaults still apply; this spec's own time samples still win.
    bool animationBlock = false;
    bool hasTimeSamples = false;
    std::map<double, Value> timeSamples;  ///< None samples block the value at that time
    bool hasConnections = false;
    /// Null unless `.connect` is authored: most attributes have none, and a ListOp is 150 bytes.
    std::shared_ptr<ListOp<PathItem>> connections;
    Dictionary metadata;
    SourceLocation location;
};

struct RelationshipSpec {
    std::string name;
    bool custom = false;
    bool hasTargets = false;
    ListOp<PathItem> targets;  ///< `= None` is an explicit empty list
    Dictionary metadata;
    SourceLocation location;
};

struct PrimSpec;

struct VariantSetSpec {
    std::string name;
    std::vector<std::unique_ptr<PrimSpec>> variants;  ///< each variant body, named by its name
    SourceLocation location;
    const PrimSpec* variant(std::string_view name) const;
};

/// A prim spec, or the body of a variant (isVariant, no specifier of its own).
struct PrimSpec {
    Specifier specifier = Specifier::Over;
    bool isVariant = false;
    std::string typeName;
    std::string name;
    Dictionary metadata;  ///< every metadata field except the arcs and list ops below
    ListOp<Reference> references, payloads;
    ListOp<PathItem> inherits, specializes;
    ListOp<std::string> variantSetNames, apiSchemas;
    std::map<std::string, std::string> variantSelections;  ///< `variants = { string set = "x" }`
    std::vector<AttributeSpec> attributes;
    std::vector<RelationshipSpec> relationships;
    std::vector<std::unique_ptr<PrimSpec>> children;
    std::vector<VariantSetSpec> variantSets;
    std::optional<std::vector<std::string>> nameChildrenOrder, propertyOrder;
    SourceLocation location;
    /// name -> child, only for prims with many children (keys view the children's names).
    std::unordered_map<std::string_view, const PrimSpec*> childIndex;

    const PrimSpec* child(std::string_view name) const;
    /// Builds the name lookup for prims with many children (called by the parser).
    void indexChildren();
    const VariantSetSpec* variantSet(std::string_view name) const;
    const AttributeSpec* attribute(std::string_view name) const;
    const RelationshipSpec* relationship(std::string_view name) const;
};

struct Layer {
    std::string file;       ///< display name used in locations (the path as opened)
    std::string anchorDir;  ///< directory relative asset paths resolve against
    Dictionary metadata;    ///< defaultPrim, upAxis, customLayerData, doc ...
    std::vector<SubLayer> subLayers;
    std::vector<std::unique_ptr<PrimSpec>> rootPrims;
    std::optional<std::vector<std::string>> rootPrimOrder;
    std::unordered_map<std::string_view, const PrimSpec*> rootIndex;  ///< see indexChildren

    std::string defaultPrim() const;
    /// Builds the root prim lookup (called by the parser).
    void indexRootPrims();
    /// Layer metadata value or nullptr.
    const Value* field(std::string_view key) const;
    /// The spec at a site path such as "/A/B" or "/A{geo=quad}/B", or nullptr.
    const PrimSpec* prim(std::string_view sitePath) const;
};

}  // namespace principled::usd
