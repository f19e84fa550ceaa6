// SPDX-License-Identifier: Apache-2.0
// UsdCollectionAPI membership: which prims a collection ("/Prim.collection:name") holds, from
// its includes / excludes relationships, expansionRule, includeRoot and the collections it
// includes. Used by collection-based material bindings (scene_adapter/materialBinding.h).
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace principled::usd {
class Stage;
}

namespace principled::adapter {

class CollectionMembership {
public:
    /// How an included path brings in what lies below it (UsdCollectionAPI expansionRule).
    enum class Rule { ExplicitOnly, ExpandPrims, Exclude };
    using WarnFn = std::function<void(const std::string& where, const std::string& message)>;

    CollectionMembership() = default;
    /// The collection at `collectionPath` ("/A/B.collection:name"). A path that is not a
    /// collection, a prim that does not exist, a cycle of included collections or a
    /// membershipExpression (not evaluated here) are reported through warn; what cannot be
    /// read includes nothing.
    /// includeRootFallback: includeRoot when not authored (UsdLux's lightLink and shadowLink
    /// collections declare true: a light lights everything until told otherwise).
    CollectionMembership(const usd::Stage& stage, std::string_view collectionPath, const WarnFn& warn,
                         bool includeRootFallback = false);

    /// Whether the collection holds every prim because nothing restricts it: not authored
    /// beyond includeRoot = the fallback true (then includes() is true for every prim).
    static bool holdsEverything(const usd::Stage& stage, std::string_view collectionPath);

    /// Whether the prim at `primPath` is a member: the nearest entry on the path or an
    /// ancestor decides (an exclude excludes; an explicitOnly include counts only for the path
    /// itself; an expandPrims include counts for everything below). The pseudo-root is never a
    /// member.
    bool includes(std::string_view primPath) const;

    /// What separates a collection's prim from its name in a collection path.
    static constexpr std::string_view kMarker = ".collection:";
    /// Whether a relationship target names a collection ("/A/B.collection:name").
    static bool isCollectionPath(std::string_view path) { return path.find(kMarker) != std::string_view::npos; }
    /// Splits "/A/B.collection:name" into "/A/B" and "name"; false if it is not that form.
    static bool splitCollectionPath(std::string_view path, std::string* prim, std::string* name);

    /// Included collections nest at most this deep (deeper ones are cut with a warning), so a
    /// hostile chain cannot exhaust the stack.
    static constexpr int kMaxNesting = 64;

private:
    using RuleMap = std::unordered_map<std::string, Rule>;
    struct Build;  // the memo of one construction (each collection's map computed once)
    static const RuleMap& ruleMap(Build& b, const std::string& collectionPath, bool includeRootFallback, int depth);
    RuleMap _rules;  ///< path -> rule (the rule map)
};

}  // namespace principled::adapter
