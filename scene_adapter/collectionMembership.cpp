// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/collectionMembership.h"

#include <algorithm>

#include "scene_adapter/usda/prim.h"
#include "scene_adapter/usda/stage.h"

namespace principled::adapter {
namespace {

std::string parentPath(std::string_view path) {
    const size_t slash = path.rfind('/');
    if (slash == std::string_view::npos || path.size() <= 1) return "";
    return slash == 0 ? "/" : std::string(path.substr(0, slash));
}

std::string tokenValue(const usd::Prim& prim, const std::string& name, const std::string& fallback) {
    const usd::Attribute* a = prim.attribute(name);
    if (!a || !a->hasValue()) return fallback;
    return a->get().getString().value_or(fallback);
}

}  // namespace

bool CollectionMembership::splitCollectionPath(std::string_view path, std::string* prim, std::string* name) {
    const size_t at = path.find(kMarker);
    if (at == std::string_view::npos || at == 0 || path[0] != '/') return false;
    const std::string_view n = path.substr(at + kMarker.size());
    if (n.empty() || n.find_first_of(":./") != std::string_view::npos) return false;
    *prim = std::string(path.substr(0, at));
    *name = std::string(n);
    return true;
}

struct CollectionMembership::Build {
    const usd::Stage& stage;
    const WarnFn& warn;
    std::unordered_map<std::string, RuleMap> done;     ///< collection path -> its rule map
    std::unordered_map<std::string, bool> inProgress;  ///< collections on the current path
};

CollectionMembership::CollectionMembership(const usd::Stage& stage, std::string_view collectionPath,
                                           const WarnFn& warn, bool includeRootFallback) {
    Build b{stage, warn, {}, {}};
    _rules = ruleMap(b, std::string(collectionPath), includeRootFallback, 0);
}

bool CollectionMembership::holdsEverything(const usd::Stage& stage, std::string_view collectionPath) {
    std::string primPath, name;
    if (!splitCollectionPath(collectionPath, &primPath, &name)) return false;
    const usd::Prim* prim = stage.prim(primPath);
    if (!prim) return false;
    const std::string prefix = "collection:" + name + ":";
    for (const char* rel : {"includes", "excludes"})
        if (const usd::Relationship* r = prim->relationship(prefix + rel); r && !r->targets().empty()) return false;
    if (const usd::Attribute* a = prim->attribute(prefix + "includeRoot"); a && a->hasValue() &&
                                                                           !a->get().getBool().value_or(true))
        return false;
    if (const usd::Attribute* e = prim->attribute(prefix + "membershipExpression"); e && e->hasValue()) return false;
    return tokenValue(*prim, prefix + "expansionRule", "expandPrims") != "explicitOnly";
}

const CollectionMembership::RuleMap& CollectionMembership::ruleMap(Build& b, const std::string& collectionPath,
                                                                 bool includeRootFallback, int depth) {
    static const RuleMap kEmpty;
    if (auto it = b.done.find(collectionPath); it != b.done.end()) return it->second;
    std::string primPath, name;
    if (!splitCollectionPath(collectionPath, &primPath, &name)) {
        b.warn(collectionPath, "not a collection path (expected </Prim.collection:name>)");
        return kEmpty;
    }
    if (b.inProgress.count(collectionPath)) {
        b.warn(collectionPath, "collection includes itself through its includes; the cycle is cut");
        return kEmpty;
    }
    if (depth >= kMaxNesting) {
        b.warn(collectionPath, "collections nested more than " + std::to_string(kMaxNesting) +
                                   " deep; the deeper ones are left out");
        return kEmpty;
    }
    const usd::Prim* prim = b.stage.prim(primPath);
    if (!prim) {
        b.warn(collectionPath, "the collection's prim does not exist; it includes nothing");
        return kEmpty;
    }
    b.inProgress[collectionPath] = true;
    const std::string prefix = "collection:" + name + ":";
    const std::string rule = tokenValue(*prim, prefix + "expansionRule", "expandPrims");
    Rule own = Rule::ExpandPrims;
    if (rule == "explicitOnly")
        own = Rule::ExplicitOnly;
    else if (rule != "expandPrims" && rule != "expandPrimsAndProperties")
        b.warn(prim->path(), "collection '" + name + "' has expansionRule '" + rule +
                                 "' (expected explicitOnly, expandPrims or expandPrimsAndProperties); expandPrims is used");
    const usd::Relationship* includes = prim->relationship(prefix + "includes");
    const usd::Relationship* excludes = prim->relationship(prefix + "excludes");
    bool includeRoot = includeRootFallback;
    if (const usd::Attribute* a = prim->attribute(prefix + "includeRoot"); a && a->hasValue())
        includeRoot = a->get().getBool().value_or(includeRootFallback);
    if (!includes && !excludes && !includeRoot)
        if (const usd::Attribute* e = prim->attribute(prefix + "membershipExpression"); e && e->hasValue())
            b.warn(e->location().str() + ": " + prim->path(),
                   "collection '" + name + "' is defined by a membershipExpression, which is not evaluated; it includes nothing");

    // UsdCollectionAPI's order: the root, then the includes in order (an included
    // collection's rules overwrite what came before, as a path listed there does), then the
    // excludes.
    RuleMap rules;
    if (includeRoot) rules["/"] = own;
    if (includes)
        for (const std::string& t : includes->targets()) {
            if (isCollectionPath(t)) {
                // UsdLux declares includeRoot true for lightLink and shadowLink collections.
                std::string nestedPrim, nestedName;
                const bool luxLink = splitCollectionPath(t, &nestedPrim, &nestedName) &&
                                     (nestedName == "lightLink" || nestedName == "shadowLink");
                for (const auto& [p, r] : ruleMap(b, t, luxLink, depth + 1)) rules[p] = r;
            } else if (t.find('.') == std::string::npos) {
                rules[t] = own;  // a prim (property targets do not hold prims)
            }
        }
    if (excludes)
        for (const std::string& t : excludes->targets())
            if (t.find('.') == std::string::npos) rules[t] = Rule::Exclude;
    b.inProgress.erase(collectionPath);
    return b.done[collectionPath] = std::move(rules);
}

bool CollectionMembership::includes(std::string_view primPath) const {
    if (primPath.empty() || primPath == "/" || _rules.empty()) return false;
    for (std::string p(primPath); !p.empty(); p = parentPath(p)) {
        const auto it = _rules.find(p);
        if (it == _rules.end()) continue;
        switch (it->second) {
            case Rule::Exclude: return false;
            case Rule::ExplicitOnly: return p.size() == primPath.size();
            case Rule::ExpandPrims: return true;
        }
    }
    return false;
}

}  // namespace principled::adapter
