// SPDX-License-Identifier: Apache-2.0
// The recursive-descent parser shared by parser.cpp (layer, prim and property structure) and
// valueParser.cpp (values, numbers, dictionaries). Internal to principled_usd.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "scene_adapter/usda/layer.h"
#include "scene_adapter/usda/lexer.h"
#include "scene_adapter/usda/parser.h"
#include "scene_adapter/usda/valueType.h"

namespace principled::usd::detail {

class Parser {
public:
    Parser(std::string_view text, const std::string& file, const std::string& anchorDir)
        : _text(text), _lex(checkHeader(text, file), file), _anchor(anchorDir) {}

    std::unique_ptr<Layer> parse();

private:
    // The `#usda 1.0` header line; the lexer then skips it as a comment.
    static std::string_view checkHeader(std::string_view text, const std::string& file);

    struct DepthGuard {
        Parser& p;
        explicit DepthGuard(Parser& parser) : p(parser) {
            if (++p._depth > kMaxNestingDepth)
                p._lex.fail(p._lex.peek(),
                            "at most " + std::to_string(kMaxNestingDepth) + " nested levels");
        }
        ~DepthGuard() { --p._depth; }
    };

    const Token& peek() const { return _lex.peek(); }
    Token next() { return _lex.next(); }
    SourceLocation here() const { return _lex.location(_lex.peek()); }
    [[noreturn]] void fail(std::string_view expected) const { _lex.fail(_lex.peek(), expected); }
    Token expect(char c) {
        if (!peek().is(c)) fail(std::string("'") + c + "'");
        return next();
    }
    bool accept(char c) {
        if (!peek().is(c)) return false;
        next();
        return true;
    }
    Token expectIdent(std::string_view what) {
        if (peek().kind != TokenKind::Identifier) fail(what);
        return next();
    }
    std::string expectString(std::string_view what) {
        if (peek().kind != TokenKind::String) fail(what);
        return unescapeString(next().text);
    }
    static std::optional<ListOpKind> listOpKeyword(const Token& t);

    /// One parenthesised metadata block `( "doc" key = value ... )`: a bare string is stored in
    /// metadata[docKey]; for each `[listop] key =`, entry(op, key) parses the value.
    template <class Entry>
    void parseMetadataBlock(Dictionary& metadata, const char* docKey, std::string_view expected,
                            Entry&& entry);
    /// `symmetryFunction`, `permission`, `displayUnit`: the identifier after `key =` on the
    /// line of the '=' (or an empty token when `optional` and there is none).
    Value parseIdentifierOnLine(std::string_view key, const Token& eq, bool optional);
    void parseLayerMetadata(Layer& layer);
    void parseSubLayers(Layer& layer);
    /// Names of the prims parsed so far in one body (views of their names).
    using SiblingNames = std::unordered_map<std::string_view, const PrimSpec*>;
    std::unique_ptr<PrimSpec> parsePrim(const SiblingNames& seen);
    void addPrim(std::vector<std::unique_ptr<PrimSpec>>& siblings, SiblingNames& seen,
                 std::unique_ptr<PrimSpec> prim);
    void parsePrimMetadata(PrimSpec& spec);
    void parsePrimMetadataEntry(PrimSpec& spec, ListOpKind op, std::string_view key);
    void parsePrimBody(PrimSpec& spec);
    void parseVariantSet(PrimSpec& spec);
    void parseReorder(std::optional<std::vector<std::string>>& names, bool root);
    /// Positions in spec.attributes / spec.relationships of the properties parsed so far in
    /// one prim body, by name: each statement finds its property in O(1), not by a scan.
    struct PropertyIndex {
        std::unordered_map<std::string, std::size_t> attributes, relationships;
    };
    void parseProperty(PrimSpec& spec, PropertyIndex& index,
                       std::optional<ListOpKind> op = std::nullopt);
    void parseRelationship(PrimSpec& spec, PropertyIndex& index, std::optional<ListOpKind> op,
                           bool custom);
    void parsePropertyMetadata(Dictionary& metadata);
    void parseTimeSamples(AttributeSpec& attr, const ValueType* type);

    std::vector<Reference> parseReferenceList();
    Reference parseReference();
    LayerOffset parseLayerOffsetParens();
    std::vector<PathItem> parsePathList();
    std::vector<std::string> parseStringList();

    Value parseTypedValue(const ValueType* type, const std::string& typeName, bool isArray);
    void parseNumericElement(const ValueType& type, std::vector<double>& out);
    double parseNumber(const ValueType& type);
    /// A bool value token as 1 or 0 (numbers, true/false, yes/no, 1/0, quoted or not).
    double parseBool(const Token& t);
    /// A number token (or inf / nan); an integer type truncates a finite fraction.
    double parseScalarNumber(const Token& t, bool integer, bool isUnsigned);
    Value parseGenericValue();
    /// The value of metadata field `key`: parseGenericValue() for a registered field; for any
    /// other, a value of any shape the grammar allows, kept as its text (typeName
    /// "unregistered") when it is not one parseGenericValue() can hold.
    Value parseMetadataValue(std::string_view key);
    Value parseUnregisteredValue();
    /// Consumes one value (atoms, tuples, lists, dictionaries) without building it.
    void skipValue();
    Dictionary parseDictionary();
    /// An @asset@ / @@@asset@@@ token, or a quoted string read as an asset path.
    AssetPath assetFromToken(const Token& t) const;
    static std::string pathFromToken(const Token& t);

    std::string_view _text;
    Lexer _lex;
    std::string _anchor;
    int _depth = 0;
};

}  // namespace principled::usd::detail
