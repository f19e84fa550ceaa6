// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/path.h"

#include <gtest/gtest.h>

namespace principled::usd {
namespace {

TEST(Path, Basics) {
    EXPECT_EQ(path::parent("/A/B"), "/A");
    EXPECT_EQ(path::parent("/A"), "/");
    EXPECT_EQ(path::parent("/"), "");
    EXPECT_EQ(path::name("/A/B"), "B");
    EXPECT_EQ(path::child("/", "A"), "/A");
    EXPECT_EQ(path::child("/A", "B"), "/A/B");
    EXPECT_EQ(path::stripVariants("/A{geo=x}{c=y}/B"), "/A/B");
}

TEST(Path, Prefixes) {
    EXPECT_TRUE(path::hasPrefix("/A/B", "/A"));
    EXPECT_TRUE(path::hasPrefix("/A.prop", "/A"));
    EXPECT_TRUE(path::hasPrefix("/A", "/A"));
    EXPECT_FALSE(path::hasPrefix("/AB", "/A"));
    EXPECT_TRUE(path::hasPrefix("/x", "/"));
    EXPECT_EQ(path::replacePrefix("/Proto/Mat.outputs:x", "/Proto", "/Inst"),
              "/Inst/Mat.outputs:x");
    EXPECT_EQ(path::replacePrefix("/A/B", "/", "/Root"), "/Root/A/B");
}

TEST(Path, MakeAbsolute) {
    EXPECT_EQ(path::makeAbsolute("/X", "/A/B"), "/X");
    EXPECT_EQ(path::makeAbsolute("../Mat", "/A/B"), "/A/Mat");
    EXPECT_EQ(path::makeAbsolute("Child.prop", "/A"), "/A/Child.prop");
    EXPECT_EQ(path::makeAbsolute(".prop", "/A"), "/A.prop");
    EXPECT_EQ(path::makeAbsolute("../../..", "/A"), "/");
    auto [prim, prop] = path::splitProperty("/A/B.inputs:file");
    EXPECT_EQ(prim, "/A/B");
    EXPECT_EQ(prop, "inputs:file");
}

}  // namespace
}  // namespace principled::usd
