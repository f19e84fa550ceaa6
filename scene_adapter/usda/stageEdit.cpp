// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/stageEdit.h"

#include <algorithm>

namespace principled::usd {

namespace {

template <class T>
void insertSorted(std::vector<const T*>& sorted, const T* item) {
    auto it = std::lower_bound(sorted.begin(), sorted.end(), item->name(),
                               [](const T* a, const std::string& n) { return a->name() < n; });
    sorted.insert(it, item);
}

}  // namespace

SourceLocation StageEdit::location() {
    return SourceLocation{"<host edit>", 0, 0};
}

Prim* StageEdit::mutablePrim(const std::string& path) {
    // The stage owns its prims; const is only the readers' view of them.
    return const_cast<Prim*>(_stage.prim(path));
}

const Attribute* StageEdit::setAttribute(const std::string& primPath, const std::string& name,
                                         const std::string& typeName, bool isArray, Value value) {
    Prim* prim = mutablePrim(primPath);
    if (!prim) return nullptr;
    auto* attr = const_cast<Attribute*>(prim->attribute(name));
    if (!attr) {
        auto created = std::make_unique<Attribute>();
        created->_name = name;
        created->_typeName = typeName;
        created->_isArray = isArray;
        created->_custom = true;
        attr = created.get();
        prim->_attributeStore.push_back(std::move(created));
        insertSorted<Attribute>(prim->_attributes, attr);
    }
    value.setLocation(location());
    attr->_default = std::move(value);
    // A session-layer default is the strongest opinion: it wins over weaker time samples.
    attr->_samples.clear();
    attr->_location = location();
    return attr;
}

const Attribute* StageEdit::connect(const std::string& primPath, const std::string& name,
                                    const std::string& typeName, std::vector<std::string> sources) {
    Prim* prim = mutablePrim(primPath);
    if (!prim) return nullptr;
    if (!prim->attribute(name))
        setAttribute(primPath, name, typeName, false, Value::none(typeName, false, location()));
    auto* attr = const_cast<Attribute*>(prim->attribute(name));
    attr->_connections = std::move(sources);
    attr->_location = location();
    return attr;
}

const Relationship* StageEdit::setRelationship(const std::string& primPath, const std::string& name,
                                               std::vector<std::string> targets) {
    Prim* prim = mutablePrim(primPath);
    if (!prim) return nullptr;
    auto* rel = const_cast<Relationship*>(prim->relationship(name));
    if (!rel) {
        auto created = std::make_unique<Relationship>();
        created->_name = name;
        rel = created.get();
        prim->_relationshipStore.push_back(std::move(created));
        insertSorted<Relationship>(prim->_relationships, rel);
    }
    rel->_targets = std::move(targets);
    rel->_location = location();
    return rel;
}

const Prim* StageEdit::definePrim(const std::string& path, const std::string& typeName) {
    if (path.size() < 2 || path[0] != '/' || _stage.prim(path)) return nullptr;
    size_t slash = path.rfind('/');
    std::string parentPath = slash == 0 ? "/" : path.substr(0, slash);
    Prim* parent = mutablePrim(parentPath);
    if (!parent) return nullptr;
    auto prim = std::make_unique<Prim>();
    prim->_path = path;
    prim->_name = path.substr(slash + 1);
    prim->_typeName = typeName;
    prim->_defined = true;
    prim->_active = parent->_active;
    prim->_abstract = parent->_abstract;
    prim->_parent = parent;
    prim->_location = location();
    Prim* raw = prim.get();
    parent->_children.push_back(raw);
    _stage._index[path] = raw;
    _stage._prims.push_back(std::move(prim));
    return raw;
}

void StageEdit::unindex(Prim& prim) {
    _stage._index.erase(prim._path);
    for (const Prim* child : prim._children) unindex(*const_cast<Prim*>(child));
}

bool StageEdit::removePrim(const std::string& path) {
    Prim* prim = mutablePrim(path);
    if (!prim || prim == _stage._root) return false;
    auto* parent = const_cast<Prim*>(prim->_parent);
    auto& siblings = parent->_children;
    siblings.erase(std::remove(siblings.begin(), siblings.end(), prim), siblings.end());
    unindex(*prim);
    return true;
}

}  // namespace principled::usd
