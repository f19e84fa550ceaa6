// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/listOp.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace principled::usd
