// SPDX-License-Identifier: Apache-2.0
#include "delegate/subdiv/stencils.h"

#include <gtest/gtest.h>

using namespace principled::subdiv;

TEST(Stencils, BuilderMergesDuplicatesAndDropsZeros) {
    StencilsBuilder b;
    b.beginRow();
    b.add(2, 0.25f);
    b.add(0, 0.5f);
    b.add(2, 0.25f);
    b.add(1, 0.0f);
    b.endRow();
    b.beginRow();
    b.add(1, 1.0f);
    b.endRow();
    Stencils s = b.finish();
    ASSERT_EQ(s.rows(), 2u);
    EXPECT_EQ(s.offsets, (std::vector<int>{0, 2, 3}));
    EXPECT_EQ(s.indices, (std::vector<int>{0, 2, 1}));
    EXPECT_EQ(s.weights, (std::vector<float>{0.5f, 0.5f, 1.0f}));
    EXPECT_EQ(s.sourceCount(), 3u);
}

TEST(Stencils, ApplyAnyComponentCountSerialAndParallel) {
    // Row r averages elements r and r + 1 of a long source, enough rows for parallel tasks.
    const int rows = 20000;
    StencilsBuilder b;
    for (int r = 0; r < rows; ++r) {
        b.beginRow();
        b.add(r, 0.5f);
        b.add(r + 1, 0.5f);
        b.endRow();
    }
    Stencils s = b.finish();
    for (int comps : {1, 2, 3, 4, 7}) {
        std::vector<float> src(size_t(rows + 1) * comps), dst(size_t(rows) * comps);
        for (size_t i = 0; i < src.size(); ++i) src[i] = float(i / comps) + float(i % comps) * 0.1f;
        s.apply(src.data(), comps, dst.data());
        for (int r = 0; r < rows; r += 997)
            for (int c = 0; c < comps; ++c)
                ASSERT_NEAR(dst[size_t(r) * comps + c], float(r) + 0.5f + 0.1f * c, 1e-3f);
    }
}
