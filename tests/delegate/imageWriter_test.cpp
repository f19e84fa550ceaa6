#include "delegate/imageWriter.h"

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>

using namespace principled;

TEST(ImageWriter, SrgbTransferMatchesTheStandard) {
    EXPECT_FLOAT_EQ(embree::linearToSrgb(0.0f), 0.0f);
    EXPECT_FLOAT_EQ(embree::linearToSrgb(1.0f), 1.0f);
    EXPECT_NEAR(embree::linearToSrgb(0.18f), 0.4614f, 1e-3f);     // mid grey
    EXPECT_NEAR(embree::linearToSrgb(0.002f), 0.02584f, 1e-5f);   // linear segment
    EXPECT_FLOAT_EQ(embree::linearToSrgb(NAN), 0.0f);
}

TEST(ImageWriter, ExrRoundTripsFloatsAndPngIsEncoded) {
    auto dir = std::filesystem::temp_directory_path() / "principled_imageWriter_test";
    std::filesystem::create_directories(dir);
    float px[2 * 4] = {0.18f, 2.5f, 0.0f, 1.0f, NAN, 0.5f, 1.0f, 0.0f};
    embree::ImageLayer layer{"", {"R", "G", "B", "A"}, px};
    std::string err;
    std::string exr = (dir / "a.exr").string(), png = (dir / "a.png").string();
    ASSERT_TRUE(embree::writeImage(exr, 2, 1, {layer}, &err)) << err;
    ASSERT_TRUE(embree::writeImage(png, 2, 1, {layer}, &err)) << err;
    auto in = OIIO::ImageInput::open(exr);
    ASSERT_TRUE(in);
    std::vector<float> back(8);
    ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, back.data()));
    EXPECT_FLOAT_EQ(back[1], 2.5f);  // HDR kept
    EXPECT_FLOAT_EQ(back[4], 0.0f);  // NaN never written
    auto pin = OIIO::ImageInput::open(png);
    ASSERT_TRUE(pin);
    EXPECT_EQ(pin->spec().nchannels, 3);
    std::vector<unsigned char> b(6);
    ASSERT_TRUE(pin->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, b.data()));
    EXPECT_EQ(b[0], 118);  // 0.18 -> sRGB 0.4614 -> 118
    EXPECT_EQ(b[1], 255);  // clamped
    EXPECT_FALSE(embree::writeImage((dir / "a.bmp").string(), 2, 1, {layer}, &err));
    EXPECT_NE(err.find(".exr or .png"), std::string::npos);
}
