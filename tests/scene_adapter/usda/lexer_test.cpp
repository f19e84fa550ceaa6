// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/lexer.h"

#include <gtest/gtest.h>

#include "testUtil.h"

namespace principled::usd {
namespace {

std::vector<Token> lexAll(std::string_view text) {
    Lexer lex(text, "l.usda");
    std::vector<Token> out;
    while (lex.peek().kind != TokenKind::End) out.push_back(lex.next());
    return out;
}

TEST(Lexer, TokenKindsAndPositions) {
    auto t = lexAll(
        "#usda 1.0\ndef Xform \"n\" {\n  float3 xformOp:translate.timeSamples = { -1.5e3: (inf, "
        "-inf, nan) }\n  @a.png@ @@@b@c@@@ </A/B.prop> 'q' \"\"\"tri\nple\"\"\" ; }");
    ASSERT_GE(t.size(), 10u);
    EXPECT_TRUE(t[0].isIdent("def"));
    EXPECT_EQ(t[0].line, 2);
    EXPECT_EQ(t[0].column, 1);
    EXPECT_TRUE(t[1].isIdent("Xform"));
    EXPECT_EQ(t[2].kind, TokenKind::String);
    EXPECT_EQ(t[2].text, "\"n\"");
    EXPECT_TRUE(t[3].is('{'));
    EXPECT_TRUE(t[5].isIdent("xformOp:translate"));
    EXPECT_EQ(t[5].column, 10);
    EXPECT_TRUE(t[6].is('.'));
    EXPECT_TRUE(t[7].isIdent("timeSamples"));
    EXPECT_EQ(t[10].kind, TokenKind::Number);
    EXPECT_EQ(t[10].text, "-1.5e3");
    EXPECT_TRUE(t[11].is(':'));
    EXPECT_TRUE(t[13].isIdent("inf"));
    EXPECT_EQ(t[15].kind, TokenKind::Number);
    EXPECT_EQ(t[15].text, "-inf");
    std::size_t i = 0;
    while (i < t.size() && t[i].kind != TokenKind::Asset) ++i;
    ASSERT_LT(i + 4, t.size());
    EXPECT_EQ(t[i].text, "@a.png@");
    EXPECT_EQ(t[i].line, 4);
    EXPECT_EQ(t[i + 1].text, "@@@b@c@@@");
    EXPECT_EQ(t[i + 2].kind, TokenKind::Path);
    EXPECT_EQ(t[i + 2].text, "</A/B.prop>");
    EXPECT_EQ(t[i + 3].text, "'q'");
    EXPECT_EQ(t[i + 4].kind, TokenKind::String);
    EXPECT_EQ(t.back().line, 5);  // the triple-quoted string spans a line
}

TEST(Lexer, Comments) {
    auto t = lexAll("# hash\n// slashes\n/* block\n */ x /* inline */ y # end");
    ASSERT_EQ(t.size(), 2u);
    EXPECT_TRUE(t[0].isIdent("x"));
    EXPECT_EQ(t[0].line, 4);
    EXPECT_EQ(t[0].column, 5);
    EXPECT_TRUE(t[1].isIdent("y"));
}

TEST(Lexer, Describe) {
    Lexer lex("x", "l.usda");
    EXPECT_EQ(Lexer::describe(lex.peek()), "'x'");
    lex.next();
    EXPECT_EQ(Lexer::describe(lex.peek()), "end of file");
    Token longToken{TokenKind::Identifier,
                    std::string_view("abcdefghijklmnopqrstuvwxyzabcdefghijklmnopqrstuvwxyz"), 1, 1};
    EXPECT_EQ(Lexer::describe(longToken), "'abcdefghijklmnopqrstuvwxyzabcdefghijklmn...'");
}

TEST(Lexer, Unescape) {
    EXPECT_EQ(unescapeString("\"a\\nb\""), "a\nb");
    EXPECT_EQ(unescapeString("'it\\'s'"), "it's");
    EXPECT_EQ(unescapeString("\"\"\"x\"y\"\"\""), "x\"y");
    EXPECT_EQ(unescapeString("\"\\x41\\t\\\\\""), "A\t\\");
    EXPECT_EQ(unescapeString("\"\""), "");
}

TEST(Lexer, UnterminatedTokensThrowWithPositions) {
    EXPECT_EQ(test::parseErrorOf([] { lexAll("x \"abc"); }),
              "l.usda:1:7: expected '\"' closing the string opened at 1:3, found end of file");
    EXPECT_EQ(
        test::parseErrorOf([] { lexAll("\n  @@@abc@@"); }),
        "l.usda:2:11: expected '@@@' closing the asset path opened at 2:3, found end of file");
    EXPECT_EQ(test::parseErrorOf([] { lexAll("<abc"); }),
              "l.usda:1:5: expected '>' closing the path opened at 1:1, found end of file");
}

}  // namespace
}  // namespace principled::usd
