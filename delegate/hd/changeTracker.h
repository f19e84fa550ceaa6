// SPDX-License-Identifier: Apache-2.0
// ChangeTracker: per-prim dirty bits plus version counters the render pass polls to decide
// whether accumulation must restart.
#pragma once

#include <atomic>
#include <mutex>
#include <unordered_map>
#include <vector>

#include "delegate/hd/dirtyBits.h"
#include "delegate/hd/path.h"

namespace principled::hd {

/// Records what changed on which prim. The scene delegate marks; the render index reads and
/// clears during sync. Marking is thread-safe; sync-time reads happen on one thread.
class ChangeTracker {
public:
    enum class Kind { Rprim, Sprim, Bprim };

    void track(Kind kind, const Path& id, DirtyBits initial);
    void untrack(Kind kind, const Path& id);

    void markRprimDirty(const Path& id, DirtyBits bits) { mark(Kind::Rprim, id, bits); }
    void markSprimDirty(const Path& id, DirtyBits bits) { mark(Kind::Sprim, id, bits); }
    void markBprimDirty(const Path& id, DirtyBits bits) { mark(Kind::Bprim, id, bits); }
    void mark(Kind kind, const Path& id, DirtyBits bits);

    DirtyBits dirtyBits(Kind kind, const Path& id) const;
    void setClean(Kind kind, const Path& id, DirtyBits remaining);

    /// Ids with any dirty bit, in path order (deterministic sync order).
    std::vector<Path> dirtyIds(Kind kind) const;

    /// Bumped on every mark and insert/remove: a render pass compares it to restart.
    unsigned sceneVersion() const { return _sceneVersion.load(); }

private:
    using Map = std::unordered_map<Path, DirtyBits>;
    Map& mapFor(Kind k) { return _maps[static_cast<int>(k)]; }
    const Map& mapFor(Kind k) const { return _maps[static_cast<int>(k)]; }

    mutable std::mutex _mutex;
    Map _maps[3];
    std::atomic<unsigned> _sceneVersion{1};
};

}  // namespace principled::hd
