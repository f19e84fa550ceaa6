// SPDX-License-Identifier: Apache-2.0
// UsdShade material resolution: the one Material a gprim (or GeomSubset) is shaded with, from
// the direct and collection-based bindings on it and its ancestors, their strengths and their
// purposes (the "full" purpose first, then all-purpose bindings).
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "scene_adapter/collectionMembership.h"

namespace principled::usd {
class Prim;
class Relationship;
class Stage;
}  // namespace principled::usd

namespace principled::adapter {

class MaterialBindingResolver {
public:
    using WarnFn = CollectionMembership::WarnFn;
    /// `purposes`: the binding purposes in order of preference ("" is the all-purpose binding);
    /// UsdRenderSettings materialBindingPurposes, whose fallback is ["full", ""].
    MaterialBindingResolver(const usd::Stage& stage, WarnFn warn,
                            std::vector<std::string> purposes = {"full", ""})
        : _stage(stage), _warn(std::move(warn)), _purposes(std::move(purposes)) {}

    /// The bound Material's path, or "" when nothing binds one. Rules (UsdShadeMaterialBindingAPI
    /// material resolution): for each purpose in order (by default "full", then all-purpose
    /// bindings), walk from the
    /// prim up to the root; at each prim its direct binding is taken when nothing nearer bound one
    /// or when it is strongerThanDescendants (bindMaterialAs), then the first of its collection
    /// bindings (material:binding:collection:NAME, in name order) whose collection holds the prim
    /// is taken when nothing nearer bound one, when the binding taken so far is this prim's own
    /// direct binding, or when it is strongerThanDescendants. The first purpose that binds wins.
    /// Bindings whose target is not a Material are reported and ignored. Thread-safe.
    std::string resolve(const usd::Prim& prim) const;

    /// A key equal for two prims whose descendants resolve alike wherever their own subtrees
    /// bind alike: per purpose, the nearest Material bound on the prim or above and the
    /// outermost strongerThanDescendants one. Collection bindings there make membership depend
    /// on the exact path, so the key is then the prim's path (no two prims share it).
    std::string inheritedKey(const usd::Prim& prim) const;

    /// Forgets the collections read so far (after an edit to the stage).
    void invalidate();
    /// Whether resolve() or inheritedKey() has met a collection-based binding (edits then
    /// re-resolve every prim: membership can reach anywhere below the binding).
    bool sawCollectionBindings() const { return _sawCollections.load(std::memory_order_relaxed); }

private:
    /// The Material a binding relationship's `targetIndex`-th target names, "" (with a
    /// warning when `warn`) when it is not a Material.
    std::string materialTarget(const usd::Relationship& rel, size_t targetIndex, const usd::Prim& subject,
                               bool warn = true) const;
    /// A direct binding's Material: "" unless it has exactly one target, a Material.
    std::string directTarget(const usd::Relationship& rel, const usd::Prim& subject, bool warn = true) const;
    bool collectionIncludes(const std::string& collectionPath, const std::string& primPath) const;

    const usd::Stage& _stage;
    WarnFn _warn;
    std::vector<std::string> _purposes;
    mutable std::mutex _mutex;
    mutable std::map<std::string, std::shared_ptr<const CollectionMembership>> _collections;
    mutable std::atomic<bool> _sawCollections{false};
};

}  // namespace principled::adapter
