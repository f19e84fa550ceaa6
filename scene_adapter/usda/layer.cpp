// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/layer.h"

namespace principled::usd {

namespace {
template <class Vec>
auto findNamed(const Vec& v, std::string_view name) -> decltype(&*v.begin()) {
    for (const auto& item : v)
        if (item.name == name) return &item;
    return nullptr;
}
}  // namespace

const PrimSpec* VariantSetSpec::variant(std::string_view n) const {
    for (const auto& v : variants)
        if (v->name == n) return v.get();
    return nullptr;
}

namespace {
// Below this many children a linear scan is faster than hashing.
constexpr std::size_t kIndexThreshold = 8;

void buildIndex(const std::vector<std::unique_ptr<PrimSpec>>& prims,
                std::unordered_map<std::string_view, const PrimSpec*>& index) {
    index.clear();
    if (prims.size() <= kIndexThreshold) return;
    index.reserve(prims.size());
    for (const auto& p : prims) index.emplace(p->name, p.get());  // first spec of a name wins
}

const PrimSpec* lookup(const std::vector<std::unique_ptr<PrimSpec>>& prims,
                       const std::unordered_map<std::string_view, const PrimSpec*>& index,
                       std::string_view name) {
    if (!index.empty()) {
        auto it = index.find(name);
        return it == index.end() ? nullptr : it->second;
    }
    for (const auto& p : prims)
        if (p->name == name) return p.get();
    return nullptr;
}
}  // namespace

void PrimSpec::indexChildren() {
    buildIndex(children, childIndex);
}
void Layer::indexRootPrims() {
    buildIndex(rootPrims, rootIndex);
}

const PrimSpec* PrimSpec::child(std::string_view n) const {
    return lookup(children, childIndex, n);
}

const VariantSetSpec* PrimSpec::variantSet(std::string_view n) const {
    return findNamed(variantSets, n);
}
const AttributeSpec* PrimSpec::attribute(std::string_view n) const {
    return findNamed(attributes, n);
}
const RelationshipSpec* PrimSpec::relationship(std::string_view n) const {
    return findNamed(relationships, n);
}

std::string Layer::defaultPrim() const {
    const Value* v = field("defaultPrim");
    if (!v) return {};
    if (auto s = v->getString()) return *s;
    return {};
}

const Value* Layer::field(std::string_view key) const {
    auto it = metadata.find(key);
    return it == metadata.end() ? nullptr : &it->second;
}

const PrimSpec* Layer::prim(std::string_view site) const {
    if (site.empty() || site[0] != '/') return nullptr;
    const PrimSpec* current = nullptr;
    std::size_t i = 1;
    while (i < site.size()) {
        std::size_t j = i;
        while (j < site.size() && site[j] != '/' && site[j] != '{') ++j;
        std::string_view name = site.substr(i, j - i);
        if (!name.empty()) {
            if (!current) {
                current = lookup(rootPrims, rootIndex, name);
            } else {
                current = current->child(name);
            }
            if (!current) return nullptr;
        }
        // Variant selections: {set=selection}, possibly several in a row.
        while (j < site.size() && site[j] == '{') {
            auto close = site.find('}', j);
            if (close == std::string_view::npos || !current) return nullptr;
            std::string_view sel = site.substr(j + 1, close - j - 1);
            auto eq = sel.find('=');
            if (eq == std::string_view::npos) return nullptr;
            const VariantSetSpec* vs = current->variantSet(sel.substr(0, eq));
            if (!vs) return nullptr;
            current = vs->variant(sel.substr(eq + 1));
            if (!current) return nullptr;
            j = close + 1;
        }
        i = j + 1;
    }
    return current;
}

}  // namespace principled::usd
