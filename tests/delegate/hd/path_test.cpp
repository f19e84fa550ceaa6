#include "delegate/hd/path.h"

#include <gtest/gtest.h>

using principled::hd::Path;
using principled::hd::Token;

TEST(Token, InternedTextComparesByIdentity) {
    Token a("mesh"), b(std::string("me") + "sh"), c("sphere");
    EXPECT_EQ(a, b);
    EXPECT_NE(a, c);
    EXPECT_EQ(a.hash(), b.hash());
    EXPECT_TRUE(Token().empty());
}

TEST(Path, NamesParentsAndProperties) {
    Path p("/World/Looks/Mat");
    EXPECT_EQ(p.name(), "Mat");
    EXPECT_EQ(p.parent(), Path("/World/Looks"));
    EXPECT_EQ(Path("/World").parent(), Path::absoluteRoot());
    EXPECT_TRUE(Path::absoluteRoot().parent().empty());
    Path prop = p.appendProperty("inputs:diffuseColor");
    EXPECT_TRUE(prop.isPropertyPath());
    EXPECT_FALSE(p.isPropertyPath());
    EXPECT_EQ(prop.name(), "inputs:diffuseColor");
    EXPECT_EQ(prop.primPath(), p);
    EXPECT_EQ(prop.parent(), p);
    EXPECT_EQ(Path::absoluteRoot().appendChild("A"), Path("/A"));
}

TEST(Path, PrefixIsElementWise) {
    EXPECT_TRUE(Path("/World/Sphere").hasPrefix(Path("/World")));
    EXPECT_TRUE(Path("/World").hasPrefix(Path("/World")));
    EXPECT_FALSE(Path("/WorldX/Sphere").hasPrefix(Path("/World")));
    EXPECT_TRUE(Path("/World.attr").hasPrefix(Path("/World")));
    EXPECT_TRUE(Path("/A").hasPrefix(Path::absoluteRoot()));
}
