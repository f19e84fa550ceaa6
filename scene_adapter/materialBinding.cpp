// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/materialBinding.h"

#include <algorithm>
#include <cctype>
#include <string_view>
#include <vector>

#include "scene_adapter/usda/prim.h"
#include "scene_adapter/usda/stage.h"

namespace principled::adapter {
namespace {

constexpr std::string_view kCollectionPrefix = "material:binding:collection:";

bool strongerThanDescendants(const usd::Relationship& rel) {
    const usd::Value* v = rel.metadata("bindMaterialAs");
    return v && v->getString().value_or("") == "strongerThanDescendants";
}

// Property "dictionary order" (how USD orders property names): letters compare without case,
// runs of digits by their value; ties fall back to plain byte order.
bool dictionaryLess(std::string_view a, std::string_view b) {
    size_t i = 0, j = 0;
    while (i < a.size() && j < b.size()) {
        if (std::isdigit(static_cast<unsigned char>(a[i])) && std::isdigit(static_cast<unsigned char>(b[j]))) {
            size_t ie = i, je = j;
            while (ie < a.size() && std::isdigit(static_cast<unsigned char>(a[ie]))) ++ie;
            while (je < b.size() && std::isdigit(static_cast<unsigned char>(b[je]))) ++je;
            std::string_view da = a.substr(i, ie - i), db = b.substr(j, je - j);
            while (da.size() > 1 && da[0] == '0') da.remove_prefix(1);
            while (db.size() > 1 && db[0] == '0') db.remove_prefix(1);
            if (da.size() != db.size()) return da.size() < db.size();
            if (da != db) return da < db;
            i = ie, j = je;
            continue;
        }
        const int ca = std::tolower(static_cast<unsigned char>(a[i])), cb = std::tolower(static_cast<unsigned char>(b[j]));
        if (ca != cb) return ca < cb;
        ++i, ++j;
    }
    if (a.size() - i != b.size() - j) return a.size() - i < b.size() - j;
    return a < b;
}

// The collection-binding relationships of one purpose on a prim, in dictionary order:
// "material:binding:collection:NAME" (all-purpose, NAME without ':') or
// "material:binding:collection:PURPOSE:NAME".
std::vector<const usd::Relationship*> collectionBindings(const usd::Prim& prim, const std::string& purpose) {
    std::vector<const usd::Relationship*> out;
    for (const usd::Relationship* r : prim.relationships()) {
        std::string_view n = r->name();
        if (n.substr(0, kCollectionPrefix.size()) != kCollectionPrefix) continue;
        n.remove_prefix(kCollectionPrefix.size());
        if (!purpose.empty()) {
            if (n.size() <= purpose.size() + 1 || n.substr(0, purpose.size()) != purpose || n[purpose.size()] != ':')
                continue;
        } else if (n.empty() || n.find(':') != std::string_view::npos) {
            continue;
        }
        out.push_back(r);
    }
    std::sort(out.begin(), out.end(),
              [](const usd::Relationship* x, const usd::Relationship* y) { return dictionaryLess(x->name(), y->name()); });
    return out;
}

// A collection binding's targets: the collection and the Material, in either order; -1 when
// neither or both are collections.
int collectionTargetIndex(const usd::Relationship& r) {
    if (r.targets().size() != 2) return -1;
    const bool first = CollectionMembership::isCollectionPath(r.targets()[0]);
    const bool second = CollectionMembership::isCollectionPath(r.targets()[1]);
    return first == second ? -1 : (first ? 0 : 1);
}

}  // namespace

std::string MaterialBindingResolver::materialTarget(const usd::Relationship& rel, size_t targetIndex,
                                                    const usd::Prim& subject, bool warn) const {
    const std::string& target = rel.targets()[targetIndex];
    const usd::Prim* m = _stage.prim(target);
    if (m && m->typeName() == "Material") return target;
    if (warn)
        _warn(rel.location().str() + ": " + subject.path(),
              rel.name() + " targets '" + target + "', which is not a Material; the binding is ignored");
    return "";
}

std::string MaterialBindingResolver::directTarget(const usd::Relationship& rel, const usd::Prim& subject,
                                                  bool warn) const {
    if (rel.targets().size() == 1) return materialTarget(rel, 0, subject, warn);
    if (warn && rel.targets().size() > 1)
        _warn(rel.location().str() + ": " + subject.path(),
              rel.name() + " has " + std::to_string(rel.targets().size()) + " targets (a direct binding names one Material); ignored");
    return "";
}

bool MaterialBindingResolver::collectionIncludes(const std::string& collectionPath, const std::string& primPath) const {
    std::shared_ptr<const CollectionMembership> c;
    {
        std::lock_guard<std::mutex> lock(_mutex);
        auto& slot = _collections[collectionPath];
        if (!slot) slot = std::make_shared<const CollectionMembership>(_stage, collectionPath, _warn);
        c = slot;
    }
    return c->includes(primPath);
}

void MaterialBindingResolver::invalidate() {
    std::lock_guard<std::mutex> lock(_mutex);
    _collections.clear();
}

std::string MaterialBindingResolver::inheritedKey(const usd::Prim& prim) const {
    // What the prim and its ancestors pass down to a descendant, per purpose: the nearest bound
    // Material (it wins where nothing inside binds) and the outermost strongerThanDescendants one
    // (it wins over anything inside). Equal keys resolve every descendant alike. Collection
    // bindings make membership depend on the exact path: the key is then the path itself.
    std::string key;
    for (const std::string& purpose : _purposes) {
        const std::string directName = purpose.empty() ? "material:binding" : "material:binding:" + purpose;
        std::string nearest, strongest;
        for (const usd::Prim* p = &prim; p && p->path() != "/"; p = p->parent()) {
            if (!collectionBindings(*p, purpose).empty()) {
                _sawCollections.store(true, std::memory_order_relaxed);
                return "path:" + prim.path();
            }
            const usd::Relationship* r = p->relationship(directName);
            if (!r) continue;
            const std::string m = directTarget(*r, prim, false);
            if (m.empty()) continue;
            if (nearest.empty()) nearest = m;
            if (strongerThanDescendants(*r)) strongest = m;
        }
        key += nearest + "|" + strongest + ";";
    }
    return key;
}

std::string MaterialBindingResolver::resolve(const usd::Prim& subject) const {
    for (const std::string& purpose : _purposes) {
        const std::string directName = purpose.empty() ? "material:binding" : "material:binding:" + purpose;
        std::string bound;  // the Material bound so far
        bool boundDirectHere = false;  // the binding taken so far is the current prim's direct one
        for (const usd::Prim* p = &subject; p && p->path() != "/"; p = p->parent()) {
            boundDirectHere = false;
            if (const usd::Relationship* r = p->relationship(directName); r && !r->targets().empty()) {
                if (bound.empty() || strongerThanDescendants(*r)) {
                    if (std::string m = directTarget(*r, subject); !m.empty()) {
                        bound = std::move(m);
                        boundDirectHere = true;
                    }
                }
            }
            for (const usd::Relationship* r : collectionBindings(*p, purpose)) {
                _sawCollections.store(true, std::memory_order_relaxed);
                const int c = collectionTargetIndex(*r);
                if (c < 0) {
                    if (!r->targets().empty())
                        _warn(r->location().str() + ": " + p->path(),
                              r->name() + " needs two targets, a collection and a Material; ignored");
                    continue;
                }
                if (!collectionIncludes(r->targets()[size_t(c)], subject.path())) continue;
                if (!bound.empty() && !boundDirectHere && !strongerThanDescendants(*r)) continue;
                if (std::string m = materialTarget(*r, size_t(1 - c), subject); !m.empty()) {
                    bound = std::move(m);
                    break;
                }
            }
        }
        if (!bound.empty()) return bound;
    }
    return "";
}

}  // namespace principled::adapter
