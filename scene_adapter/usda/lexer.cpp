// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/lexer.h"

#include "scene_adapter/usda/utf8.h"

namespace principled::usd {

namespace {
bool isIdentStart(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c == '_';
}
bool isIdentChar(char c) {
    return isIdentStart(c) || (c >= '0' && c <= '9') || c == ':';
}
bool isDigit(char c) {
    return c >= '0' && c <= '9';
}
bool isNonAscii(char c) {
    return static_cast<unsigned char>(c) >= 0x80;
}
}  // namespace

Lexer::Lexer(std::string_view text, std::string file) : _text(text), _file(std::move(file)) {
    _next = scan();
}

std::string quoteText(std::string_view text) {
    std::string out = "'";
    std::size_t n = 0;
    for (char c : text) {
        if (++n > 40) {
            out += "...";
            break;
        }
        auto u = static_cast<unsigned char>(c);
        if (u < 0x20 || u >= 0x7f) {
            static const char* kHex = "0123456789abcdef";
            out += "\\x";
            out += kHex[u >> 4];
            out += kHex[u & 15];
        } else {
            out += c;
        }
    }
    return out + "'";
}

std::string Lexer::describe(const Token& t) {
    if (t.kind == TokenKind::End) return "end of file";
    return quoteText(t.text);
}

void Lexer::fail(const Token& at, std::string_view expected) const {
    throw ParseError(location(at), "expected " + std::string(expected) + ", found " + describe(at));
}

void Lexer::failHere(std::string_view expected, std::string_view found) const {
    SourceLocation where{_file, _line, static_cast<int>(_pos - _lineStart) + 1};
    throw ParseError(where, "expected " + std::string(expected) + ", found " + std::string(found));
}

std::size_t Lexer::lineBreakAt(std::size_t pos) const {
    if (pos >= _text.size()) return 0;
    if (_text[pos] == '\n') return 1;
    if (_text[pos] != '\r') return 0;
    return pos + 1 < _text.size() && _text[pos + 1] == '\n' ? 2 : 1;
}

void Lexer::newLine(std::size_t length) {
    _pos += length;
    ++_line;
    _lineStart = _pos;
}

void Lexer::skipSpaceAndComments() {
    const std::size_t n = _text.size();
    while (_pos < n) {
        char c = _text[_pos];
        if (std::size_t eol = lineBreakAt(_pos)) {
            newLine(eol);
        } else if (c == ' ' || c == '\t' || c == '\f' || c == '\v') {
            ++_pos;
        } else if (c == '#' || (c == '/' && _pos + 1 < n && _text[_pos + 1] == '/')) {
            while (_pos < n && !lineBreakAt(_pos)) ++_pos;
        } else if (c == '/' && _pos + 1 < n && _text[_pos + 1] == '*') {
            int line = _line, col = static_cast<int>(_pos - _lineStart) + 1;
            _pos += 2;
            bool closed = false;
            while (_pos < n) {
                if (_text[_pos] == '*' && _pos + 1 < n && _text[_pos + 1] == '/') {
                    _pos += 2;
                    closed = true;
                    break;
                }
                if (std::size_t eol = lineBreakAt(_pos))
                    newLine(eol);
                else
                    ++_pos;
            }
            if (!closed)
                failHere("'*/' closing the comment opened at " + std::to_string(line) + ":" +
                             std::to_string(col),
                         "end of file");
        } else {
            break;
        }
    }
}

void Lexer::scanString(Token& t) {
    const std::size_t n = _text.size();
    const std::size_t start = _pos;
    const char q = _text[_pos];
    const bool triple = _pos + 2 < n && _text[_pos + 1] == q && _text[_pos + 2] == q;
    const std::string opened = std::to_string(t.line) + ":" + std::to_string(t.column);
    const std::string closing = std::string(triple ? 3 : 1, q);
    _pos += triple ? 3 : 1;
    for (;;) {
        if (_pos >= n)
            failHere("'" + closing + "' closing the string opened at " + opened, "end of file");
        char c = _text[_pos];
        if (c == '\\' && !lineBreakAt(_pos + 1)) {
            _pos += 2;  // an escaped character (a line break is not escaped: see below)
            if (_pos > n) _pos = n;
            continue;
        }
        if (c == '\\') ++_pos;
        if (std::size_t eol = lineBreakAt(_pos)) {
            if (!triple)
                failHere("'" + closing + "' closing the string opened at " + opened, "end of line");
            newLine(eol);
            continue;
        }
        if (c == q) {
            if (!triple) {
                ++_pos;
                break;
            }
            if (_pos + 2 < n && _text[_pos + 1] == q && _text[_pos + 2] == q) {
                _pos += 3;
                break;
            }
        }
        ++_pos;
    }
    t.kind = TokenKind::String;
    t.text = _text.substr(start, _pos - start);
}

void Lexer::scanIdentifier() {
    // OpenUSD 24.03+ identifiers are Unicode: (XID_Start | '_') XID_Continue* (pathParser.h
    // Utf8Identifier). We approximate both classes by "any well-formed multi-byte UTF-8
    // sequence", so a non-ASCII letter, digit or mark is accepted anywhere in a name; what
    // OpenUSD would refuse (a non-ASCII symbol or space) is accepted here too. Malformed UTF-8 is
    // an error at the offending byte.
    const std::size_t n = _text.size();
    while (_pos < n) {
        const char c = _text[_pos];
        if (isIdentChar(c)) {
            ++_pos;
        } else if (isNonAscii(c)) {
            std::size_t length = utf8SequenceLength(_text, _pos);
            if (length == 0)
                failHere("a well-formed UTF-8 character in an identifier",
                         quoteText(_text.substr(_pos, 1)));
            _pos += length;
        } else {
            break;
        }
    }
}

Token Lexer::scan() {
    skipSpaceAndComments();
    Token t;
    t.line = _line;
    t.column = static_cast<int>(_pos - _lineStart) + 1;
    const std::size_t n = _text.size();
    if (_pos >= n) {
        t.kind = TokenKind::End;
        t.text = {};
        return t;
    }
    const std::size_t start = _pos;
    const char c = _text[_pos];
    if (isIdentStart(c) || isNonAscii(c)) {
        scanIdentifier();
        t.kind = TokenKind::Identifier;
    } else if (isDigit(c) ||
               ((c == '-' || c == '+' || c == '.') && _pos + 1 < n &&
                (isDigit(_text[_pos + 1]) ||
                 (c != '.' && (_text[_pos + 1] == '.' || isIdentStart(_text[_pos + 1])))))) {
        // A maximal number-like run; the parser validates it with std::from_chars so that
        // "1.2.3" or "4x" is reported as one bad number.
        ++_pos;
        while (_pos < n) {
            char d = _text[_pos];
            if (isDigit(d) || d == '.' || isIdentStart(d)) {
                ++_pos;
            } else if ((d == '-' || d == '+') &&
                       (_text[_pos - 1] == 'e' || _text[_pos - 1] == 'E')) {
                ++_pos;
            } else {
                break;
            }
        }
        t.kind = TokenKind::Number;
    } else if (c == '"' || c == '\'') {
        scanString(t);
        return t;
    } else if (c == '@') {
        const bool triple = _pos + 2 < n && _text[_pos + 1] == '@' && _text[_pos + 2] == '@';
        _pos += triple ? 3 : 1;
        for (;;) {
            const std::size_t eol = lineBreakAt(_pos);
            if (_pos >= n || (!triple && eol))
                failHere(std::string(triple ? "'@@@'" : "'@'") +
                             " closing the asset path opened at " + std::to_string(t.line) + ":" +
                             std::to_string(t.column),
                         _pos >= n ? "end of file" : "end of line");
            if (eol) {
                newLine(eol);
                continue;
            }
            if (triple && _text.compare(_pos, 3, "@@@") == 0 &&
                !(_pos + 3 < n && _text[_pos + 3] == '@')) {
                _pos += 3;
                break;
            }
            if (!triple && _text[_pos] == '@') {
                ++_pos;
                break;
            }
            if (triple && _text[_pos] == '\\' && !lineBreakAt(_pos + 1)) ++_pos;
            ++_pos;
        }
        t.kind = TokenKind::Asset;
    } else if (c == '<') {
        ++_pos;
        while (_pos < n && _text[_pos] != '>' && !lineBreakAt(_pos)) ++_pos;
        if (_pos >= n || _text[_pos] != '>')
            failHere("'>' closing the path opened at " + std::to_string(t.line) + ":" +
                         std::to_string(t.column),
                     _pos >= n ? "end of file" : "end of line");
        ++_pos;
        t.kind = TokenKind::Path;
    } else {
        ++_pos;
        t.kind = TokenKind::Punct;
    }
    t.text = _text.substr(start, _pos - start);
    return t;
}

namespace {
int hexDigit(char h) {
    return (h >= '0' && h <= '9')   ? h - '0'
           : (h >= 'a' && h <= 'f') ? h - 'a' + 10
           : (h >= 'A' && h <= 'F') ? h - 'A' + 10
                                    : -1;
}

/// Decodes the escape whose backslash is at body[i] into `out`; returns the index of its last
/// character. As TfEscapeStringReplaceChar (base/tf/stringUtils.cpp): \a \b \f \n \r \t
/// \v; \x takes every hex digit that follows, \ooo one to three octal digits, each giving one
/// byte (modulo 256); any other character stands for itself (\\ \" \' \c -> c).
std::size_t unescapeOne(std::string_view body, std::size_t i, std::string& out) {
    const char e = body[++i];
    switch (e) {
        case 'a': out += '\a'; return i;
        case 'b': out += '\b'; return i;
        case 'f': out += '\f'; return i;
        case 'n': out += '\n'; return i;
        case 'r': out += '\r'; return i;
        case 't': out += '\t'; return i;
        case 'v': out += '\v'; return i;
        case 'x': {
            unsigned v = 0;
            while (i + 1 < body.size() && hexDigit(body[i + 1]) >= 0)
                v = (v * 16 + static_cast<unsigned>(hexDigit(body[++i]))) & 0xFFu;
            out += static_cast<char>(v);
            return i;
        }
        default:
            break;
    }
    if (e >= '0' && e <= '7') {
        unsigned v = static_cast<unsigned>(e - '0');
        for (int digits = 1; digits < 3 && i + 1 < body.size() && body[i + 1] >= '0' &&
                             body[i + 1] <= '7';
             ++digits)
            v = v * 8 + static_cast<unsigned>(body[++i] - '0');
        out += static_cast<char>(v & 0xFFu);
        return i;
    }
    out += e;
    return i;
}
}  // namespace

std::string unescapeString(std::string_view raw) {
    std::size_t q = (raw.size() >= 6 && raw[1] == raw[0] && raw[2] == raw[0]) ? 3 : 1;
    if (raw.size() < 2 * q) return {};
    std::string_view body = raw.substr(q, raw.size() - 2 * q);
    std::string out;
    out.reserve(body.size());
    for (std::size_t i = 0; i < body.size(); ++i) {
        if (body[i] == '\\' && i + 1 < body.size())
            i = unescapeOne(body, i, out);
        else
            out += body[i];
    }
    return out;
}

}  // namespace principled::usd
