// SPDX-License-Identifier: Apache-2.0
#include "delegate/hd/token.h"

#include <memory>
#include <mutex>
#include <string>
#include <string_view>
#include <unordered_set>

namespace principled::hd {
namespace {

// Transparent hashing: a lookup by string_view builds no std::string (a token constructed for
// text already interned, the common case, allocates nothing).
struct Hash {
    using is_transparent = void;
    size_t operator()(std::string_view s) const { return std::hash<std::string_view>{}(s); }
};
struct Equal {
    using is_transparent = void;
    bool operator()(std::string_view a, std::string_view b) const { return a == b; }
};

struct Registry {
    std::mutex mutex;
    // Node-based set: element addresses are stable, so the pointer is the identity.
    std::unordered_set<std::string, Hash, Equal> strings;
};

Registry& registry() {
    static Registry* r = new Registry();  // never destroyed: tokens may outlive static dtors
    return *r;
}

const std::string* intern(std::string_view text) {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    auto it = r.strings.find(text);
    if (it != r.strings.end()) return &*it;
    return &*r.strings.emplace(text).first;
}

}  // namespace

Token::Token() {
    static const std::string* const empty = intern("");
    _text = empty;
}
Token::Token(std::string_view text) : _text(intern(text)) {}

}  // namespace principled::hd
