// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/listOp.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>

namespace principled::usd {
namespace {

using Names = std::vector<std::string>;

TEST(ListOp, ExplicitReplaces) {
    ListOp<std::string> op;
    op.set(ListOpKind::Explicit, {"a", "b", "a"});
    Names list{"x"};
    op.applyTo(list);
    EXPECT_EQ(list, (Names{"a", "b"}));
}

TEST(ListOp, PrependAppendDeleteAddReorder) {
    Names list{"a", "b", "c"};
    ListOp<std::string> op;
    op.set(ListOpKind::Prepend, {"c", "z"});
    op.set(ListOpKind::Append, {"a"});
    op.set(ListOpKind::Delete, {"b"});
    op.set(ListOpKind::Add, {"c", "n"});
    op.applyTo(list);
    EXPECT_EQ(list, (Names{"c", "z", "n", "a"}));
    ListOp<std::string> reorder;
    reorder.set(ListOpKind::Reorder, {"a", "missing", "n"});
    reorder.applyTo(list);
    EXPECT_EQ(list, (Names{"c", "z", "a", "n"}));
    Names letters{"a", "b", "c", "d", "e"};
    ListOp<std::string> dThenB;
    dThenB.set(ListOpKind::Reorder, {"d", "b"});
    dThenB.applyTo(letters);
    EXPECT_EQ(letters, (Names{"a", "d", "e", "b", "c"}));  // runs move with their item
    EXPECT_FALSE(reorder.empty());
    EXPECT_TRUE(ListOp<std::string>{}.empty());
}

// Sdf's list editing written the direct way (a search per item), as the reference the linear
// implementation must match: delete, add (if absent), prepend (first of repeats, moved to the
// front), append (each moved to the end in turn).
Names reference(Names list, const Names& del, const Names& add, const Names& pre, const Names& app) {
    auto remove = [&list](const std::string& x) { list.erase(std::remove(list.begin(), list.end(), x), list.end()); };
    auto has = [](const Names& l, const std::string& x) { return std::find(l.begin(), l.end(), x) != l.end(); };
    for (const auto& x : del) remove(x);
    for (const auto& x : add)
        if (!has(list, x)) list.push_back(x);
    Names front;
    for (const auto& x : pre) {
        if (has(front, x)) continue;
        remove(x);
        front.push_back(x);
    }
    list.insert(list.begin(), front.begin(), front.end());
    for (const auto& x : app) {
        remove(x);
        list.push_back(x);
    }
    return list;
}

TEST(ListOp, MatchesTheItemByItemDefinitionWithRepeats) {
    std::mt19937 rng(7);
    auto names = [&rng](int n) {
        Names v;
        for (int i = 0; i < n; ++i) v.push_back(std::string(1, char('a' + rng() % 8)));
        return v;
    };
    for (int trial = 0; trial < 2000; ++trial) {
        const Names base = names(int(rng() % 6)), del = names(int(rng() % 3)), add = names(int(rng() % 4)),
                    pre = names(int(rng() % 4)), app = names(int(rng() % 4));
        ListOp<std::string> op;
        op.set(ListOpKind::Delete, del);
        op.set(ListOpKind::Add, add);
        op.set(ListOpKind::Prepend, pre);
        op.set(ListOpKind::Append, app);
        Names list = base;
        op.applyTo(list);
        ASSERT_EQ(list, reference(base, del, add, pre, app)) << "trial " << trial;
    }
}

TEST(ListOp, HundredThousandTargetsComposeInLinearTime) {
    // Over a list of 100k, a prepend of 100k (half of them already present) and an append of
    // the same: with a search per item this took ~10 s (a 100k-target relationship); it now takes
    // milliseconds. ctest's timeout is the bound.
    Names list, pre;
    for (int i = 0; i < 100000; ++i) list.push_back("/t" + std::to_string(i));
    for (int i = 50000; i < 150000; ++i) pre.push_back("/t" + std::to_string(i));
    ListOp<std::string> op;
    op.set(ListOpKind::Prepend, pre);
    op.set(ListOpKind::Append, {"/t0"});
    op.applyTo(list);
    ASSERT_EQ(list.size(), 150000u);
    EXPECT_EQ(list.front(), "/t50000");
    EXPECT_EQ(list[100000], "/t1");
    EXPECT_EQ(list.back(), "/t0");
}

}  // namespace
}  // namespace principled::usd
