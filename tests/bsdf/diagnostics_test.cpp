// SPDX-License-Identifier: Apache-2.0
#include "bsdf/diagnostics.h"

#include "testUtil.h"

namespace principled::bsdf {
namespace {

TEST(Diagnostics, SetParameterAcceptsNamesAndColours) {
    MaterialParams p = cliDefaults();
    EXPECT_EQ(p.baseColor, glm::vec3(1.0f));
    EXPECT_FLOAT_EQ(p.specular, 0.5f);
    EXPECT_FLOAT_EQ(p.roughness, 0.5f);
    EXPECT_FLOAT_EQ(p.sheenTint, 0.0f);
    EXPECT_EQ(setParameter(p, "roughness", "0.25"), "");
    EXPECT_FLOAT_EQ(p.roughness, 0.25f);
    EXPECT_EQ(setParameter(p, "baseColor", "1:0.5:0.2"), "");
    EXPECT_EQ(p.baseColor, glm::vec3(1.0f, 0.5f, 0.2f));
    EXPECT_EQ(setParameter(p, "baseColor", "0.3"), "");
    EXPECT_EQ(p.baseColor, glm::vec3(0.3f));
    EXPECT_EQ(setParameter(p, "thin", "1"), "");
    EXPECT_TRUE(p.thin);
    EXPECT_EQ(setParameter(p, "ior", "1.33"), "");
}

TEST(Diagnostics, SetParameterRejectsBadInput) {
    MaterialParams p = cliDefaults();
    EXPECT_NE(setParameter(p, "roughnes", "0.5"), "");
    EXPECT_NE(setParameter(p, "roughness", "abc"), "");
    EXPECT_NE(setParameter(p, "roughness", "0.5x"), "");
    EXPECT_NE(setParameter(p, "roughness", ""), "");
    EXPECT_NE(setParameter(p, "roughness", "1.5"), "");
    EXPECT_NE(setParameter(p, "roughness", "nan"), "");
    EXPECT_NE(setParameter(p, "baseColor", "1:2"), "");
    EXPECT_NE(setParameter(p, "baseColor", "1:0.5:x"), "");
    EXPECT_NE(setParameter(p, "ior", "0.5"), "");
    EXPECT_FLOAT_EQ(p.roughness, 0.5f);  // unchanged by failures
}

TEST(Diagnostics, AlbedoStandardErrorIsSmall) {
    Bsdf b(cliDefaults(), Options{});
    AlbedoResult r = directionalAlbedo(b, 0.5f, 100000);
    EXPECT_NEAR(r.albedo.x, 1.064f, 0.01f);
    EXPECT_LT(r.stdError.x, 0.003f);
}

}  // namespace
}  // namespace principled::bsdf
