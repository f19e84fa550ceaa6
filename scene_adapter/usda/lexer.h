// SPDX-License-Identifier: Apache-2.0
// Hand-written USDA tokenizer: identifiers (with ':' namespaces, UTF-8 allowed), numbers (incl.
// inf/nan), quoted strings ('', "", triple-quoted), @asset@ / @@@asset@@@, </path>, punctuation.
// Comments: '#', '//' to end of line and '/* ... */'. Tokens are views into the source text;
// nothing is allocated per token.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "scene_adapter/usda/error.h"
#include "scene_adapter/usda/sourceLocation.h"

namespace principled::usd {

enum class TokenKind : std::uint8_t { End, Identifier, Number, String, Asset, Path, Punct };

struct Token {
    TokenKind kind = TokenKind::End;
    std::string_view text;  ///< raw text, including quotes / @ / <>
    int line = 1;
    int column = 1;

    bool is(char c) const { return kind == TokenKind::Punct && text.size() == 1 && text[0] == c; }
    bool isIdent(std::string_view s) const { return kind == TokenKind::Identifier && text == s; }
};

class Lexer {
public:
    Lexer(std::string_view text, std::string file);

    const Token& peek() const { return _next; }
    Token next() {
        Token t = _next;
        _lastEnd = t.text.data() + t.text.size();
        _next = scan();
        return t;
    }
    /// Just past the text of the token next() returned last (nullptr before the first).
    const char* lastEnd() const { return _lastEnd; }

    const std::string& file() const { return _file; }
    SourceLocation location(const Token& t) const { return {_file, t.line, t.column}; }

    /// Throws ParseError "file:line:col: expected <expected>, found <describe(at)>".
    [[noreturn]] void fail(const Token& at, std::string_view expected) const;
    /// "end of file" or the token text in single quotes (abbreviated when long).
    static std::string describe(const Token& t);

private:
    Token scan();
    void skipSpaceAndComments();
    /// Line breaks are "\r\n", "\n" and a lone "\r" (classic Mac; the grammar's Eol is
    /// one<'\r', '\n'>): 2, 1 or 1; 0 when there is none at `pos`.
    std::size_t lineBreakAt(std::size_t pos) const;
    /// Moves past a line break of `length` bytes at _pos to the start of the next line.
    void newLine(std::size_t length);
    [[noreturn]] void failHere(std::string_view expected, std::string_view found) const;
    void scanString(Token& t);
    /// An identifier from _pos: ASCII letters, digits, '_', ':' and UTF-8 characters.
    void scanIdentifier();

    std::string_view _text;
    FileName _file;  ///< interned once: every token location shares it
    std::size_t _pos = 0;
    std::size_t _lineStart = 0;
    int _line = 1;
    Token _next;
    const char* _lastEnd = nullptr;
};

/// `text` in single quotes for an error message: bytes outside printable ASCII as \\xNN, cut
/// after 40 characters with "...".
std::string quoteText(std::string_view text);

/// The contents of a string token with escapes decoded (quotes stripped).
std::string unescapeString(std::string_view raw);

}  // namespace principled::usd
