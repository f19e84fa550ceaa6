// SPDX-License-Identifier: Apache-2.0
#include "delegate/hd/renderIndex.h"

#include <algorithm>
#include <unordered_map>

#include <tbb/parallel_for.h>

namespace principled::hd {
namespace {

bool contains(const std::vector<Token>& v, const Token& t) {
    return std::find(v.begin(), v.end(), t) != v.end();
}

}  // namespace

RenderIndex::RenderIndex(RenderDelegate* renderDelegate) : _renderDelegate(renderDelegate) {}

RenderIndex::~RenderIndex() { clear(); }

bool RenderIndex::isRprimTypeSupported(const Token& t) const {
    return contains(_renderDelegate->supportedRprimTypes(), t);
}
bool RenderIndex::isSprimTypeSupported(const Token& t) const {
    return contains(_renderDelegate->supportedSprimTypes(), t);
}

bool RenderIndex::insertRprim(const Token& typeId, SceneDelegate* delegate, const Path& id) {
    if (!isRprimTypeSupported(typeId) || _rprims.count(id)) return false;
    auto prim = _renderDelegate->createRprim(typeId, id);
    if (!prim) return false;
    prim->setPrimId(static_cast<int>(_rprimsById.size()));
    _rprimsById.push_back(prim.get());
    _tracker.track(ChangeTracker::Kind::Rprim, id, prim->initialDirtyBits());
    _rprims[id] = Entry<Rprim>{typeId, delegate, std::move(prim)};
    return true;
}

bool RenderIndex::insertSprim(const Token& typeId, SceneDelegate* delegate, const Path& id) {
    if (!isSprimTypeSupported(typeId) || _sprims.count(id)) return false;
    auto prim = _renderDelegate->createSprim(typeId, id);
    if (!prim) return false;
    _tracker.track(ChangeTracker::Kind::Sprim, id, prim->initialDirtyBits());
    _sprims[id] = Entry<Sprim>{typeId, delegate, std::move(prim)};
    return true;
}

bool RenderIndex::insertBprim(const Token& typeId, SceneDelegate* delegate, const Path& id) {
    if (!contains(_renderDelegate->supportedBprimTypes(), typeId) || _bprims.count(id))
        return false;
    auto prim = _renderDelegate->createBprim(typeId, id);
    if (!prim) return false;
    _tracker.track(ChangeTracker::Kind::Bprim, id, prim->initialDirtyBits());
    _bprims[id] = Entry<Bprim>{typeId, delegate, std::move(prim)};
    return true;
}

void RenderIndex::removeRprim(const Path& id) {
    auto it = _rprims.find(id);
    if (it == _rprims.end()) return;
    it->second.prim->finalize(_renderDelegate->renderParam());
    int pid = it->second.prim->primId();
    if (pid >= 0 && pid < static_cast<int>(_rprimsById.size())) _rprimsById[pid] = nullptr;
    _tracker.untrack(ChangeTracker::Kind::Rprim, id);
    _rprims.erase(it);
}

void RenderIndex::removeSprim(const Path& id) {
    auto it = _sprims.find(id);
    if (it == _sprims.end()) return;
    it->second.prim->finalize(_renderDelegate->renderParam());
    _tracker.untrack(ChangeTracker::Kind::Sprim, id);
    _sprims.erase(it);
}

void RenderIndex::removeBprim(const Path& id) {
    auto it = _bprims.find(id);
    if (it == _bprims.end()) return;
    it->second.prim->finalize(_renderDelegate->renderParam());
    _tracker.untrack(ChangeTracker::Kind::Bprim, id);
    _bprims.erase(it);
}

void RenderIndex::clear() {
    while (!_rprims.empty()) removeRprim(_rprims.begin()->first);
    while (!_sprims.empty()) removeSprim(_sprims.begin()->first);
    while (!_bprims.empty()) removeBprim(_bprims.begin()->first);
    _rprimsById.clear();
}

Rprim* RenderIndex::rprim(const Path& id) const {
    auto it = _rprims.find(id);
    return it == _rprims.end() ? nullptr : it->second.prim.get();
}

Sprim* RenderIndex::sprim(const Token& typeId, const Path& id) const {
    auto it = _sprims.find(id);
    if (it == _sprims.end() || it->second.typeId != typeId) return nullptr;
    return it->second.prim.get();
}

Bprim* RenderIndex::bprim(const Token& typeId, const Path& id) const {
    auto it = _bprims.find(id);
    if (it == _bprims.end() || it->second.typeId != typeId) return nullptr;
    return it->second.prim.get();
}

std::vector<Path> RenderIndex::sprimIds(const Token& typeId) const {
    std::vector<Path> ids;
    for (const auto& [id, e] : _sprims)
        if (e.typeId == typeId) ids.push_back(id);
    return ids;
}

std::vector<Path> RenderIndex::rprimIds() const {
    std::vector<Path> ids;
    for (const auto& [id, e] : _rprims) ids.push_back(id);
    return ids;
}

Rprim* RenderIndex::rprimByPrimId(int id) const {
    if (id < 0 || id >= static_cast<int>(_rprimsById.size())) return nullptr;
    return _rprimsById[id];
}

void RenderIndex::sync() {
    RenderParam* param = _renderDelegate->renderParam();
    using K = ChangeTracker::Kind;
    _lastSync = SyncRecord{};
    for (const Path& id : _tracker.dirtyIds(K::Bprim)) {
        auto& e = _bprims.at(id);
        DirtyBits bits = _tracker.dirtyBits(K::Bprim, id);
        _lastSync.bprims.emplace_back(id, bits);
        e.prim->sync(e.sceneDelegate, param, &bits);
        _tracker.setClean(K::Bprim, id, bits);
    }
    for (const Path& id : _tracker.dirtyIds(K::Sprim)) {
        auto& e = _sprims.at(id);
        DirtyBits bits = _tracker.dirtyBits(K::Sprim, id);
        _lastSync.sprims.emplace_back(id, bits);
        e.prim->sync(e.sceneDelegate, param, &bits);
        _tracker.setClean(K::Sprim, id, bits);
    }
    // Rprims in parallel: each touches only its own state (see Rprim::sync's contract).
    std::vector<Path> dirty = _tracker.dirtyIds(K::Rprim);
    std::vector<DirtyBits> bits(dirty.size());
    for (size_t i = 0; i < dirty.size(); ++i) {
        bits[i] = _tracker.dirtyBits(K::Rprim, dirty[i]);
        _lastSync.rprims.emplace_back(dirty[i], bits[i]);
    }
    std::vector<Rprim*> prims(dirty.size());
    std::vector<SceneDelegate*> delegates(dirty.size());
    for (size_t i = 0; i < dirty.size(); ++i) {
        auto& e = _rprims.at(dirty[i]);
        prims[i] = e.prim.get();
        delegates[i] = e.sceneDelegate;
    }
    // The plan may pull more rprims into this sync (a scene-wide fit that moves clean ones);
    // it is asked again with them until it adds none, so it plans from every prim it syncs.
    std::unordered_map<Rprim*, size_t> syncing;
    for (size_t i = 0; i < prims.size(); ++i) syncing.emplace(prims[i], i);
    for (;;) {
        std::vector<std::pair<Rprim*, DirtyBits>> also;
        _renderDelegate->prepareRprimSync(prims, delegates, bits, &also);
        bool added = false;
        for (const auto& [prim, extra] : also) {
            auto it = _rprims.find(prim->id());
            if (it == _rprims.end() || it->second.prim.get() != prim) continue;
            if (auto s = syncing.find(prim); s != syncing.end()) {  // already syncing: for more now
                added = added || (bits[s->second] | extra) != bits[s->second];
                bits[s->second] |= extra;
                continue;
            }
            syncing.emplace(prim, prims.size());
            dirty.push_back(prim->id());
            bits.push_back(extra);
            _lastSync.rprims.emplace_back(prim->id(), extra);
            prims.push_back(prim);
            delegates.push_back(it->second.sceneDelegate);
            added = true;
        }
        if (!added) break;
    }
    tbb::parallel_for(size_t(0), dirty.size(), [&](size_t i) { prims[i]->sync(delegates[i], param, &bits[i]); });
    for (size_t i = 0; i < dirty.size(); ++i) _tracker.setClean(K::Rprim, dirty[i], bits[i]);
    _renderDelegate->commitResources(&_tracker);
}

}  // namespace principled::hd
