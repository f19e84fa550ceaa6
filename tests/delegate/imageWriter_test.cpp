#include "delegate/imageWriter.h"

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdlib>
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

// EXR and PNG are encoded by delegate/imageio/nativeWriter.cpp (no OpenImageIO at write time):
// OpenImageIO must read back every value, across ZIP blocks of 16 lines with a partial last
// block, layered and long (> 31 characters) channel names, and the same pixels as its own
// writer (PRINCIPLED_IMAGE_WRITER=oiio).
TEST(ImageWriter, NativeExrAndPngReadBackExactlyAndMatchOpenImageIO) {
    auto dir = std::filesystem::temp_directory_path() / "principled_imageWriter_test";
    std::filesystem::create_directories(dir);
    const int w = 37, h = 53;
    std::vector<float> rgba(size_t(w) * h * 4), aov(size_t(w) * h * 2);
    for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = float((i * 7919) % 1000) / 997.0f * (i % 5 ? 1.0f : 40.0f);
    for (size_t i = 0; i < aov.size(); ++i) aov[i] = -float(i) * 0.25f;
    std::vector<embree::ImageLayer> layers = {
        {"", {"R", "G", "B", "A"}, rgba.data()},
        {"a_rather_long_layer_name_for_the_test", {"X", "Y"}, aov.data()}};
    auto read = [](const std::string& path, std::vector<std::string>* names) {
        auto in = OIIO::ImageInput::open(path);
        EXPECT_TRUE(in) << OIIO::geterror();
        if (!in) return std::vector<float>();
        const auto& spec = in->spec();
        if (names) *names = spec.channelnames;
        std::vector<float> px(size_t(spec.width) * spec.height * spec.nchannels);
        EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
        return px;
    };
    std::string err;
    std::string exr = (dir / "native.exr").string(), png = (dir / "native.png").string();
    ASSERT_TRUE(embree::writeImage(exr, w, h, layers, &err)) << err;
    ASSERT_TRUE(embree::writeImage(png, w, h, {layers[0]}, &err)) << err;
    std::vector<std::string> names;
    std::vector<float> back = read(exr, &names);
    ASSERT_EQ(names.size(), 6u);
    ASSERT_EQ(back.size(), size_t(w) * h * 6);
    // OpenImageIO lists R, G, B, A first, then the layer's channels.
    EXPECT_EQ(names[0], "R");
    EXPECT_EQ(names[3], "A");
    EXPECT_EQ(names[4], "a_rather_long_layer_name_for_the_test.X");
    for (size_t p = 0; p < size_t(w) * h; ++p) {
        for (int c = 0; c < 4; ++c) ASSERT_EQ(back[p * 6 + c], rgba[p * 4 + c]) << p << " " << c;
        for (int c = 0; c < 2; ++c) ASSERT_EQ(back[p * 6 + 4 + c], aov[p * 2 + c]) << p << " " << c;
    }
    setenv("PRINCIPLED_IMAGE_WRITER", "oiio", 1);
    std::string exrO = (dir / "oiio.exr").string(), pngO = (dir / "oiio.png").string();
    bool ok = embree::writeImage(exrO, w, h, layers, &err) && embree::writeImage(pngO, w, h, {layers[0]}, &err);
    unsetenv("PRINCIPLED_IMAGE_WRITER");
    ASSERT_TRUE(ok) << err;
    EXPECT_TRUE(read(exrO, nullptr) == back);
    EXPECT_TRUE(read(pngO, nullptr) == read(png, nullptr));
}
