// SPDX-License-Identifier: Apache-2.0
// A PointInstancer's per-instance primvars, flattened once per instancer and shared by all of
// its prototypes (a forest of P tree prototypes with a colour per instance holds one copy,
// not P).
#pragma once

#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_map>
#include <vector>

#include "delegate/hd/path.h"
#include "delegate/sceneData.h"

namespace principled::hd {
class SceneDelegate;
struct InstancerArrays;
}

namespace principled::embree {

using InstancerPrimvars = std::shared_ptr<const std::vector<PrimvarChannel>>;

/// The instancer's vertex, varying, uniform and instance primvars as float channels of
/// `count` values each (indexed primvars expanded); primvars of another length are left out,
/// with a warning each. Null when there are none.
InstancerPrimvars readInstancerPrimvars(const hd::SceneDelegate* delegate, const hd::Path& instancerId,
                                        size_t count, std::vector<std::string>* warnings);

/// Per instancer, the channels last read, valid while the scene delegate hands out the same
/// InstancerArrays object (it replaces it on every edit of the instancer; a delegate that
/// builds a new one per call just gets no sharing). Holds the channels weakly: the instance
/// records own them, so a removed instancer leaves only a small entry. Thread-safe; prototypes
/// of one instancer syncing in parallel read it once between them, and its warnings (primvars
/// of the wrong length) go out once, with that read.
class InstancerPrimvarCache {
public:
    InstancerPrimvars get(const hd::SceneDelegate* delegate, const hd::Path& instancerId,
                          const std::shared_ptr<const hd::InstancerArrays>& arrays, size_t count,
                          std::vector<std::string>* warnings);
    /// Reads of the primvars so far (a statistic for tests and benchmarks).
    long reads() const;

private:
    struct Entry {
        std::mutex mutex;
        std::weak_ptr<const hd::InstancerArrays> arrays;
        size_t count = 0;
        bool valid = false;
        std::weak_ptr<const std::vector<PrimvarChannel>> primvars;
        bool none = false;  ///< the instancer has no usable per-instance primvars
    };
    mutable std::mutex _mutex;
    std::unordered_map<hd::Path, std::shared_ptr<Entry>> _entries;
    std::atomic<long> _reads{0};
};

}  // namespace principled::embree
