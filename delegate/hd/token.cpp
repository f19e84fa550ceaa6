// SPDX-License-Identifier: Apache-2.0
#include "delegate/hd/token.h"

#include <memory>
#include <mutex>
#include <unordered_set>

namespace principled::hd {
namespace {

struct Registry {
    std::mutex mutex;
    // Node-based set: element addresses are stable, so the pointer is the identity.
    std::unordered_set<std::string> strings;
};

Registry& registry() {
    static Registry* r = new Registry();  // never destroyed: tokens may outlive static dtors
    return *r;
}

const std::string* intern(std::string_view text) {
    Registry& r = registry();
    std::lock_guard<std::mutex> lock(r.mutex);
    return &*r.strings.emplace(text).first;
}

}  // namespace

Token::Token() : _text(intern("")) {}
Token::Token(std::string_view text) : _text(intern(text)) {}

}  // namespace principled::hd
