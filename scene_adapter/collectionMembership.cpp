// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/collectionMembership.h"

#include <algorithm>

#include "scene_adapter/usda/prim.h"
#include "scene_adapter/usda/stage.h"

namespace principled::adapter {
namespace {

constexpr std::string_view kCollectionMarker = ".collection:";

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
    const size_t at = path.find(kCollectionMarker);
    if (at == std::string_view::npos || at == 0 || path[0] != '/') return false;
    const std::string_view n = path.substr(at + kCollectionMarker.size());
    if (n.empty() || n.find_first_of(":./") != std::string_view::npos) return false;
    *prim = std::string(path.substr(0, at));
    *name = std::string(n);
    return true;
}

CollectionMembership::CollectionMembership(const usd::Stage& stage, std::string_view collectionPath,
                                           const WarnFn& warn, bool includeRootFallback) {
    std::vector<std::string> visiting;
    addCollection(stage, collectionPath, warn, &visiting, includeRootFallback);
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

void CollectionMembership::addCollection(const usd::Stage& stage, std::string_view collectionPath,
                                         const WarnFn& warn, std::vector<std::string>* visiting,
                                         bool includeRootFallback) {
    std::string primPath, name;
    if (!splitCollectionPath(collectionPath, &primPath, &name)) {
        warn(std::string(collectionPath), "not a collection path (expected </Prim.collection:name>)");
        return;
    }
    if (std::find(visiting->begin(), visiting->end(), collectionPath) != visiting->end()) {
        warn(std::string(collectionPath), "collection includes itself through its includes; the cycle is cut");
        return;
    }
    const usd::Prim* prim = stage.prim(primPath);
    if (!prim) {
        warn(std::string(collectionPath), "the collection's prim does not exist; it includes nothing");
        return;
    }
    visiting->emplace_back(collectionPath);
    const std::string prefix = "collection:" + name + ":";
    const std::string rule = tokenValue(*prim, prefix + "expansionRule", "expandPrims");
    Rule own = Rule::ExpandPrims;
    if (rule == "explicitOnly")
        own = Rule::ExplicitOnly;
    else if (rule != "expandPrims" && rule != "expandPrimsAndProperties")
        warn(prim->path(), "collection '" + name + "' has expansionRule '" + rule +
                               "' (expected explicitOnly, expandPrims or expandPrimsAndProperties); expandPrims is used");
    const usd::Relationship* includes = prim->relationship(prefix + "includes");
    const usd::Relationship* excludes = prim->relationship(prefix + "excludes");
    bool includeRoot = includeRootFallback;
    if (const usd::Attribute* a = prim->attribute(prefix + "includeRoot"); a && a->hasValue())
        includeRoot = a->get().getBool().value_or(includeRootFallback);
    if (!includes && !excludes && !includeRoot)
        if (const usd::Attribute* e = prim->attribute(prefix + "membershipExpression"); e && e->hasValue())
            warn(e->location().str() + ": " + prim->path(),
                 "collection '" + name + "' is defined by a membershipExpression, which is not evaluated; it includes nothing");

    // Included collections first; this collection's own includes, then its excludes, override
    // what they say about the same path.
    std::vector<std::string> direct;
    if (includes)
        for (const std::string& t : includes->targets()) {
            if (t.find(kCollectionMarker) != std::string::npos) {
                CollectionMembership nested;
                nested.addCollection(stage, t, warn, visiting, false);
                for (const auto& [p, r] : nested._rules) _rules.emplace(p, r);
            } else if (t.find('.') == std::string::npos) {
                direct.push_back(t);  // a prim (property targets do not hold prims)
            }
        }
    for (const std::string& p : direct) _rules[p] = own;
    if (includeRoot) _rules["/"] = own;
    if (excludes)
        for (const std::string& t : excludes->targets())
            if (t.find('.') == std::string::npos) _rules[t] = Rule::Exclude;
    visiting->pop_back();
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
