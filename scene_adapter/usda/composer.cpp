// SPDX-License-Identifier: Apache-2.0
// Follows the structure of Pcp (pxr/usd/pcp/primIndex.cpp) in a much reduced form: no
// relocations, no instancing (instanceable prims are expanded like any other), implied class
// arcs only into the root layer stack, ancestral arcs before direct arcs of the same kind.
#include "scene_adapter/usda/composer.h"

#include <cmath>

#include <algorithm>
#include <filesystem>
#include <unordered_set>

#include "scene_adapter/usda/assetResolver.h"
#include "scene_adapter/usda/parser.h"
#include "scene_adapter/usda/path.h"

namespace principled::usd {

namespace {
// Nodes one prim index may hold: far above real assets (tens), low enough that an adversarial
// diamond of references cannot exhaust memory.
constexpr std::size_t kMaxNodesPerPrim = 1024;
// Arcs nested inside arcs (a reference of a reference of ...), and composed namespace depth:
// both bound the composer's recursion so that chained layers cannot overflow the stack.
constexpr int kMaxArcDepth = 256;
constexpr int kMaxNamespaceDepth = 1024;

std::string describeSite(const LayerStack* stack, std::string_view site) {
    return stack->identifier + "<" + std::string(site) + ">";
}

// Adds a weaker opinion of metadata field `key`: the stronger value stays, except that
// dictionaries (customData, assetInfo, ...) merge key by key, as Sdf composes them.
void composeField(Dictionary& out, const std::string& key, const Value& weaker) {
    auto [it, inserted] = out.emplace(key, weaker);
    if (inserted) return;
    const Dictionary* strong = it->second.dictionary();
    const Dictionary* weak = weaker.dictionary();
    if (!strong || !weak) return;
    Dictionary merged = *strong;
    for (const auto& [k, v] : *weak) composeField(merged, k, v);
    it->second = Value::dictionary(std::move(merged), it->second.location());
}

// [inner..., outer...]: a mapping through `inner`, then through `outer`.
std::shared_ptr<const std::vector<MapStep>> chain(std::vector<MapStep> inner,
                                                  const std::vector<MapStep>& outer) {
    inner.insert(inner.end(), outer.begin(), outer.end());
    return std::make_shared<const std::vector<MapStep>>(std::move(inner));
}

template <class T, class Get>
std::vector<T> composeListOp(const std::vector<const PrimSpec*>& strongFirst, Get get) {
    std::vector<T> result;
    for (auto it = strongFirst.rbegin(); it != strongFirst.rend(); ++it) get(**it).applyTo(result);
    return result;
}
}  // namespace

bool LayerStack::hasPrim(std::string_view site) const {
    for (const Layer* layer : layers)
        if (layer->prim(site)) return true;
    return false;
}

void PrimIndexNode::addChild(std::unique_ptr<PrimIndexNode> child) {
    child->parent = this;
    auto pos = std::find_if(children.begin(), children.end(),
                            [&](const auto& c) { return c->arc > child->arc; });
    children.insert(pos, std::move(child));
}

Composer::Composer(Stage& stage, const StageOptions& options) : _stage(stage), _options(options) {}
Composer::~Composer() = default;

void Composer::warn(const SourceLocation& where, std::string message,
                    Diagnostic::Severity severity) {
    Diagnostic d{where, std::move(message), severity};
    if (_reported.insert(d.str()).second) _stage._warnings.push_back(std::move(d));
}

const Layer* Composer::loadLayer(const std::string& absolutePath, const std::string& displayName) {
    auto it = _layers.find(absolutePath);
    if (it != _layers.end()) return it->second.get();
    if (_layers.size() + _anonymous.size() >= _options.maxLayers)
        throw Error({displayName, 0, 0}, "too many layers (StageOptions::maxLayers = " +
                                             std::to_string(_options.maxLayers) + ")");
    std::string text = readLayerText(absolutePath);
    std::unique_ptr<Layer> layer = parseLayer(text, displayName, directoryOf(absolutePath));
    const Layer* raw = layer.get();
    _layers.emplace(absolutePath, std::move(layer));
    _stage._layerFiles.push_back(displayName);
    return raw;
}

const LayerStack* Composer::loadStack(const Layer* root) {
    auto it = _stacks.find(root);
    if (it != _stacks.end()) return it->second.get();
    auto stack = std::make_unique<LayerStack>();
    stack->identifier = root->file;
    std::vector<const Layer*> chain;
    addToStack(*stack, root, LayerOffset{}, chain);
    const LayerStack* raw = stack.get();
    _stacks.emplace(root, std::move(stack));
    return raw;
}

namespace {

// A layer's time codes per second: timeCodesPerSecond, else framesPerSecond, else 24 (the
// fallbacks UsdStage uses for the root layer; Pcp applies the same to every layer stack).
double timeCodesPerSecond(const Layer& layer) {
    for (const char* key : {"timeCodesPerSecond", "framesPerSecond"})
        if (const Value* v = layer.field(key))
            if (auto d = v->getDouble(); d && std::isfinite(*d) && *d > 0.0) return *d;
    return 24.0;
}

// The authored offset of an arc (sublayer or reference) from a layer at `innerTcps` into one
// at `outerTcps`: Pcp multiplies its scale by the ratio, so one second stays one second.
LayerOffset withTimeScale(LayerOffset authored, double outerTcps, double innerTcps) {
    authored.scale *= outerTcps / innerTcps;
    return authored;
}

}  // namespace

void Composer::addToStack(LayerStack& stack, const Layer* layer, LayerOffset offset,
                          std::vector<const Layer*>& chain) {
    stack.layers.push_back(layer);
    stack.offsets.push_back(offset);
    chain.push_back(layer);
    if (const Value* r = layer->field("relocates"))
        warn(r->location(), "relocates are not applied (prims stay where their specs put them)");
    for (const SubLayer& sub : layer->subLayers) {
        if (sub.resolvedPath.empty()) {
            warn(sub.location, "sublayer @" + sub.assetPath + "@ not found (relative to " +
                                   layer->anchorDir + ")");
            continue;
        }
        const Layer* subLayer = nullptr;
        try {
            subLayer = loadLayer(sub.resolvedPath, sub.resolvedPath);
        } catch (const Error& e) {
            warn(sub.location, "cannot load sublayer @" + sub.assetPath + "@: " + e.what(),
                 Diagnostic::Severity::Error);
            continue;
        }
        if (std::find(chain.begin(), chain.end(), subLayer) != chain.end()) {
            std::string cycle;
            for (const Layer* l : chain) cycle += l->file + " -> ";
            warn(sub.location, "sublayer cycle: " + cycle + subLayer->file,
                 Diagnostic::Severity::Error);
            continue;
        }
        LayerOffset subOffset = sub.offset;
        if (!subOffset.valid()) {  // PcpErrorInvalidSublayerOffset
            warn(sub.location, "invalid sublayer offset (" + subOffset.str() + ") for @" + sub.assetPath +
                                   "@: using no offset instead");
            subOffset = LayerOffset{};
        }
        addToStack(stack, subLayer,
                   offset.compose(withTimeScale(subOffset, timeCodesPerSecond(*layer), timeCodesPerSecond(*subLayer))),
                   chain);
    }
    chain.pop_back();
}

void Composer::composeFile(const std::string& path) {
    std::error_code ec;
    std::string absolute = std::filesystem::absolute(path, ec).lexically_normal().string();
    if (ec) absolute = path;
    compose(loadLayer(absolute, path));
}

void Composer::composeText(std::string_view text, const std::string& displayName) {
    _anonymous.push_back(parseLayer(text, displayName, currentDirectory()));
    _stage._layerFiles.push_back(displayName);
    compose(_anonymous.back().get());
}

void Composer::compose(const Layer* rootLayer) {
    Stage& s = _stage;
    s._layerMetadata = rootLayer->metadata;
    s._defaultPrim = rootLayer->defaultPrim();
    if (const Value* v = rootLayer->field("upAxis"))
        if (auto t = v->getString()) s._upAxis = *t;
    auto number = [&](const char* key, double& out, bool* authored) {
        if (const Value* v = rootLayer->field(key))
            if (auto d = v->getDouble()) {
                out = *d;
                if (authored) *authored = true;
            }
    };
    number("metersPerUnit", s._metersPerUnit, nullptr);
    number("startFrame", s._startTimeCode, &s._hasStart);  // legacy names (SdfLayer fallbacks)
    number("endFrame", s._endTimeCode, &s._hasEnd);
    number("startTimeCode", s._startTimeCode, &s._hasStart);
    number("endTimeCode", s._endTimeCode, &s._hasEnd);
    number("framesPerSecond", s._framesPerSecond, nullptr);
    s._timeCodesPerSecond = s._framesPerSecond;
    number("timeCodesPerSecond", s._timeCodesPerSecond, nullptr);

    _rootStack = loadStack(rootLayer);

    auto root = std::make_unique<Prim>();
    root->_path = "/";
    root->_defined = true;
    root->_location = {rootLayer->file, 0, 0};
    Prim* rootPrim = root.get();
    s._root = rootPrim;
    s._index["/"] = rootPrim;
    s._prims.push_back(std::move(root));

    std::vector<std::string> names;
    std::unordered_set<std::string> seen;
    for (auto it = _rootStack->layers.rbegin(); it != _rootStack->layers.rend(); ++it)
        for (const auto& p : (*it)->rootPrims)
            if (seen.insert(p->name).second) names.push_back(p->name);
    for (auto it = _rootStack->layers.rbegin(); it != _rootStack->layers.rend(); ++it)
        if ((*it)->rootPrimOrder) {
            ListOp<std::string> op;
            op.set(ListOpKind::Reorder, *(*it)->rootPrimOrder);
            op.applyTo(names);
        }
    composeChildren(*rootPrim, nullptr, names, 1);
}

std::unique_ptr<PrimIndexNode> Composer::derive(const Node& source, std::string_view name,
                                                Node* parent) {
    auto n = std::make_unique<Node>();
    n->stack = source.stack;
    n->site = path::child(source.site, name);
    n->arc = source.arc;
    n->map = source.map;
    n->offset = source.offset;
    n->arcLocation = source.arcLocation;
    n->inert = source.inert;
    n->parent = parent;
    for (const auto& c : source.children)
        if (auto d = derive(*c, name, n.get())) n->children.push_back(std::move(d));
    if (parent && n->children.empty() && (n->inert || !n->stack->hasPrim(n->site))) return nullptr;
    ++_nodeCount;
    return n;
}

std::vector<const PrimSpec*> Composer::specsAt(const Node& node) {
    std::vector<const PrimSpec*> out;
    if (node.inert) return out;  // an instance's own opinions on its descendants
    for (const Layer* layer : node.stack->layers)
        if (const PrimSpec* s = layer->prim(node.site)) out.push_back(s);
    return out;
}

bool Composer::reserveNode(const Node& parent, const SourceLocation& where) {
    int depth = 0;
    for (const Node* n = &parent; n; n = n->parent) ++depth;
    if (depth >= kMaxArcDepth) {
        warn(where,
             "composition arcs nested more than " + std::to_string(kMaxArcDepth) +
                 " deep; further arcs are ignored",
             Diagnostic::Severity::Error);
        return false;
    }
    if (++_nodeCount <= kMaxNodesPerPrim) return true;
    warn(where,
         "composition too complex: more than " + std::to_string(kMaxNodesPerPrim) +
             " arcs contribute to one prim; further arcs are ignored",
         Diagnostic::Severity::Error);
    return false;
}

void Composer::expandArcs(Node& node) {
    std::vector<const PrimSpec*> specs = specsAt(node);
    if (specs.empty()) return;
    for (const PathItem& item : composeListOp<PathItem>(
             specs, [](const PrimSpec& s) -> auto& { return s.inherits; }))
        addClassArc(node, item, Arc::Inherit);
    for (const Reference& r : composeListOp<Reference>(
             specs, [](const PrimSpec& s) -> auto& { return s.references; }))
        addReferenceArc(node, r, Arc::Reference);
    if (_options.loadPayloads)
        for (const Reference& r : composeListOp<Reference>(
                 specs, [](const PrimSpec& s) -> auto& { return s.payloads; }))
            addReferenceArc(node, r, Arc::Payload);
    for (const PathItem& item : composeListOp<PathItem>(
             specs, [](const PrimSpec& s) -> auto& { return s.specializes; }))
        addClassArc(node, item, Arc::Specialize);
}

bool Composer::reportCycle(const Node& from, const LayerStack* stack, const std::string& site,
                           const SourceLocation& where, const char* arcName) {
    for (const Node* a = &from; a; a = a->parent) {
        if (a->stack != stack) continue;
        std::string as = path::stripVariants(a->site);
        if (!path::hasPrefix(as, site) && !path::hasPrefix(site, as)) continue;
        std::vector<const Node*> chain;
        for (const Node* b = &from; b; b = b->parent) {
            chain.push_back(b);
            if (b == a) break;
        }
        std::string text;
        for (auto it = chain.rbegin(); it != chain.rend(); ++it)
            text += describeSite((*it)->stack, path::stripVariants((*it)->site)) + " -> ";
        text += describeSite(stack, site);
        warn(where, std::string(arcName) + " cycle: " + text, Diagnostic::Severity::Error);
        return true;
    }
    return false;
}

void Composer::addReferenceArc(Node& node, const Reference& ref, Arc arc) {
    const char* what = arc == Arc::Payload ? "payload" : "reference";
    const LayerStack* stack = node.stack;
    std::string label =
        ref.assetPath.empty() ? "<" + ref.primPath + ">" : "@" + ref.assetPath + "@";
    if (!ref.assetPath.empty()) {
        if (ref.resolvedPath.empty()) {
            warn(ref.location, std::string(what) + " " + label +
                                   " not found (relative to the directory of " + ref.location.file +
                                   "); the prim is composed without it");
            return;
        }
        try {
            stack = loadStack(loadLayer(ref.resolvedPath, ref.resolvedPath));
        } catch (const Error& e) {
            warn(ref.location, std::string("cannot load ") + what + " " + label + ": " + e.what(),
                 Diagnostic::Severity::Error);
            return;
        }
    }
    std::string target = ref.primPath;
    if (target.empty()) {
        std::string dp = stack->layers.front()->defaultPrim();
        if (dp.empty()) {
            warn(ref.location, std::string(what) + " " + label +
                                   " names no prim and its layer has no defaultPrim");
            return;
        }
        target = dp[0] == '/' ? dp : "/" + dp;
    }
    if (!stack->hasPrim(target)) {
        warn(ref.location, std::string(what) + " target <" + target + "> not found in " +
                               stack->identifier + "; the prim is composed without it");
        return;
    }
    if (reportCycle(node, stack, target, ref.location, what)) return;
    for (const auto& [buildingStack, buildingSite] : _building)
        if (buildingStack == stack &&
            (path::hasPrefix(buildingSite, target) || path::hasPrefix(target, buildingSite))) {
            warn(ref.location,
                 std::string(what) + " cycle: " + describeSite(stack, target) +
                     " is referenced while composing itself",
                 Diagnostic::Severity::Error);
            return;
        }
    if (!reserveNode(node, ref.location)) return;
    // A prim below the root brings the arcs authored on its ancestors (ancestral opinions).
    bool subroot = path::parent(target) != "/";
    std::unique_ptr<Node> child =
        subroot ? buildSubrootIndex(stack, target, ref.location) : std::make_unique<Node>();
    if (!child) return;
    child->stack = stack;
    child->site = target;
    child->arc = arc;
    // Maps and time offsets of the whole subtree continue through this arc: first the
    // reference (target -> the referencing prim), then the referencing node's own mapping.
    // An internal reference or payload (no asset path) stays in the same layer stack, so paths
    // outside the referenced prim keep their meaning there (Pcp adds the root identity for such
    // arcs, as for class arcs): a binding to a material beside the source prim still resolves.
    std::vector<MapStep> outer{{target, path::stripVariants(node.site), ref.assetPath.empty()}};
    outer.insert(outer.end(), node.map->begin(), node.map->end());
    // Time mapping: the node's, then the offset of the sublayer that authored the arc, then
    // the arc's own (offset; scale).
    LayerOffset authoring;
    const Layer* authoringLayer = node.stack->layers.front();
    for (std::size_t i = 0; i < node.stack->layers.size(); ++i)
        if (node.stack->layers[i]->file == ref.location.file) {
            authoring = node.stack->offsets[i];
            authoringLayer = node.stack->layers[i];
        }
    // Between layers of different time codes per second the arc's scale takes their ratio (the
    // authoring layer's offset already carries its own ratio to the stack's root).
    LayerOffset authored = ref.offset;
    if (!authored.valid()) {  // PcpErrorInvalidReferenceOffset
        warn(ref.location, "invalid " + std::string(what) + " offset (" +
                               authored.str() + "): using no offset instead");
        authored = LayerOffset{};
    }
    const LayerOffset arcOffset = withTimeScale(authored, timeCodesPerSecond(*authoringLayer),
                                                timeCodesPerSecond(*stack->layers.front()));
    LayerOffset offset = node.offset.compose(authoring).compose(arcOffset);
    std::vector<Node*> todo{child.get()};
    while (!todo.empty()) {
        Node* n = todo.back();
        todo.pop_back();
        n->map = chain(*n->map, outer);
        n->offset = offset.compose(n->offset);
        for (const auto& c : n->children) todo.push_back(c.get());
    }
    child->arcLocation = ref.location;
    Node* raw = child.get();
    node.addChild(std::move(child));
    if (!subroot) expandArcs(*raw);
}

std::unique_ptr<PrimIndexNode> Composer::buildSubrootIndex(const LayerStack* stack,
                                                           const std::string& target,
                                                           const SourceLocation& where) {
    // The prim index of `target` inside its own layer stack, built like the stage's: from the
    // root prim down, expanding arcs and variants at each level. Implied classes and variant
    // overrides do not apply inside it, and ancestors' variant selections come from the
    // referenced layer stack only.
    if (_building.size() >= 16) {  // 16: nested sub-root references, far beyond real assets
        warn(where, "references to non-root prims nested too deeply", Diagnostic::Severity::Error);
        return nullptr;
    }
    _building.emplace_back(stack, target);
    Node* savedRoot = _indexRoot;
    _indexRoot = nullptr;
    std::vector<std::string> names;
    for (std::size_t i = 1; i < target.size();) {
        std::size_t j = target.find('/', i);
        if (j == std::string::npos) j = target.size();
        names.push_back(target.substr(i, j - i));
        i = j + 1;
    }
    auto index = std::make_unique<Node>();
    index->stack = stack;
    index->site = "/" + names.front();
    expandArcs(*index);
    std::map<std::string, std::string> used;
    expandVariants(*index, {}, used);
    for (std::size_t i = 1; i < names.size(); ++i) {
        auto derived = derive(*index, names[i], nullptr);
        for (Node* n : strengthOrder(*derived)) expandArcs(*n);
        // The target's own variant sets are left to the referencing prim's index, where
        // stronger opinions (the referencing layers) may select them.
        if (i + 1 < names.size()) {
            used.clear();
            expandVariants(*derived, {}, used);
        }
        index = std::move(derived);
    }
    _indexRoot = savedRoot;
    _building.pop_back();
    return index;
}

void Composer::addImpliedClassArc(const Node& node, const std::string& target, Arc arc,
                                  const SourceLocation& where) {
    // Only arcs seen through a reference or payload have an implied counterpart.
    bool viaReference = false;
    for (const Node* n = &node; n; n = n->parent)
        if (n->arc == Arc::Reference || n->arc == Arc::Payload) viaReference = true;
    if (!viaReference || !_indexRoot) return;
    // Map the class into stage namespace; paths outside the referenced prim are global classes
    // and keep their path (Pcp adds the root identity to reference map functions).
    std::string mapped = target;
    for (const MapStep& step : *node.map)
        if (path::hasPrefix(mapped, step.source))
            mapped = path::replacePrefix(mapped, step.source, step.target);
    if (!_rootStack->hasPrim(mapped)) return;
    for (const Node* n : strengthOrder(*_indexRoot))
        if (n->stack == _rootStack && path::stripVariants(n->site) == mapped) return;
    if (reportCycle(*_indexRoot, _rootStack, mapped, where,
                    arc == Arc::Inherit ? "inherits" : "specializes"))
        return;
    if (!reserveNode(*_indexRoot, where)) return;
    auto child = std::make_unique<Node>();
    child->stack = _rootStack;
    child->site = mapped;
    child->arc = arc;
    child->map = chain({{mapped, _indexRoot->site, true}}, {});
    child->arcLocation = where;
    Node* raw = child.get();
    _indexRoot->addChild(std::move(child));
    expandArcs(*raw);
}

void Composer::addClassArc(Node& node, const PathItem& item, Arc arc) {
    std::string site = path::stripVariants(node.site);
    std::string target = path::makeAbsolute(item.path, site);
    addImpliedClassArc(node, target, arc, item.location);
    if (!node.stack->hasPrim(target)) return;  // a missing class is legal: no opinions
    if (reportCycle(node, node.stack, target, item.location,
                    arc == Arc::Inherit ? "inherits" : "specializes"))
        return;
    if (!reserveNode(node, item.location)) return;
    auto child = std::make_unique<Node>();
    child->stack = node.stack;
    child->site = target;
    child->arc = arc;
    child->map = chain({{target, site, true}}, *node.map);
    child->offset = node.offset;
    child->arcLocation = item.location;
    Node* raw = child.get();
    node.addChild(std::move(child));
    expandArcs(*raw);
}

std::vector<PrimIndexNode*> Composer::strengthOrder(Node& root) {
    std::vector<Node*> out;
    std::vector<Node*> deferred{&root};  // specializes subtrees are weaker than everything else
    for (std::size_t i = 0; i < deferred.size(); ++i) {
        std::vector<Node*> stack{deferred[i]};
        while (!stack.empty()) {
            Node* n = stack.back();
            stack.pop_back();
            out.push_back(n);
            for (auto it = n->children.rbegin(); it != n->children.rend(); ++it) {
                if ((*it)->arc == Arc::Specialize) continue;
                stack.push_back(it->get());
            }
            for (const auto& c : n->children)
                if (c->arc == Arc::Specialize) deferred.push_back(c.get());
        }
    }
    return out;
}

std::string Composer::selectVariant(Node& root, const std::string& primPath,
                                    const std::string& set) {
    auto o = _options.variantOverrides.find(primPath);
    if (o != _options.variantOverrides.end()) {
        auto s = o->second.find(set);
        if (s != o->second.end()) return s->second;
    }
    for (Node* n : strengthOrder(root))
        for (const PrimSpec* spec : specsAt(*n)) {
            auto it = spec->variantSelections.find(set);
            if (it != spec->variantSelections.end()) return it->second;
        }
    return {};
}

void Composer::expandVariants(Node& root, const std::string& primPath,
                              std::map<std::string, std::string>& used) {
    // Each pass expands one variant set (strongest node first), then starts over: the new
    // variant may author selections or sets of its own.
    for (std::size_t pass = 0; pass < kMaxNodesPerPrim; ++pass) {
        bool added = false;
        for (Node* n : strengthOrder(root)) {
            if (n->variantsDone) continue;
            std::vector<const PrimSpec*> specs = specsAt(*n);
            if (!n->variantSetNames)
                n->variantSetNames = composeListOp<std::string>(
                    specs, [](const PrimSpec& s) -> auto& { return s.variantSetNames; });
            while (n->nextVariantSet < n->variantSetNames->size()) {
                const std::string set = (*n->variantSetNames)[n->nextVariantSet++];
                std::string selection = selectVariant(root, primPath, set);
                if (selection.empty()) continue;
                used.emplace(set, selection);
                std::string site = n->site + "{" + set + "=" + selection + "}";
                if (!n->stack->hasPrim(site)) {
                    auto o = _options.variantOverrides.find(primPath);
                    if (o != _options.variantOverrides.end() && o->second.count(set))
                        warn(specs.front()->location, "variant set \"" + set + "\" of " + primPath +
                                                          " has no variant \"" + selection + "\"");
                    continue;
                }
                if (!reserveNode(*n, specs.front()->location)) return;
                auto child = std::make_unique<Node>();
                child->stack = n->stack;
                child->site = site;
                child->arc = Arc::Variant;
                child->map = n->map;
                child->offset = n->offset;
                child->arcLocation = specs.front()->location;
                Node* raw = child.get();
                n->addChild(std::move(child));
                expandArcs(*raw);
                added = true;
                break;
            }
            if (added) break;
            n->variantsDone = true;  // every set of this node is expanded
        }
        if (!added) return;
    }
}

std::string Composer::instanceKey(const std::vector<Node*>& order,
                                  const std::map<std::string, std::string>& used) {
    // Pcp's instance key, simplified: every arc below the prim's own (local) site, with its
    // time mapping, plus the variant selections. Local opinions on the instance prim itself
    // (its transform, say) are not part of what instances share.
    std::string key;
    for (const Node* n : order) {
        if (n->arc == Arc::Root) continue;
        key += std::to_string(static_cast<int>(n->arc)) + "|" + n->stack->identifier + "|" +
               n->site + "|" + std::to_string(n->offset.offset) + "|" +
               std::to_string(n->offset.scale) + "\n";
    }
    for (const auto& [set, selection] : used) key += "{" + set + "=" + selection + "}";
    return key.empty() ? std::string("(no arcs)") : key;
}

std::vector<Composer::SpecRef> Composer::gatherSpecs(const std::vector<Node*>& order) const {
    std::vector<SpecRef> out;
    for (const Node* n : order)
        for (std::size_t i = 0; i < n->stack->layers.size() && !n->inert; ++i)
            if (const PrimSpec* s = n->stack->layers[i]->prim(n->site))
                out.push_back({s, n, n->offset.compose(n->stack->offsets[i])});
    return out;
}

std::optional<std::string> Composer::mapToStage(const Node& node, const std::string& p) const {
    std::string out = p;
    for (const MapStep& step : *node.map) {
        if (path::hasPrefix(out, step.source)) {
            out = path::replacePrefix(out, step.source, step.target);
        } else if (!step.identityFallback) {
            return std::nullopt;
        }
    }
    return out;
}

std::vector<std::string> Composer::composeTargets(
    const std::vector<std::pair<const ListOp<PathItem>*, const SpecRef*>>& opsStrongFirst) {
    std::vector<std::string> result;
    for (auto it = opsStrongFirst.rbegin(); it != opsStrongFirst.rend(); ++it) {
        const ListOp<PathItem>& op = *it->first;
        const Node& node = *it->second->node;
        std::string anchor = path::stripVariants(node.site);
        auto mapList = [&](const std::vector<PathItem>& items) {
            std::vector<std::string> out;
            for (const PathItem& item : items) {
                auto mapped = mapToStage(node, path::makeAbsolute(item.path, anchor));
                if (mapped) {
                    out.push_back(std::move(*mapped));
                } else {
                    warn(item.location, "target <" + item.path +
                                            "> lies outside the referenced prim and is dropped");
                }
            }
            return out;
        };
        ListOp<std::string> mapped;
        mapped.isExplicit = op.isExplicit;
        mapped.explicitItems = mapList(op.explicitItems);
        mapped.added = mapList(op.added);
        mapped.prepended = mapList(op.prepended);
        mapped.appended = mapList(op.appended);
        mapped.deleted = mapList(op.deleted);
        mapped.ordered = mapList(op.ordered);
        mapped.applyTo(result);
    }
    return result;
}

void Composer::composePrim(Prim& prim, Node& index, const std::map<std::string, std::string>& used,
                           std::vector<std::string>& childNames) {
    std::vector<Node*> order = strengthOrder(index);
    std::vector<SpecRef> specs = gatherSpecs(order);

    // Specifier: the strongest def/class opinion. A class reached through an inherit or
    // specializes arc is the thing being inherited, not an abstract prim.
    const SpecRef* defining = nullptr;
    for (const SpecRef& s : specs) {
        if (s.spec->isVariant || s.spec->specifier == Specifier::Over) continue;
        defining = &s;
        break;
    }
    if (defining) {
        prim._defined = true;
        bool viaClassArc = false;
        for (const Node* n = defining->node; n; n = n->parent)
            if (n->arc == Arc::Inherit || n->arc == Arc::Specialize) viaClassArc = true;
        if (defining->spec->specifier == Specifier::Class && !viaClassArc) prim._abstract = true;
        prim._location = defining->spec->location;
    } else if (!specs.empty()) {
        prim._location = specs.front().spec->location;
    }
    if (prim._parent && prim._parent->isAbstract()) prim._abstract = true;
    for (const SpecRef& s : specs)
        if (!s.spec->typeName.empty()) {
            prim._typeName = s.spec->typeName;
            break;
        }
    for (const SpecRef& s : specs)
        for (const auto& [key, value] : s.spec->metadata) composeField(prim._metadata, key, value);
    if (const Value* r = prim.metadata("relocates"))
        warn(r->location(), "relocates are not applied (prims stay where their specs put them)");
    for (const char* key : {"clips", "clipSets"})
        if (const Value* c = prim.metadata(key))
            warn(c->location(), std::string(key) + " (value clips) are not applied: " + prim.path() +
                                    " and its descendants keep the values their layers author, not the clips' animation");
    if (const Value* active = prim.metadata("active"))
        if (auto b = active->getBool()) prim._active = *b;
    if (prim._parent && !prim._parent->isActive()) prim._active = false;
    std::vector<const PrimSpec*> strongFirst;
    for (const SpecRef& s : specs) strongFirst.push_back(s.spec);
    prim._appliedSchemas = composeListOp<std::string>(
        strongFirst, [](const PrimSpec& s) -> auto& { return s.apiSchemas; });
    prim._variantSelections = used;
    if (const Value* inst = prim.metadata("instanceable"))
        if (inst->getBool().value_or(false)) prim._instanceKey = instanceKey(order, used);

    // Properties: every opinion of each name, strongest first.
    std::map<std::string, std::vector<std::pair<const AttributeSpec*, const SpecRef*>>> attrs;
    std::map<std::string, std::vector<std::pair<const RelationshipSpec*, const SpecRef*>>> rels;
    for (const SpecRef& s : specs) {
        for (const AttributeSpec& a : s.spec->attributes) attrs[a.name].push_back({&a, &s});
        for (const RelationshipSpec& r : s.spec->relationships) rels[r.name].push_back({&r, &s});
    }
    for (const auto& [name, opinions] : attrs) {
        auto attr = std::make_unique<Attribute>();
        const AttributeSpec& top = *opinions.front().first;
        attr->_name = name;
        attr->_typeName = top.typeName;
        attr->_isArray = top.isArray;
        attr->_uniform = top.variability == Variability::Uniform;
        attr->_custom = top.custom;
        attr->_location = top.location;
        std::size_t defaultAt = opinions.size(), samplesAt = opinions.size();
        std::size_t animationBlockAt = opinions.size();
        std::vector<std::pair<const ListOp<PathItem>*, const SpecRef*>> connections;
        for (std::size_t i = 0; i < opinions.size(); ++i) {
            const AttributeSpec& a = *opinions[i].first;
            if (defaultAt == opinions.size() && a.defaultValue) defaultAt = i;
            if (samplesAt == opinions.size() && a.hasTimeSamples) samplesAt = i;
            if (animationBlockAt == opinions.size() && a.animationBlock) animationBlockAt = i;
            if (a.hasConnections && a.connections) connections.push_back({a.connections.get(), opinions[i].second});
            for (const auto& [key, value] : a.metadata) composeField(attr->_metadata, key, value);
        }
        if (defaultAt < opinions.size()) attr->_default = *opinions[defaultAt].first->defaultValue;
        // Value resolution (UsdAttribute::Get): per opinion, time samples before the default;
        // so samples win unless a strictly stronger opinion authored a default or an
        // AnimationBlock (which hides weaker samples but lets a weaker default through).
        if (samplesAt < opinions.size() && samplesAt <= defaultAt &&
            samplesAt <= animationBlockAt) {
            const LayerOffset& off = opinions[samplesAt].second->offset;
            for (const auto& [t, v] : opinions[samplesAt].first->timeSamples)
                attr->_samples.emplace(off.apply(t), v);
        }
        if (!connections.empty()) attr->_connections = composeTargets(connections);
        prim._attributes.push_back(attr.get());
        prim._attributeStore.push_back(std::move(attr));
    }
    for (const auto& [name, opinions] : rels) {
        auto rel = std::make_unique<Relationship>();
        rel->_name = name;
        rel->_location = opinions.front().first->location;
        std::vector<std::pair<const ListOp<PathItem>*, const SpecRef*>> targets;
        for (const auto& [r, s] : opinions) {
            if (r->hasTargets) targets.push_back({&r->targets, s});
            for (const auto& [key, value] : r->metadata) composeField(rel->_metadata, key, value);
        }
        rel->_targets = composeTargets(targets);
        prim._relationships.push_back(rel.get());
        prim._relationshipStore.push_back(std::move(rel));
    }

    childNames = childNamesOf(specs);
}

std::vector<std::string> Composer::childNamesOf(const std::vector<SpecRef>& specs) {
    std::vector<std::string> names;
    std::unordered_set<std::string> seen;
    for (auto it = specs.rbegin(); it != specs.rend(); ++it)
        for (const auto& c : it->spec->children)
            if (seen.insert(c->name).second) names.push_back(c->name);
    for (auto it = specs.rbegin(); it != specs.rend(); ++it)
        if (it->spec->nameChildrenOrder) {
            ListOp<std::string> op;
            op.set(ListOpKind::Reorder, *it->spec->nameChildrenOrder);
            op.applyTo(names);
        }
    return names;
}

void Composer::composeChildren(Prim& parent, Node* parentIndex,
                               const std::vector<std::string>& names, int depth) {
    if (!names.empty() && depth > kMaxNamespaceDepth) {
        warn(parent._location,
             "namespace deeper than " + std::to_string(kMaxNamespaceDepth) + " levels below " +
                 parent._path + "; children are ignored",
             Diagnostic::Severity::Error);
        return;
    }
    for (const std::string& name : names) {
        if (_stage._prims.size() >= _options.maxPrims) {
            if (!_primLimitHit)
                warn(parent._location,
                     "too many prims (StageOptions::maxPrims = " +
                         std::to_string(_options.maxPrims) +
                         "); the rest of the stage is not composed",
                     Diagnostic::Severity::Error);
            _primLimitHit = true;
            return;
        }
        std::string primPath = path::child(parent._path, name);
        _nodeCount = 0;
        std::unique_ptr<Node> index;
        std::vector<Node*> existing;  // the nodes before this prim's own arcs
        if (parentIndex) {
            index = derive(*parentIndex, name, nullptr);
            // Arcs authored at this level, on every node the ancestral arcs brought in.
            existing = strengthOrder(*index);
            _indexRoot = index.get();
            for (Node* n : existing) expandArcs(*n);
        } else {
            index = std::make_unique<Node>();
            index->stack = _rootStack;
            index->site = primPath;
            _indexRoot = index.get();
            existing = {index.get()};
            expandArcs(*index);
        }
        std::map<std::string, std::string> used;
        expandVariants(*index, primPath, used);

        auto prim = std::make_unique<Prim>();
        prim->_path = primPath;
        prim->_name = name;
        prim->_parent = &parent;
        std::vector<std::string> childNames;
        composePrim(*prim, *index, used, childNames);
        if (prim->isInstance()) {
            // A prim tagged instanceable is an instance only when an arc of its own (not its
            // ancestors') brings in what instances share (Pcp_PrimIndexIsInstanceable); else it
            // is an ordinary prim.
            const std::unordered_set<const Node*> before(existing.begin(), existing.end());
            bool direct = false;
            for (const Node* n : strengthOrder(*index)) direct = direct || !before.count(n);
            if (!direct) {
                prim->_instanceKey.clear();
            } else {
                // Scenegraph instancing: an instance's descendants come from its arcs alone;
                // what its own layer stacks say about them is ignored (so instances of one
                // prototype agree, whichever of them is drawn as the prototype).
                for (Node* n : existing) n->inert = true;
                childNames = childNamesOf(gatherSpecs(strengthOrder(*index)));
            }
        }
        Prim* raw = prim.get();
        parent._children.push_back(raw);
        _stage._index[primPath] = raw;
        _stage._prims.push_back(std::move(prim));
        if (raw->_active) composeChildren(*raw, index.get(), childNames, depth + 1);
    }
}

}  // namespace principled::usd
