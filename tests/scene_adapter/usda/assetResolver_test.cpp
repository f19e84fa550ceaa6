// SPDX-License-Identifier: Apache-2.0
#include "scene_adapter/usda/assetResolver.h"

#include <gtest/gtest.h>

#include "scene_adapter/usda/error.h"
#include "testUtil.h"

namespace principled::usd {
namespace {

TEST(AssetResolver, RelativeAbsoluteMissingUdim) {
    test::TempDir dir("resolver");
    std::string tex = dir.write("a/tex.png", "x");
    EXPECT_EQ(resolveAsset("tex.png", dir.path("a")), tex);
    EXPECT_EQ(resolveAsset("./a/../a/tex.png", dir.path()), tex);
    EXPECT_EQ(resolveAsset(tex, "/nowhere"), tex);
    EXPECT_EQ(resolveAsset("missing.png", dir.path()), "");
    EXPECT_EQ(resolveAsset("", dir.path()), "");
    EXPECT_EQ(resolveAsset("t.<UDIM>.png", dir.path("a")), dir.path("a/t.<UDIM>.png"));
    EXPECT_EQ(directoryOf(tex), dir.path("a"));
}

TEST(AssetResolver, RefusesBinaryAndUnreadableFiles) {
    test::TempDir dir("binary");
    std::string crate = dir.write("x.usdc", std::string("PXR-USDC\x00\x01", 10));
    std::string zip = dir.write("x.usdz", std::string("PK\x03\x04....", 8));
    try {
        readLayerText(crate);
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(
            std::string(e.what()).rfind(crate + ": binary USD crate file (usdc) is not "
                                                "supported: the text format (usda) is required",
                                        0),
            0u)
            << e.what();
    }
    try {
        readLayerText(zip);
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("USDZ/zip archive is not supported"),
                  std::string::npos);
    }
    EXPECT_THROW(readLayerText(dir.path("nope.usda")), Error);
    EXPECT_THROW(readLayerText(dir.path()), Error);
}

}  // namespace
}  // namespace principled::usd
