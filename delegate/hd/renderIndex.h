// SPDX-License-Identifier: Apache-2.0
// RenderIndex: the table of prims a scene delegate populates and a render delegate realises.
// sync() pulls dirty data in Hydra's order: bprims, sprims, rprims (in parallel), then commit.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "delegate/hd/changeTracker.h"
#include "delegate/hd/prim.h"
#include "delegate/hd/renderDelegate.h"
#include "delegate/hd/sceneDelegate.h"

namespace principled::hd {

class RenderIndex {
public:
    /// The render delegate must outlive the index.
    explicit RenderIndex(RenderDelegate* renderDelegate);
    ~RenderIndex();
    RenderIndex(const RenderIndex&) = delete;
    RenderIndex& operator=(const RenderIndex&) = delete;

    /// Inserts a prim of a type the render delegate supports; returns false (and inserts
    /// nothing) for an unsupported type or a duplicate id.
    bool insertRprim(const Token& typeId, SceneDelegate* delegate, const Path& id);
    bool insertSprim(const Token& typeId, SceneDelegate* delegate, const Path& id);
    bool insertBprim(const Token& typeId, SceneDelegate* delegate, const Path& id);
    void removeRprim(const Path& id);
    void removeSprim(const Path& id);
    void removeBprim(const Path& id);
    /// Removes every prim (finalizing each).
    void clear();

    bool isRprimTypeSupported(const Token& typeId) const;
    bool isSprimTypeSupported(const Token& typeId) const;

    Rprim* rprim(const Path& id) const;
    Sprim* sprim(const Token& typeId, const Path& id) const;
    Bprim* bprim(const Token& typeId, const Path& id) const;
    std::vector<Path> sprimIds(const Token& typeId) const;
    std::vector<Path> rprimIds() const;
    size_t rprimCount() const { return _rprims.size(); }
    /// The rprim whose primId() is id, or nullptr.
    Rprim* rprimByPrimId(int id) const;

    /// Syncs every dirty prim (bprims, then sprims, then rprims in parallel) and commits.
    void sync();

    /// What the last sync() pulled: the ids of the prims it synced (path order) and the dirty
    /// bits each had. Tests of incremental updates read it; cost is one entry per dirty prim.
    struct SyncRecord {
        std::vector<std::pair<Path, DirtyBits>> rprims, sprims, bprims;
    };
    const SyncRecord& lastSync() const { return _lastSync; }

    ChangeTracker& changeTracker() { return _tracker; }
    const ChangeTracker& changeTracker() const { return _tracker; }
    RenderDelegate* renderDelegate() const { return _renderDelegate; }

private:
    template <typename P>
    struct Entry {
        Token typeId;
        SceneDelegate* sceneDelegate = nullptr;
        std::unique_ptr<P> prim;
    };

    RenderDelegate* _renderDelegate;
    ChangeTracker _tracker;
    std::map<Path, Entry<Rprim>> _rprims;
    std::map<Path, Entry<Sprim>> _sprims;
    std::map<Path, Entry<Bprim>> _bprims;
    std::vector<Rprim*> _rprimsById;
    SyncRecord _lastSync;
};

}  // namespace principled::hd
