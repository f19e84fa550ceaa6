// SPDX-License-Identifier: Apache-2.0
// Value grammar: typed values (scalars, tuples, matrices, arrays, strings, assets), numbers via
// std::from_chars, untyped metadata values and dictionaries.
#include <cctype>
#include <charconv>
#include <cmath>
#include <optional>

#include "scene_adapter/usda/assetResolver.h"
#include "scene_adapter/usda/metadataFields.h"
#include "scene_adapter/usda/parserImpl.h"

namespace principled::usd::detail {

namespace {
// A value's text for "found Y" in an error, quoted like a token.
std::string quoted(const std::string& text) {
    return quoteText(text);
}

// Inside @@@...@@@ the only escape is \@@@ for @@@ (Sdf_EvalAssetPath; Sdf writes it when a
// path holds "@@@").
std::string unescapeTripleAt(const std::string& path) {
    std::string out;
    out.reserve(path.size());
    for (std::size_t i = 0; i < path.size(); ++i) {
        if (path.compare(i, 4, "\\@@@") == 0) {
            out += "@@@";
            i += 3;
        } else {
            out += path[i];
        }
    }
    return out;
}
}  // namespace

AssetPath Parser::assetFromToken(const Token& t) const {
    std::string_view s = t.text;
    std::size_t q = s.size() >= 6 && s.substr(0, 3) == "@@@" ? 3 : 1;
    AssetPath a;
    if (t.kind == TokenKind::String) {
        a.authored = unescapeString(t.text);  // _GetImpl<SdfAssetPath>: a string converts
    } else {
        a.authored = std::string(s.substr(q, s.size() - 2 * q));
        if (q == 3) a.authored = unescapeTripleAt(a.authored);
    }
    a.resolved = resolveAsset(a.authored, _anchor);
    a.anchored = anchorAsset(a.authored, _anchor);
    return a;
}

std::string Parser::pathFromToken(const Token& t) {
    return std::string(t.text.substr(1, t.text.size() - 2));
}

Value Parser::parseTypedValue(const ValueType* type, const std::string& typeName, bool isArray) {
    SourceLocation where = here();
    if (peek().isIdent("None")) {
        next();
        return Value::none(typeName, isArray, where);
    }
    const ValueType& t = *type;
    if (t.scalar == ScalarType::Opaque)
        fail("no value for an attribute of valueless type '" + typeName + "'");
    if (!isArray) {
        if (t.isNumeric()) {
            if (t.components == 1) return Value::number(typeName, parseNumber(t), where);
            std::vector<double> v;
            v.reserve(static_cast<std::size_t>(t.components));
            parseNumericElement(t, v);
            return Value::tuple(typeName, std::move(v), where);
        }
        if (t.scalar == ScalarType::Asset) {
            if (peek().kind != TokenKind::Asset && peek().kind != TokenKind::String)
                fail("an asset path '@...@'");
            return Value::asset(assetFromToken(next()), where);
        }
        return Value::string(typeName, expectString("a quoted string"), where);
    }
    DepthGuard guard(*this);
    expect('[');
    if (t.isNumeric()) {
        std::vector<double> v;
        while (!peek().is(']')) {
            parseNumericElement(t, v);
            if (!accept(',') && !peek().is(']')) fail("',' or ']'");
        }
        next();
        return Value::numberArray(typeName, t.components, std::move(v), where);
    }
    if (t.scalar == ScalarType::Asset) {
        std::vector<AssetPath> v;
        while (!peek().is(']')) {
            if (peek().kind != TokenKind::Asset && peek().kind != TokenKind::String)
                fail("an asset path '@...@' or ']'");
            v.push_back(assetFromToken(next()));
            if (!accept(',') && !peek().is(']')) fail("',' or ']'");
        }
        next();
        return Value::assetArray(std::move(v), where);
    }
    std::vector<std::string> v;
    while (!peek().is(']')) {
        v.push_back(expectString("a quoted string or ']'"));
        if (!accept(',') && !peek().is(']')) fail("',' or ']'");
    }
    next();
    return Value::stringArray(typeName, std::move(v), where);
}

void Parser::parseNumericElement(const ValueType& type, std::vector<double>& out) {
    if (type.components == 1) {
        out.push_back(parseNumber(type));
        return;
    }
    DepthGuard guard(*this);
    expect('(');
    const int rows = type.rows > 0 ? type.rows : 1;
    const int cols = type.rows > 0 ? type.rows : type.components;
    for (int r = 0; r < rows; ++r) {
        if (type.rows > 0) {
            if (r > 0) expect(',');
            expect('(');
        }
        for (int c = 0; c < cols; ++c) {
            if (c > 0) expect(',');
            out.push_back(parseNumber(type));
        }
        if (type.rows > 0) {
            accept(',');  // a tuple may end in a comma (ListOf is list_tail in the grammar)
            expect(')');
        }
    }
    accept(',');
    expect(')');
}

double Parser::parseNumber(const ValueType& type) {
    Token t = peek();
    if (type.scalar == ScalarType::Bool) {
        double v = parseBool(t);
        next();
        return v;
    }
    const char* what = type.isInteger() ? "an integer" : "a number";
    double v = 0.0;
    if (t.kind == TokenKind::String && !type.isInteger()) {
        // _GetImpl<floating>: the strings "inf", "-inf" and "nan" convert.
        std::string s = unescapeString(t.text);
        if (s != "inf" && s != "-inf" && s != "nan") fail(what);
        v = s == "nan" ? std::nan("") : (s[0] == '-' ? -HUGE_VAL : HUGE_VAL);
    } else if (t.kind == TokenKind::Number || t.kind == TokenKind::Identifier) {
        v = parseScalarNumber(t, type.isInteger(), type.isUnsigned());
    } else {
        fail(what);
    }
    // The declared type's range (USD rejects an int of 2^32 rather than wrapping it).
    double lo = 0.0, hi = 0.0;
    const char* range = nullptr;
    switch (type.scalar) {
        case ScalarType::UChar: lo = 0.0, hi = 255.0, range = "an integer in [0, 255] (uchar)"; break;
        case ScalarType::Int: lo = -2147483648.0, hi = 2147483647.0, range = "an integer in [-2^31, 2^31 - 1] (int)"; break;
        case ScalarType::UInt: lo = 0.0, hi = 4294967295.0, range = "an integer in [0, 2^32 - 1] (uint)"; break;
        case ScalarType::Int64: lo = -9223372036854775808.0, hi = 9223372036854775807.0, range = "an integer in [-2^63, 2^63 - 1] (int64)"; break;
        case ScalarType::UInt64: lo = 0.0, hi = 18446744073709551615.0, range = "an integer in [0, 2^64 - 1] (uint64)"; break;
        default: break;
    }
    if (range && !(v >= lo && v <= hi)) _lex.fail(t, range);
    next();
    return v;
}

namespace {
// Sdf_BoolFromString (parserHelpers.cpp): true/false, yes/no, 1/0, in any case.
std::optional<bool> boolFromString(std::string_view s) {
    std::string lower(s);
    for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (lower == "true" || lower == "yes" || lower == "1") return true;
    if (lower == "false" || lower == "no" || lower == "0") return false;
    return std::nullopt;
}
}  // namespace

double Parser::parseBool(const Token& t) {
    // _GetImpl<bool> (parserHelpers.h): a number is true when nonzero (NaN included); strings
    // and identifiers go through Sdf_BoolFromString.
    if (t.kind == TokenKind::Number || t.isIdent("inf") || t.isIdent("nan"))
        return parseScalarNumber(t, false, false) != 0.0 ? 1.0 : 0.0;
    std::optional<bool> b;
    if (t.kind == TokenKind::Identifier) b = boolFromString(t.text);
    if (t.kind == TokenKind::String) b = boolFromString(unescapeString(t.text));
    if (!b) _lex.fail(t, "a bool (a number, true/false, yes/no or 1/0)");
    return *b ? 1.0 : 0.0;
}

double Parser::parseScalarNumber(const Token& t, bool integer, bool isUnsigned) {
    const char* what = integer ? "an integer" : "a number";
    std::string_view s = t.text;
    if (t.kind == TokenKind::Identifier) {
        if (!integer && (s == "inf" || s == "nan")) return s == "inf" ? HUGE_VAL : std::nan("");
        _lex.fail(t, what);
    }
    if (!s.empty() && s[0] == '+') s.remove_prefix(1);
    const char* first = s.data();
    const char* last = s.data() + s.size();
    if (integer) {
        std::int64_t i = 0;
        auto [p, ec] = std::from_chars(first, last, i);
        if (ec == std::errc() && p == last) {
            if (isUnsigned && i < 0) _lex.fail(t, "an unsigned integer");
            return static_cast<double>(i);
        }
        if (isUnsigned) {
            std::uint64_t u = 0;
            auto [pu, ecu] = std::from_chars(first, last, u);
            if (ecu == std::errc() && pu == last) return static_cast<double>(u);
        }
    }
    double d = 0.0;
    auto [p, ec] = std::from_chars(first, last, d);
    if (p != last || (ec != std::errc() && ec != std::errc::result_out_of_range))
        _lex.fail(t, what);
    if (ec == std::errc::result_out_of_range) {
        // Overflow reads as +-inf, underflow as 0, as strtod does.
        bool neg = s[0] == '-';
        auto e = s.find_first_of("eE");
        bool tiny = e != std::string_view::npos && e + 1 < s.size() && s[e + 1] == '-';
        d = tiny ? 0.0 : (neg ? -HUGE_VAL : HUGE_VAL);
    }
    // _GetImpl<integral>: a finite number converts, truncated toward zero (its range is
    // checked by the caller); inf and nan do not.
    if (integer) {
        if (!std::isfinite(d)) _lex.fail(t, "a finite number for an integer");
        d = std::trunc(d);
    }
    return d;
}

Value Parser::parseGenericValue() {
    DepthGuard guard(*this);
    SourceLocation where = here();
    const Token& t = peek();
    switch (t.kind) {
        case TokenKind::String:
            return Value::string("string", unescapeString(next().text), where);
        case TokenKind::Asset:
            return Value::asset(assetFromToken(next()), where);
        case TokenKind::Path:
            return Value::path(pathFromToken(next()), where);
        case TokenKind::Number: {
            bool isInt = t.text.find_first_of(".eEin") == std::string_view::npos;
            double v = parseScalarNumber(t, false, false);
            next();
            return Value::number(isInt ? "int" : "double", v, where);
        }
        case TokenKind::Identifier: {
            Token id = next();
            if (id.text == "None") return Value::none({}, false, where);
            if (id.text == "true" || id.text == "false")
                return Value::number("bool", id.text == "true" ? 1.0 : 0.0, where);
            if (id.text == "inf") return Value::number("double", HUGE_VAL, where);
            if (id.text == "nan") return Value::number("double", std::nan(""), where);
            return Value::string("token", std::string(id.text), where);
        }
        default:
            break;
    }
    if (t.is('{')) return Value::dictionary(parseDictionary(), where);
    if (t.is('(')) {
        next();
        std::vector<double> v;
        while (!accept(')')) {
            Value e = parseGenericValue();
            if (auto d = e.getDouble()) {
                v.push_back(*d);
            } else if (auto tup = e.getTuple()) {
                v.insert(v.end(), tup->begin(), tup->end());
            } else {
                throw ParseError(e.location(),
                                 "expected a number in a tuple, found " + quoted(e.toString()));
            }
            if (!accept(',') && !peek().is(')')) fail("',' or ')'");
        }
        return Value::tuple("double", std::move(v), where);
    }
    if (t.is('[')) {
        next();
        std::vector<Value> items;
        while (!accept(']')) {
            items.push_back(parseGenericValue());
            if (!accept(',') && !peek().is(']')) fail("',' or ']'");
        }
        if (items.empty()) return Value::stringArray("string", {}, where);
        const Value& first = items.front();
        for (const Value& e : items)
            if (e.kind() != first.kind() || e.components() != first.components())
                throw ParseError(e.location(), "expected array elements of one type, found " +
                                                   quoted(e.toString()));
        switch (first.kind()) {
            case Value::Kind::Number:
            case Value::Kind::Tuple: {
                std::vector<double> v;
                for (const Value& e : items) {
                    if (auto d = e.getDouble())
                        v.push_back(*d);
                    else if (auto tup = e.getTuple())
                        v.insert(v.end(), tup->begin(), tup->end());
                }
                return Value::numberArray(first.typeName(), first.components(), std::move(v),
                                          where);
            }
            case Value::Kind::String:
            case Value::Kind::Path: {
                std::vector<std::string> v;
                for (const Value& e : items)
                    v.push_back(e.getString() ? *e.getString() : *e.getPath());
                return Value::stringArray(first.typeName(), std::move(v), where);
            }
            case Value::Kind::Asset: {
                std::vector<AssetPath> v;
                for (const Value& e : items) v.push_back(*e.getAsset());
                return Value::assetArray(std::move(v), where);
            }
            default:
                throw ParseError(first.location(),
                                 "expected numbers, strings, assets or paths in a list, found " +
                                     quoted(first.toString()));
        }
    }
    fail("a value");
}

Value Parser::parseMetadataValue(std::string_view key) {
    return isRegisteredMetadataField(key) ? parseGenericValue() : parseUnregisteredValue();
}

Value Parser::parseUnregisteredValue() {
    const Lexer start = _lex;
    try {
        return parseGenericValue();
    } catch (const ParseError&) {
        _lex = start;  // a tuple of strings, a nested or mixed list...: keep the text
    }
    SourceLocation where = here();
    const char* begin = peek().text.data();
    skipValue();  // throws a located error if this is no value at all
    return Value::string("unregistered", std::string(begin, _lex.lastEnd()), where);
}

void Parser::skipValue() {
    DepthGuard guard(*this);
    const Token& t = peek();
    if (t.kind == TokenKind::String || t.kind == TokenKind::Asset || t.kind == TokenKind::Path ||
        t.kind == TokenKind::Number || t.kind == TokenKind::Identifier) {
        next();
        return;
    }
    if (t.is('{')) {
        parseDictionary();
        return;
    }
    if (!t.is('(') && !t.is('[')) fail("a value");
    const char close = t.is('(') ? ')' : ']';
    next();
    while (!accept(close)) {
        skipValue();
        if (!accept(',') && !peek().is(close)) fail(std::string("',' or '") + close + "'");
    }
}

Dictionary Parser::parseDictionary() {
    DepthGuard guard(*this);
    expect('{');
    Dictionary d;
    for (;;) {
        if (accept('}')) return d;
        if (accept(';')) continue;
        if (peek().kind == TokenKind::End) fail("'}'");
        // Untyped map entries: prefixSubstitutions { "a": "b", ... }, relocates { </a>: </b> }.
        if (peek().kind == TokenKind::String || peek().kind == TokenKind::Path) {
            Token keyTok = next();
            std::string key = keyTok.kind == TokenKind::String ? unescapeString(keyTok.text)
                                                               : pathFromToken(keyTok);
            expect(':');
            d[key] = parseGenericValue();
            if (!accept(',') && !peek().is('}') && !peek().is(';')) fail("',' or '}'");
            continue;
        }
        Token typeTok = expectIdent("a value type name or '}'");
        bool isArray = false;
        if (accept('[')) {
            expect(']');
            isArray = true;
        }
        std::string key;
        if (peek().kind == TokenKind::String) {
            key = unescapeString(next().text);
        } else {
            key = std::string(expectIdent("a dictionary key").text);
        }
        expect('=');
        if (typeTok.text == "dictionary") {
            SourceLocation where = here();
            d[key] = Value::dictionary(parseDictionary(), where);
        } else if (const ValueType* type = findValueType(typeTok.text)) {
            d[key] = parseTypedValue(type, std::string(type->name), isArray);
        } else {
            _lex.fail(typeTok, "a value type name");
        }
    }
}

}  // namespace principled::usd::detail
