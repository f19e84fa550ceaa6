// SPDX-License-Identifier: Apache-2.0
// Grammar: pxr/usd/sdf/textFileFormatParser.h (the PEGTL grammar of USDA 1.0), restricted to
// what assets use. Newlines are treated as whitespace; ';' separators are accepted.
#include "scene_adapter/usda/parser.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "scene_adapter/usda/assetResolver.h"
#include "scene_adapter/usda/parserImpl.h"

namespace principled::usd {

namespace detail {

namespace {
constexpr std::string_view kNewestVersion = "1.1";

// "M.m" or "M.m.p" (SdfUsdaData::ValidateLayerVersionString) as {M, m, p}; nullopt otherwise.
std::optional<std::array<long, 3>> parseLayerVersion(std::string_view v) {
    std::array<long, 3> parts{0, 0, 0};
    for (int i = 0; i < 3; ++i) {
        std::size_t digits = 0;
        long n = 0;
        while (digits < v.size() && v[digits] >= '0' && v[digits] <= '9' && digits < 9)
            n = n * 10 + (v[digits++] - '0');
        if (digits == 0) return std::nullopt;
        parts[static_cast<std::size_t>(i)] = n;
        v.remove_prefix(digits);
        if (v.empty()) return i >= 1 ? std::optional(parts) : std::nullopt;
        if (v[0] != '.') return std::nullopt;
        v.remove_prefix(1);
    }
    return std::nullopt;
}
}  // namespace

std::string_view Parser::checkHeader(std::string_view text, const std::string& file) {
    refuseBinary(text, file);
    std::string_view body = text;
    if (body.substr(0, 3) == "\xEF\xBB\xBF") body.remove_prefix(3);  // UTF-8 byte order mark
    std::string_view first = body.substr(0, body.find_first_of("\r\n"));
    while (!first.empty() && (first.back() == ' ' || first.back() == '\t'))
        first.remove_suffix(1);
    bool ok =
        first.substr(0, 5) == "#usda" && first.size() > 5 && (first[5] == ' ' || first[5] == '\t');
    if (ok) {
        std::string_view version = first.substr(5);
        version.remove_prefix(std::min(version.find_first_not_of(" \t"), version.size()));
        // Every version from 1.0 to the newest we read (1.1, which OpenUSD writes for splines
        // with tangent algorithms; a spline attribute is still refused where it is authored).
        auto v = parseLayerVersion(version);
        if (v && !((*v)[0] == 1 && ((*v)[1] == 0 || ((*v)[1] == 1 && (*v)[2] == 0))))
            throw ParseError({file, 1, 1},
                             "expected a USDA version from 1.0 to " + std::string(kNewestVersion) +
                                 " (the versions this reader supports), found " +
                                 quoteText(first));
        ok = v.has_value();
    }
    if (!ok) {
        std::string found = body.empty()    ? "end of file"
                            : first.empty() ? "'\\n'"
                                            : Lexer::describe(Token{TokenKind::Punct, first, 1, 1});
        throw ParseError({file, 1, 1}, "expected '#usda 1.0', found " + found);
    }
    return body;
}

void Parser::addPrim(std::vector<std::unique_ptr<PrimSpec>>& siblings, SiblingNames& seen,
                     std::unique_ptr<PrimSpec> prim) {
    seen.emplace(prim->name, prim.get());
    siblings.push_back(std::move(prim));
}

std::optional<ListOpKind> Parser::listOpKeyword(const Token& t) {
    if (t.kind != TokenKind::Identifier) return std::nullopt;
    if (t.text == "prepend") return ListOpKind::Prepend;
    if (t.text == "append") return ListOpKind::Append;
    if (t.text == "delete") return ListOpKind::Delete;
    if (t.text == "add") return ListOpKind::Add;
    if (t.text == "reorder") return ListOpKind::Reorder;
    return std::nullopt;
}

std::unique_ptr<Layer> Parser::parse() {
    auto layer = std::make_unique<Layer>();
    layer->file = _lex.file();
    layer->anchorDir = _anchor;
    if (peek().is('(')) parseLayerMetadata(*layer);
    SiblingNames seen;
    for (;;) {
        const Token& t = peek();
        if (t.kind == TokenKind::End) break;
        if (t.is(';')) {
            next();
        } else if (t.isIdent("def") || t.isIdent("over") || t.isIdent("class")) {
            addPrim(layer->rootPrims, seen, parsePrim(seen));
        } else if (t.isIdent("reorder")) {
            next();
            if (!peek().isIdent("rootPrims")) fail("'rootPrims'");
            next();
            parseReorder(layer->rootPrimOrder, true);
        } else {
            fail("'def', 'over' or 'class'");
        }
    }
    layer->indexRootPrims();
    return layer;
}

template <class Entry>
void Parser::parseMetadataBlock(Dictionary& metadata, const char* docKey, std::string_view expected,
                                Entry&& entry) {
    DepthGuard guard(*this);
    expect('(');
    for (;;) {
        const Token& t = peek();
        if (t.is(')')) {
            next();
            return;
        }
        if (t.is(';')) {
            next();
            continue;
        }
        if (t.kind == TokenKind::String) {
            SourceLocation where = here();
            metadata[docKey] = Value::string("string", unescapeString(next().text), where);
            continue;
        }
        ListOpKind op = ListOpKind::Explicit;
        if (auto k = listOpKeyword(t)) {
            op = *k;
            next();
        }
        Token key = expectIdent(expected);
        Token eq = expect('=');
        if (key.text == "symmetryFunction" || key.text == "permission" ||
            key.text == "displayUnit") {
            // Their own grammar rules (textFileFormatParser.h): an identifier on the line of the
            // '=', optional for symmetryFunction (Sdf writes `symmetryFunction = ` when empty).
            metadata[std::string(key.text)] =
                parseIdentifierOnLine(key.text, eq, key.text == "symmetryFunction");
            continue;
        }
        entry(op, key.text);
    }
}

Value Parser::parseIdentifierOnLine(std::string_view key, const Token& eq, bool optional) {
    SourceLocation where = here();
    const Token& t = peek();
    if (t.kind == TokenKind::Identifier && t.line == eq.line)
        return Value::string("token", std::string(next().text), where);
    if (optional) return Value::string("token", "", _lex.location(eq));
    fail("an identifier after '" + std::string(key) + " =' on line " + std::to_string(eq.line));
}

void Parser::parseLayerMetadata(Layer& layer) {
    parseMetadataBlock(layer.metadata, "doc", "a layer metadata name or ')'",
                       [&](ListOpKind, std::string_view key) {
                           if (key == "subLayers")
                               parseSubLayers(layer);
                           else
                               layer.metadata[std::string(key)] = parseMetadataValue(key);
                       });
}

void Parser::parseSubLayers(Layer& layer) {
    DepthGuard guard(*this);
    expect('[');
    while (!peek().is(']')) {
        if (peek().kind != TokenKind::Asset) fail("a sublayer asset path '@...@' or ']'");
        SubLayer sub;
        sub.location = here();
        AssetPath a = assetFromToken(next());
        sub.assetPath = a.authored;
        sub.resolvedPath = a.resolved;
        if (peek().is('(')) sub.offset = parseLayerOffsetParens();
        layer.subLayers.push_back(std::move(sub));
        if (!accept(',') && !peek().is(']')) fail("',' or ']'");
    }
    next();
}

LayerOffset Parser::parseLayerOffsetParens() {
    DepthGuard guard(*this);
    LayerOffset off;
    expect('(');
    while (!accept(')')) {
        if (accept(';')) continue;
        Token key = expectIdent("'offset', 'scale' or ')'");
        expect('=');
        if (key.text == "offset" || key.text == "scale") {
            static const ValueType kDouble{"double", ScalarType::Double, 1, 0, false};
            double v = parseNumber(kDouble);
            (key.text == "offset" ? off.offset : off.scale) = v;
        } else {
            parseGenericValue();  // customData and other arc metadata: accepted, unused
        }
    }
    return off;
}

std::unique_ptr<PrimSpec> Parser::parsePrim(const SiblingNames& seen) {
    DepthGuard guard(*this);
    auto spec = std::make_unique<PrimSpec>();
    spec->location = here();
    Token kw = next();
    spec->specifier = kw.text == "def"     ? Specifier::Def
                      : kw.text == "class" ? Specifier::Class
                                           : Specifier::Over;
    if (peek().kind == TokenKind::Identifier) {
        spec->typeName = std::string(next().text);
        while (accept('.'))  // PrimTypeName = list<Identifier, Dot>: "Foo.Bar"
            spec->typeName += "." + std::string(expectIdent("a type name after '.'").text);
    }
    if (peek().kind != TokenKind::String) fail("a quoted prim name");
    Token nameTok = peek();
    spec->name = expectString("a quoted prim name");
    if (spec->name.empty() ||
        spec->name.find_first_of("/.{}<>[]:=@\"' \t\r\n") != std::string::npos ||
        std::any_of(spec->name.begin(), spec->name.end(),
                    [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; }) ||
        (spec->name[0] >= '0' && spec->name[0] <= '9'))
        _lex.fail(nameTok, "a valid prim name (an identifier)");
    // One layer holds one spec per path (Sdf): a second spec of the same name is an error.
    if (auto it = seen.find(spec->name); it != seen.end())
        _lex.fail(nameTok, "a unique prim name (" + quoteText(spec->name) +
                               " is already defined at " +
                               std::to_string(it->second->location.line) + ":" +
                               std::to_string(it->second->location.column) + ")");
    if (peek().is('(')) parsePrimMetadata(*spec);
    expect('{');
    parsePrimBody(*spec);
    return spec;
}

void Parser::parsePrimMetadata(PrimSpec& spec) {
    parseMetadataBlock(spec.metadata, "documentation", "a prim metadata name or ')'",
                       [&](ListOpKind op, std::string_view k) { parsePrimMetadataEntry(spec, op, k); });
}

void Parser::parsePrimMetadataEntry(PrimSpec& spec, ListOpKind op, std::string_view k) {
    if (k == "references") {
        spec.references.set(op, parseReferenceList());
    } else if (k == "payload") {
        spec.payloads.set(op, parseReferenceList());
    } else if (k == "inherits") {
        spec.inherits.set(op, parsePathList());
    } else if (k == "specializes") {
        spec.specializes.set(op, parsePathList());
    } else if (k == "variantSets") {
        spec.variantSetNames.set(op, parseStringList());
    } else if (k == "apiSchemas") {
        spec.apiSchemas.set(op, parseStringList());
    } else if (k == "variants") {
        SourceLocation where = here();
        Dictionary d = parseDictionary();
        for (const auto& [name, v] : d) {
            if (auto s = v.getString()) spec.variantSelections[name] = *s;
        }
        spec.metadata["variants"] = Value::dictionary(std::move(d), where);
    } else {
        std::string name(k == "doc" ? std::string_view("documentation") : k);
        spec.metadata[name] = parseMetadataValue(name);
    }
}

void Parser::parseReorder(std::optional<std::vector<std::string>>& names, bool) {
    expect('=');
    names = parseStringList();
}

void Parser::parsePrimBody(PrimSpec& spec) {
    SiblingNames seen;
    PropertyIndex properties;
    for (;;) {
        const Token& t = peek();
        if (t.is('}')) {
            next();
            spec.indexChildren();
            return;
        }
        if (t.kind == TokenKind::End) fail("'}'");
        if (t.is(';')) {
            next();
        } else if (t.isIdent("def") || t.isIdent("over") || t.isIdent("class")) {
            addPrim(spec.children, seen, parsePrim(seen));
        } else if (t.isIdent("variantSet")) {
            parseVariantSet(spec);
        } else if (t.isIdent("reorder")) {
            next();
            if (peek().isIdent("nameChildren")) {
                next();
                parseReorder(spec.nameChildrenOrder, false);
            } else if (peek().isIdent("properties")) {
                next();
                parseReorder(spec.propertyOrder, false);
            } else if (peek().isIdent("rel")) {
                parseRelationship(spec, properties, ListOpKind::Reorder, false);
            } else {
                parseProperty(spec, properties, ListOpKind::Reorder);  // reorder x.connect = [...]
            }
        } else if (t.kind == TokenKind::Identifier) {
            parseProperty(spec, properties);
        } else {
            fail("a property, a child prim, 'variantSet' or '}'");
        }
    }
}

void Parser::parseVariantSet(PrimSpec& spec) {
    DepthGuard guard(*this);
    SourceLocation where = here();
    next();  // variantSet
    std::string setName = expectString("a quoted variant set name");
    expect('=');
    expect('{');
    VariantSetSpec* vs = nullptr;
    for (auto& existing : spec.variantSets)
        if (existing.name == setName) vs = &existing;
    if (!vs) {
        spec.variantSets.push_back(VariantSetSpec{setName, {}, where});
        vs = &spec.variantSets.back();
    }
    for (;;) {
        if (accept('}')) break;
        if (accept(';')) continue;
        if (peek().kind != TokenKind::String) fail("a quoted variant name or '}'");
        auto variant = std::make_unique<PrimSpec>();
        variant->isVariant = true;
        variant->location = here();
        variant->name = expectString("a quoted variant name");
        if (peek().is('(')) parsePrimMetadata(*variant);
        expect('{');
        {
            DepthGuard inner(*this);
            parsePrimBody(*variant);
        }
        // A set's list is small; look it up again because push_back may move `vs`.
        vs->variants.push_back(std::move(variant));
    }
}

void Parser::parseProperty(PrimSpec& spec, PropertyIndex& index, std::optional<ListOpKind> op) {
    if (!op) {
        op = listOpKeyword(peek());
        if (op) next();
    }
    SourceLocation where = here();
    bool custom = false;
    if (peek().isIdent("custom")) {
        custom = true;
        next();
    }
    Variability variability = Variability::Varying;
    if (peek().isIdent("uniform")) {
        variability = Variability::Uniform;
        next();
    } else if (peek().isIdent("varying")) {
        next();
    } else if (peek().isIdent("config")) {
        variability = Variability::Config;
        next();
    }
    if (peek().isIdent("rel")) {
        parseRelationship(spec, index, op, custom);
        return;
    }
    if (peek().kind != TokenKind::Identifier) fail("a value type name or 'rel'");
    Token typeTok = peek();
    const ValueType* type = findValueType(typeTok.text);
    if (!type) fail("a value type name or 'rel'");
    next();
    bool isArray = false;
    if (accept('[')) {
        expect(']');
        isArray = true;
    }
    Token nameTok = expectIdent("a property name");
    std::string name(nameTok.text);
    std::string_view field;
    if (accept('.')) {
        Token f = expectIdent("'connect' or 'timeSamples'");
        if (f.text != "connect" && f.text != "timeSamples")
            _lex.fail(f, "'connect' or 'timeSamples'");
        field = f.text;
    }
    auto [slot, added] = index.attributes.try_emplace(name, spec.attributes.size());
    if (added) {
        spec.attributes.emplace_back();
        spec.attributes.back().name = name;
        spec.attributes.back().location = where;
    }
    AttributeSpec* attr = &spec.attributes[slot->second];
    attr->typeName = std::string(type->name);  // a legacy alias ("Vec3f") as its Sdf name
    attr->isArray = isArray;
    attr->custom = attr->custom || custom;
    if (variability != Variability::Varying) attr->variability = variability;
    if (field == "connect") {
        if (accept('=')) {
            if (!attr->connections) attr->connections = std::make_shared<ListOp<PathItem>>();
            attr->connections->set(op.value_or(ListOpKind::Explicit), parsePathList());
            attr->hasConnections = true;
        }
    } else if (field == "timeSamples") {
        expect('=');
        parseTimeSamples(*attr, type);
    } else if (peek().is('=')) {
        // One spec per property: a second value for it in the same prim is an error (Sdf), not
        // a silent override.
        if (attr->defaultValue || attr->animationBlock)
            _lex.fail(nameTok, "a property given one value (" + quoteText(name) + " already has one, declared at " +
                                   std::to_string(attr->location.line) + ":" + std::to_string(attr->location.column) + ")");
        next();
        if (peek().isIdent("AnimationBlock")) {
            next();
            attr->animationBlock = true;
        } else {
            attr->defaultValue = parseTypedValue(type, attr->typeName, isArray);
        }
    } else {
        // A declaration without a value ends its line (or opens its metadata).
        const Token& t = peek();
        if (t.line == nameTok.line && t.kind != TokenKind::End && !t.is('(') && !t.is(';') &&
            !t.is('}'))
            fail("'='");
    }
    if (peek().is('(')) parsePropertyMetadata(attr->metadata);
}

void Parser::parseRelationship(PrimSpec& spec, PropertyIndex& index,
                               std::optional<ListOpKind> op, bool custom) {
    SourceLocation where = here();
    next();  // rel
    Token nameTok = expectIdent("a relationship name");
    std::string name(nameTok.text);
    if (accept('.')) {
        Token f = expectIdent("'default'");
        if (f.text != "default") _lex.fail(f, "'default'");
    }
    auto [slot, added] = index.relationships.try_emplace(name, spec.relationships.size());
    if (added) {
        spec.relationships.emplace_back();
        spec.relationships.back().name = name;
        spec.relationships.back().location = where;
    }
    RelationshipSpec* rel = &spec.relationships[slot->second];
    rel->custom = rel->custom || custom;
    if (accept('=')) {
        rel->targets.set(op.value_or(ListOpKind::Explicit), parsePathList());
        rel->hasTargets = true;
    }
    if (peek().is('(')) parsePropertyMetadata(rel->metadata);
}

void Parser::parsePropertyMetadata(Dictionary& metadata) {
    parseMetadataBlock(metadata, "documentation", "a property metadata name or ')'",
                       [&](ListOpKind, std::string_view key) {
                           std::string name(key == "doc" ? std::string_view("documentation") : key);
                           metadata[name] = parseMetadataValue(name);
                       });
}

void Parser::parseTimeSamples(AttributeSpec& attr, const ValueType* type) {
    DepthGuard guard(*this);
    expect('{');
    attr.hasTimeSamples = true;
    static const ValueType kDouble{"double", ScalarType::Double, 1, 0, false};
    while (!accept('}')) {
        if (peek().kind == TokenKind::End) fail("'}'");
        double t = parseNumber(kDouble);
        expect(':');
        attr.timeSamples[t] = parseTypedValue(type, attr.typeName, attr.isArray);
        if (!accept(',') && !peek().is('}')) fail("',' or '}'");
    }
}

std::vector<Reference> Parser::parseReferenceList() {
    DepthGuard guard(*this);
    std::vector<Reference> out;
    if (peek().isIdent("None")) {
        next();
        return out;
    }
    if (!accept('[')) {
        out.push_back(parseReference());
        return out;
    }
    while (!accept(']')) {
        out.push_back(parseReference());
        if (!accept(',') && !peek().is(']')) fail("',' or ']'");
    }
    return out;
}

Reference Parser::parseReference() {
    Reference r;
    r.location = here();
    const Token& t = peek();
    if (t.kind == TokenKind::Asset) {
        AssetPath a = assetFromToken(next());
        r.assetPath = a.authored;
        r.resolvedPath = a.resolved;
        if (peek().kind == TokenKind::Path) r.primPath = pathFromToken(next());
    } else if (t.kind == TokenKind::Path) {
        r.primPath = pathFromToken(next());
        if (r.primPath.empty() || r.primPath[0] != '/')
            throw ParseError(r.location, "expected an absolute prim path, found " +
                                             quoteText("<" + r.primPath + ">"));
    } else {
        fail("an asset path '@...@' or a prim path '<...>'");
    }
    if (peek().is('(')) r.offset = parseLayerOffsetParens();
    return r;
}

std::vector<PathItem> Parser::parsePathList() {
    DepthGuard guard(*this);
    std::vector<PathItem> out;
    if (peek().isIdent("None")) {
        next();
        return out;
    }
    if (peek().kind == TokenKind::Path) {
        SourceLocation where = here();
        out.push_back({pathFromToken(next()), where});
        return out;
    }
    if (!accept('[')) fail("a path '<...>', a list of paths or None");
    while (!accept(']')) {
        if (peek().kind != TokenKind::Path) fail("a path '<...>' or ']'");
        SourceLocation where = here();
        out.push_back({pathFromToken(next()), where});
        if (!accept(',') && !peek().is(']')) fail("',' or ']'");
    }
    return out;
}

std::vector<std::string> Parser::parseStringList() {
    DepthGuard guard(*this);
    std::vector<std::string> out;
    if (peek().isIdent("None")) {
        next();
        return out;
    }
    if (peek().kind == TokenKind::String) {
        out.push_back(unescapeString(next().text));
        return out;
    }
    if (!accept('[')) fail("a quoted string or a list of strings");
    while (!accept(']')) {
        out.push_back(expectString("a quoted string or ']'"));
        if (!accept(',') && !peek().is(']')) fail("',' or ']'");
    }
    return out;
}

}  // namespace detail

std::unique_ptr<Layer> parseLayer(std::string_view text, const std::string& file,
                                  const std::string& anchorDir) {
    detail::Parser parser(text, file, anchorDir);
    return parser.parse();
}

std::unique_ptr<Layer> parseLayerFile(const std::string& file) {
    std::string text = readLayerText(file);
    return parseLayer(text, file, directoryOf(file));
}

}  // namespace principled::usd
