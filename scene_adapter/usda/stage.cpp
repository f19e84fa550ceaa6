// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/stage.h"

#include <algorithm>
#include <cmath>

#include "scene_adapter/usda/composer.h"
#include "scene_adapter/usda/timeSamples.h"

namespace principled::usd {

namespace {
const Value* findIn(const Dictionary& d, std::string_view key) {
    auto it = d.find(key);
    return it == d.end() ? nullptr : &it->second;
}

template <class T>
const T* findByName(const std::vector<const T*>& sorted, std::string_view name) {
    auto it = std::lower_bound(sorted.begin(), sorted.end(), name,
                               [](const T* a, std::string_view n) { return a->name() < n; });
    return (it != sorted.end() && (*it)->name() == name) ? *it : nullptr;
}
}  // namespace

Value Attribute::get(double time) const {
    if (std::isnan(time)) {
        if (_default) return *_default;
        if (!_samples.empty()) return _samples.begin()->second;
        return {};
    }
    if (!_samples.empty()) return evaluateTimeSamples(_samples, time);
    if (_default) return *_default;
    return {};
}

const Value* Attribute::metadata(std::string_view key) const {
    return findIn(_metadata, key);
}
const Value* Relationship::metadata(std::string_view key) const {
    return findIn(_metadata, key);
}
const Value* Prim::metadata(std::string_view key) const {
    return findIn(_metadata, key);
}

bool Prim::hasAPI(std::string_view schema) const {
    for (const std::string& applied : _appliedSchemas) {
        if (applied == schema) return true;
        if (applied.size() > schema.size() && applied.compare(0, schema.size(), schema) == 0 &&
            applied[schema.size()] == ':')
            return true;
    }
    return false;
}

const Attribute* Prim::attribute(std::string_view name) const {
    return findByName(_attributes, name);
}

const Relationship* Prim::relationship(std::string_view name) const {
    return findByName(_relationships, name);
}

std::string Diagnostic::str() const {
    std::string out = where.str();
    if (!out.empty()) out += ": ";
    out += severity == Severity::Error ? "error: " : "warning: ";
    return out + message;
}

std::unique_ptr<Stage> Stage::open(const std::string& path, const StageOptions& options) {
    std::unique_ptr<Stage> stage(new Stage());
    Composer(*stage, options).composeFile(path);
    return stage;
}

std::unique_ptr<Stage> Stage::openString(std::string_view text, const std::string& displayName,
                                         const StageOptions& options) {
    std::unique_ptr<Stage> stage(new Stage());
    Composer(*stage, options).composeText(text, displayName);
    return stage;
}

const Prim* Stage::prim(std::string_view path) const {
    auto it = _index.find(std::string(path));
    return it == _index.end() ? nullptr : it->second;
}

std::vector<const Prim*> Stage::traverse() const {
    std::vector<const Prim*> out;
    if (!_root) return out;
    std::vector<const Prim*> stack(_root->children().rbegin(), _root->children().rend());
    while (!stack.empty()) {
        const Prim* p = stack.back();
        stack.pop_back();
        if (!p->isActive() || !p->isDefined() || p->isAbstract()) continue;
        out.push_back(p);
        stack.insert(stack.end(), p->children().rbegin(), p->children().rend());
    }
    return out;
}

double Stage::defaultTime() const {
    return _hasStart ? _startTimeCode : kDefaultTime;
}

const Value* Stage::layerMetadata(std::string_view key) const {
    return findIn(_layerMetadata, key);
}

}  // namespace principled::usd
