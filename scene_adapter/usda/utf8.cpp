// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/utf8.h"

namespace principled::usd {

namespace {
bool inRange(unsigned char c, unsigned char lo, unsigned char hi) {
    return c >= lo && c <= hi;
}
}  // namespace

std::size_t utf8SequenceLength(std::string_view text, std::size_t pos) {
    if (pos >= text.size()) return 0;
    const auto at = [&](std::size_t i) {
        return pos + i < text.size() ? static_cast<unsigned char>(text[pos + i]) : 0;
    };
    const unsigned char b0 = at(0);
    // The allowed range of the second byte depends on the first (excludes overlong forms,
    // surrogates and code points above U+10FFFF); later bytes are 80..BF.
    std::size_t length = 0;
    unsigned char lo = 0x80, hi = 0xBF;
    if (inRange(b0, 0xC2, 0xDF)) {
        length = 2;
    } else if (inRange(b0, 0xE0, 0xEF)) {
        length = 3;
        if (b0 == 0xE0) lo = 0xA0;
        if (b0 == 0xED) hi = 0x9F;
    } else if (inRange(b0, 0xF0, 0xF4)) {
        length = 4;
        if (b0 == 0xF0) lo = 0x90;
        if (b0 == 0xF4) hi = 0x8F;
    } else {
        return 0;  // ASCII, a continuation byte, C0/C1 (overlong) or F5..FF
    }
    if (!inRange(at(1), lo, hi)) return 0;
    for (std::size_t i = 2; i < length; ++i)
        if (!inRange(at(i), 0x80, 0xBF)) return 0;
    return length;
}

}  // namespace principled::usd
