// SPDX-License-Identifier: Apache-2.0
#include "delegate/hd/changeTracker.h"

#include <algorithm>

namespace principled::hd {

void ChangeTracker::track(Kind kind, const Path& id, DirtyBits initial) {
    std::lock_guard<std::mutex> lock(_mutex);
    mapFor(kind)[id] = initial;
    ++_sceneVersion;
}

void ChangeTracker::untrack(Kind kind, const Path& id) {
    std::lock_guard<std::mutex> lock(_mutex);
    mapFor(kind).erase(id);
    ++_sceneVersion;
}

void ChangeTracker::mark(Kind kind, const Path& id, DirtyBits bits) {
    std::lock_guard<std::mutex> lock(_mutex);
    auto it = mapFor(kind).find(id);
    if (it == mapFor(kind).end()) return;  // unknown prim: nothing to sync
    it->second |= bits;
    ++_sceneVersion;
}

DirtyBits ChangeTracker::dirtyBits(Kind kind, const Path& id) const {
    std::lock_guard<std::mutex> lock(_mutex);
    auto it = mapFor(kind).find(id);
    return it == mapFor(kind).end() ? 0 : it->second;
}

void ChangeTracker::setClean(Kind kind, const Path& id, DirtyBits remaining) {
    std::lock_guard<std::mutex> lock(_mutex);
    auto it = mapFor(kind).find(id);
    if (it != mapFor(kind).end()) it->second = remaining;
}

std::vector<Path> ChangeTracker::dirtyIds(Kind kind) const {
    std::vector<Path> ids;
    {
        std::lock_guard<std::mutex> lock(_mutex);
        for (const auto& [id, bits] : mapFor(kind))
            if (bits != 0) ids.push_back(id);
    }
    std::sort(ids.begin(), ids.end());
    return ids;
}

}  // namespace principled::hd
