// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/sourceLocation.h"

#include <mutex>
#include <unordered_set>

namespace principled::usd {

FileName::FileName(const std::string& name) {
    if (name.empty()) return;
    // A node-based set: element addresses stay valid as it grows. A process opens few files,
    // so the table is never pruned.
    static std::mutex mutex;
    static std::unordered_set<std::string>* table = new std::unordered_set<std::string>();
    std::lock_guard<std::mutex> lock(mutex);
    _name = &*table->insert(name).first;
}

const std::string& FileName::emptyName() {
    static const std::string* const empty = new std::string();  // never destroyed, as the table
    return *empty;
}

}  // namespace principled::usd
