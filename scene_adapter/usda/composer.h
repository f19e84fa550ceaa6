// SPDX-License-Identifier: Apache-2.0
// Composition (a small Pcp): for every prim path, a "prim index" tree of nodes (layer stack +
// site path + arc) built from the parent's index (ancestral arcs) plus the arcs authored at the
// prim, in LIVRPS strength order: local, inherits, variants, references, payloads, specializes.
// Opinions are then read from each node's specs strongest first.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "scene_adapter/usda/layer.h"
#include "scene_adapter/usda/stage.h"

namespace principled::usd {

/// A layer and its sublayers, strongest first, with each layer's time offset.
struct LayerStack {
    std::string identifier;  ///< the root layer's file
    std::vector<const Layer*> layers;
    std::vector<LayerOffset> offsets;
    bool hasPrim(std::string_view site) const;
};

enum class Arc : unsigned char { Root, Inherit, Variant, Reference, Payload, Specialize };

/// One step of a node's namespace mapping: paths under `source` move under `target`; other
/// paths are unmappable unless `identityFallback` (class arcs keep the layer stack namespace).
struct MapStep {
    std::string source, target;
    bool identityFallback = false;
};

struct PrimIndexNode {
    const LayerStack* stack = nullptr;
    std::string site;  ///< prim path in the stack, with variant selections: "/A{v=x}/B"
    Arc arc = Arc::Root;
    /// Node namespace -> stage namespace, innermost step first. Shared between a node and the
    /// nodes derived from it for descendant prims (the mapping is prefix-based).
    std::shared_ptr<const std::vector<MapStep>> map = std::make_shared<std::vector<MapStep>>();
    LayerOffset offset;  ///< node time -> stage time
    SourceLocation arcLocation;
    PrimIndexNode* parent = nullptr;
    std::vector<std::unique_ptr<PrimIndexNode>> children;  ///< sorted by arc (LIVRPS)
    /// Variant sets listed at this site (composed once), and how many are expanded so far.
    std::optional<std::vector<std::string>> variantSetNames;
    std::size_t nextVariantSet = 0;
    bool variantsDone = false;  ///< all variant sets at this site are expanded
    /// Below an instanceable prim: this node is the instance's own (local or ancestral) layer
    /// stack, whose opinions on the instance's descendants USD ignores; the nodes of the
    /// instance's arcs below it still contribute. Carried to the nodes derived from it.
    bool inert = false;

    void addChild(std::unique_ptr<PrimIndexNode> child);
};

class Composer {
public:
    Composer(Stage& stage, const StageOptions& options);
    ~Composer();
    /// Throws Error when the root layer cannot be read or parsed.
    void composeFile(const std::string& path);
    void composeText(std::string_view text, const std::string& displayName);

private:
    using Node = PrimIndexNode;
    struct SpecRef {
        const PrimSpec* spec;
        const Node* node;
        LayerOffset offset;
    };

    const Layer* loadLayer(const std::string& absolutePath, const std::string& displayName);
    const LayerStack* loadStack(const Layer* root);
    void addToStack(LayerStack& stack, const Layer* layer, LayerOffset offset,
                    std::vector<const Layer*>& chain);
    void compose(const Layer* rootLayer);
    void warn(const SourceLocation& where, std::string message,
              Diagnostic::Severity severity = Diagnostic::Severity::Warning);

    std::unique_ptr<Node> derive(const Node& source, std::string_view name, Node* parent);
    void expandArcs(Node& node);
    void addReferenceArc(Node& node, const Reference& ref, Arc arc);
    void addClassArc(Node& node, const PathItem& item, Arc arc);
    std::unique_ptr<Node> buildSubrootIndex(const LayerStack* stack, const std::string& target,
                                            const SourceLocation& where);
    /// Pcp's implied inherits/specializes: a class arc inside a referenced asset also picks up
    /// the class at the mapped path in the root layer stack (stronger than the asset's class).
    void addImpliedClassArc(const Node& node, const std::string& target, Arc arc,
                            const SourceLocation& where);
    bool reportCycle(const Node& from, const LayerStack* stack, const std::string& site,
                     const SourceLocation& where, const char* arcName);
    bool reserveNode(const Node& parent, const SourceLocation& where);
    void expandVariants(Node& root, const std::string& primPath,
                        std::map<std::string, std::string>& used);
    std::string selectVariant(Node& root, const std::string& primPath, const std::string& set);

    static std::vector<Node*> strengthOrder(Node& root);
    static std::vector<const PrimSpec*> specsAt(const Node& node);
    std::vector<SpecRef> gatherSpecs(const std::vector<Node*>& order) const;
    /// Child prim names in Pcp order: weakest opinion first, stronger ones append new names,
    /// then every nameChildrenOrder reorders.
    static std::vector<std::string> childNamesOf(const std::vector<SpecRef>& specsStrongFirst);
    static std::string instanceKey(const std::vector<Node*>& order,
                                   const std::map<std::string, std::string>& used);
    std::optional<std::string> mapToStage(const Node& node, const std::string& path) const;
    std::vector<std::string> composeTargets(
        const std::vector<std::pair<const ListOp<PathItem>*, const SpecRef*>>& opsStrongFirst);

    void composeChildren(Prim& parent, Node* parentIndex, const std::vector<std::string>& names,
                         int depth);
    void composePrim(Prim& prim, Node& index, const std::map<std::string, std::string>& used,
                     std::vector<std::string>& childNames);

    Stage& _stage;
    const StageOptions& _options;
    std::map<std::string, std::unique_ptr<Layer>> _layers;  ///< by absolute path
    std::vector<std::unique_ptr<Layer>> _anonymous;
    std::map<const Layer*, std::unique_ptr<LayerStack>> _stacks;
    const LayerStack* _rootStack = nullptr;
    Node* _indexRoot = nullptr;
    std::size_t _nodeCount = 0;
    bool _primLimitHit = false;
    std::set<std::string> _reported;
    /// Sub-root reference targets whose index is being built (cycle detection across them).
    std::vector<std::pair<const LayerStack*, std::string>> _building;
};

}  // namespace principled::usd
