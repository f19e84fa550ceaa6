#include "delegate/imageWriter.h"
#include "delegate/imageio/nativeWriter.h"

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
    // The pixel aspect ratio reaches the EXR header (1 unless given).
    EXPECT_FLOAT_EQ(in->spec().get_float_attribute("PixelAspectRatio", 0.0f), 1.0f);
    std::string wide = (dir / "wide.exr").string();
    ASSERT_TRUE(embree::writeImage(wide, 2, 1, {layer}, &err, 2.0f)) << err;
    auto win = OIIO::ImageInput::open(wide);
    ASSERT_TRUE(win);
    EXPECT_FLOAT_EQ(win->spec().get_float_attribute("PixelAspectRatio", 0.0f), 2.0f);
}

// EXR and PNG are encoded by delegate/imageio/nativeWriter.cpp with OpenEXRCore and libpng (no
// OpenImageIO at write time):
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

// Many AOV layers in one EXR (the render writes each AOV as "layer.channel"), an RGBA PNG through
// libpng, and errors from OpenEXR / libpng naming the file.
TEST(ImageWriter, ManyAovLayersRgbaPngAndErrors) {
    auto dir = std::filesystem::temp_directory_path() / "principled_imageWriter_test";
    std::filesystem::create_directories(dir);
    const int w = 19, h = 33, layersN = 10;
    std::vector<std::vector<float>> data(layersN);
    std::vector<embree::ImageLayer> layers;
    for (int l = 0; l < layersN; ++l) {
        data[l].resize(size_t(w) * h * 4);
        for (size_t i = 0; i < data[l].size(); ++i) data[l][i] = float(l) * 1000.0f + float(i) * 0.125f;
        layers.push_back({l == 0 ? "" : "aov" + std::to_string(l), {"R", "G", "B", "A"}, data[l].data()});
    }
    std::string err;
    std::string exr = (dir / "many.exr").string();
    ASSERT_TRUE(embree::writeImage(exr, w, h, layers, &err)) << err;
    auto in = OIIO::ImageInput::open(exr);
    ASSERT_TRUE(in) << OIIO::geterror();
    const auto& spec = in->spec();
    ASSERT_EQ(spec.nchannels, layersN * 4);
    EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(spec.alpha_channel, 3);
    std::vector<float> back(size_t(w) * h * spec.nchannels);
    ASSERT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, back.data()));
    for (int c = 0; c < spec.nchannels; ++c) {
        const std::string& name = spec.channelnames[size_t(c)];
        auto dot = name.find('.');
        int l = dot == std::string::npos ? 0 : std::stoi(name.substr(3, dot - 3));
        int k = int(std::string("RGBA").find(name.back()));
        ASSERT_GE(k, 0) << name;
        for (size_t p = 0; p < size_t(w) * h; ++p)
            ASSERT_EQ(back[p * spec.nchannels + c], data[size_t(l)][p * 4 + k]) << name << " " << p;
    }

    std::vector<uint8_t> rgba(size_t(w) * h * 4);
    for (size_t i = 0; i < rgba.size(); ++i) rgba[i] = uint8_t(i * 37);
    std::string png = (dir / "rgba.png").string();
    ASSERT_TRUE(imageio::writePng8(png, w, h, 4, rgba.data(), &err)) << err;
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);  // straight alpha, as written
    auto pin = OIIO::ImageInput::open(png, &config);
    ASSERT_TRUE(pin);
    ASSERT_EQ(pin->spec().nchannels, 4);
    std::vector<uint8_t> pb(rgba.size());
    ASSERT_TRUE(pin->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, pb.data()));
    EXPECT_TRUE(pb == rgba);

    EXPECT_FALSE(embree::writeImage("/nonexistent/dir/x.exr", w, h, layers, &err));
    EXPECT_NE(err.find("/nonexistent/dir/x.exr: OpenEXR"), std::string::npos) << err;
    EXPECT_FALSE(embree::writeImage("/nonexistent/dir/x.png", w, h, layers, &err));
    EXPECT_NE(err.find("/nonexistent/dir/x.png: libpng"), std::string::npos) << err;
}
