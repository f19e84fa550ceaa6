// SPDX-License-Identifier: Apache-2.0
// UTF-8 well-formedness (Unicode 15, table 3-7): the lexer reads identifiers as UTF-8.
#pragma once

#include <cstddef>
#include <string_view>

namespace principled::usd {

/// The length (2-4) of the well-formed multi-byte UTF-8 sequence that starts at text[pos], or 0
/// when the bytes there are not one (a stray continuation byte, an overlong form, a surrogate,
/// a code point above U+10FFFF, or a sequence cut short). ASCII bytes give 0 too: callers
/// handle them first.
std::size_t utf8SequenceLength(std::string_view text, std::size_t pos);

}  // namespace principled::usd
