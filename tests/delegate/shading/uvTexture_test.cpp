// SPDX-License-Identifier: Apache-2.0
#include "delegate/shading/uvTexture.h"

#include <gtest/gtest.h>

#include "delegate/shading/colorSpace.h"
#include "testImages.h"

using namespace principled;
using namespace principled::shading;
using principled::shading::test::TempDir;
using principled::shading::test::writeImage;

namespace {

hd::MaterialNode textureNode(const std::string& file, std::map<hd::Token, hd::Value> params = {}) {
    hd::MaterialNode n;
    n.path = hd::Path("/M/Tex");
    n.identifier = hd::Token("UsdUVTexture");
    n.parameters = std::move(params);
    n.parameters[hd::Token("file")] = hd::Value(file);
    return n;
}

// A uniform 2x2 image of one colour (row order is irrelevant).
bool writeFlat(const std::string& path, int channels, const glm::vec4& c, OIIO::TypeDesc format,
               const std::vector<std::pair<std::string, std::string>>& attributes = {}) {
    std::vector<float> px;
    for (int i = 0; i < 4; ++i)
        for (int k = 0; k < channels; ++k) px.push_back(c[k]);
    return writeImage(path, 2, 2, channels, px, format, attributes);
}

void expectNear(const glm::vec4& a, const glm::vec4& b, float tol = 1e-4f) {
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(a[i], b[i], tol) << "channel " << i;
}

class UvTextureTest : public ::testing::Test {
  protected:
    TempDir dir;
    TextureCache cache;
    std::vector<std::string> notes;
    const glm::vec2 mid{0.5f, 0.5f};
};

// 8-bit code 188 is sRGB-encoded 0.5 linear (0.7354 * 255 = 187.5).
constexpr float kCode = 188.0f / 255.0f;

}  // namespace

TEST_F(UvTextureTest, AutoDecodesEightBitRgbAsSrgb) {
    std::string png = dir.file("rgb8.png");
    ASSERT_TRUE(writeFlat(png, 3, glm::vec4(kCode), OIIO::TypeDesc::UINT8));
    UvTexture t = UvTexture::resolve(textureNode(png), cache, &notes);
    ASSERT_NE(t.texture, nullptr);
    EXPECT_TRUE(t.decodeSrgb);
    float lin = srgbToLinear(kCode);
    EXPECT_NEAR(lin, 0.5f, 0.003f);
    expectNear(t.sample(cache, mid), glm::vec4(lin, lin, lin, 1.0f));
    EXPECT_TRUE(notes.empty());
}

TEST_F(UvTextureTest, RawIsNotDecoded) {
    std::string png = dir.file("raw8.png");
    ASSERT_TRUE(writeFlat(png, 3, glm::vec4(kCode), OIIO::TypeDesc::UINT8));
    UvTexture t = UvTexture::resolve(
        textureNode(png, {{hd::Token("sourceColorSpace"), hd::Value(hd::Token("raw"))}}), cache,
        &notes);
    EXPECT_FALSE(t.decodeSrgb);
    expectNear(t.sample(cache, mid), glm::vec4(kCode, kCode, kCode, 1.0f));
}

TEST_F(UvTextureTest, AutoKeepsFloatSixteenBitAndGreyscaleRaw) {
    std::string exr = dir.file("f.exr"), png16 = dir.file("rgb16.png"), grey = dir.file("g8.png");
    ASSERT_TRUE(writeFlat(exr, 3, glm::vec4(0.25f), OIIO::TypeDesc::FLOAT));
    ASSERT_TRUE(writeFlat(png16, 3, glm::vec4(0.25f), OIIO::TypeDesc::UINT16));
    ASSERT_TRUE(writeFlat(grey, 1, glm::vec4(kCode), OIIO::TypeDesc::UINT8));
    for (const std::string& f : {exr, png16, grey}) {
        UvTexture t = UvTexture::resolve(textureNode(f), cache, &notes);
        ASSERT_NE(t.texture, nullptr) << f;
        EXPECT_FALSE(t.decodeSrgb) << f;
    }
    // Forced sRGB on a float file decodes.
    UvTexture forced = UvTexture::resolve(
        textureNode(exr, {{hd::Token("sourceColorSpace"), hd::Value(hd::Token("sRGB"))}}), cache,
        &notes);
    EXPECT_TRUE(forced.decodeSrgb);
    EXPECT_NEAR(forced.sample(cache, mid).x, srgbToLinear(0.25f), 1e-5f);
}

TEST_F(UvTextureTest, AutoFollowsExplicitColourMetadata) {
    // A 16-bit PNG with gAMA 2.2 is sRGB; an 8-bit RGB PNG with gAMA 1.0 stays raw.
    std::string png16 = dir.file("gamma22.png"), png8 = dir.file("gamma1.png");
    ASSERT_TRUE(writeFlat(png16, 3, glm::vec4(0.25f), OIIO::TypeDesc::UINT16,
                          {{"oiio:ColorSpace", "Gamma2.2"}}));
    ASSERT_TRUE(writeFlat(png8, 3, glm::vec4(kCode), OIIO::TypeDesc::UINT8,
                          {{"oiio:ColorSpace", "linear"}}));
    UvTexture t = UvTexture::resolve(textureNode(png16), cache, &notes);
    ASSERT_NE(t.texture, nullptr);
    EXPECT_EQ(t.texture->info().colorTag, ColorTag::Srgb);
    EXPECT_TRUE(t.decodeSrgb);
    EXPECT_NEAR(t.sample(cache, mid).x, srgbToLinear(0.25f), 1e-4f);
    UvTexture lin = UvTexture::resolve(textureNode(png8), cache, &notes);
    ASSERT_NE(lin.texture, nullptr);
    EXPECT_EQ(lin.texture->info().colorTag, ColorTag::Linear);
    EXPECT_FALSE(lin.decodeSrgb);
    EXPECT_NEAR(lin.sample(cache, mid).x, kCode, 1e-5f);
}

TEST_F(UvTextureTest, ScaleAndBiasApplyAfterDecoding) {
    std::string exr = dir.file("sb.exr");
    ASSERT_TRUE(writeFlat(exr, 4, glm::vec4(0.25f, 0.5f, 0.75f, 1.0f), OIIO::TypeDesc::FLOAT));
    UvTexture t = UvTexture::resolve(
        textureNode(exr, {{hd::Token("scale"), hd::Value(glm::vec4(2, 2, 2, 1))},
                          {hd::Token("bias"), hd::Value(glm::vec4(-1, -1, -1, 0))}}),
        cache, &notes);
    expectNear(t.sample(cache, mid), glm::vec4(-0.5f, 0.0f, 0.5f, 1.0f));

    std::string png = dir.file("sb8.png");
    ASSERT_TRUE(writeFlat(png, 3, glm::vec4(kCode), OIIO::TypeDesc::UINT8));
    UvTexture s =
        UvTexture::resolve(textureNode(png, {{hd::Token("scale"), hd::Value(glm::vec4(-1.0f))},
                                             {hd::Token("bias"), hd::Value(glm::vec4(1.0f))}}),
                           cache, &notes);
    float lin = srgbToLinear(kCode);
    expectNear(s.sample(cache, mid), glm::vec4(1 - lin, 1 - lin, 1 - lin, 0.0f));
}

TEST_F(UvTextureTest, MissingFileUsesTheFallbackAndNotesThePathOnce) {
    std::string missing = dir.file("missing.png");
    auto node = textureNode(missing, {{hd::Token("fallback"), hd::Value(glm::vec4(1, 0, 0, 1))},
                                      {hd::Token("scale"), hd::Value(glm::vec4(0.5f))}});
    UvTexture t = UvTexture::resolve(node, cache, &notes);
    EXPECT_EQ(t.texture, nullptr);
    expectNear(t.sample(cache, mid), glm::vec4(1, 0, 0, 1));  // fallback as is
    ASSERT_EQ(notes.size(), 1u);
    EXPECT_NE(notes[0].find(missing), std::string::npos) << notes[0];
    EXPECT_NE(notes[0].find("/M/Tex"), std::string::npos) << notes[0];
    UvTexture again = UvTexture::resolve(node, cache, &notes);
    EXPECT_EQ(notes.size(), 1u);  // reported once per cache
    expectNear(again.sample(cache, mid), glm::vec4(1, 0, 0, 1));
}

TEST_F(UvTextureTest, DefaultFallbackIsOpaqueBlack) {
    UvTexture t = UvTexture::resolve(textureNode(""), cache, &notes);
    expectNear(t.sample(cache, mid), glm::vec4(0, 0, 0, 1));
    EXPECT_EQ(notes.size(), 1u);
}

TEST_F(UvTextureTest, WrapTokensAndUseMetadata) {
    // Column 0 black, column 1 white; s = 1.25 is column 0.5 past the right edge.
    std::string plain = dir.file("plain.exr"), tagged = dir.file("tagged.exr");
    std::vector<float> px = {0, 1, 0, 1};
    ASSERT_TRUE(writeImage(plain, 2, 2, 1, px, OIIO::TypeDesc::FLOAT));
    ASSERT_TRUE(
        writeImage(tagged, 2, 2, 1, px, OIIO::TypeDesc::FLOAT, {{"wrapmodes", "periodic,mirror"}}));
    glm::vec2 outside(1.25f, 0.5f);
    auto wrapNode = [&](const std::string& f, const char* w) {
        return textureNode(f, {{hd::Token("wrapS"), hd::Value(hd::Token(w))},
                               {hd::Token("wrapT"), hd::Value(hd::Token(w))}});
    };
    EXPECT_NEAR(
        UvTexture::resolve(wrapNode(plain, "black"), cache, &notes).sample(cache, outside).x, 0.0f,
        1e-5f);
    EXPECT_NEAR(
        UvTexture::resolve(wrapNode(plain, "clamp"), cache, &notes).sample(cache, outside).x, 1.0f,
        1e-5f);
    EXPECT_NEAR(
        UvTexture::resolve(wrapNode(plain, "repeat"), cache, &notes).sample(cache, outside).x, 0.0f,
        1e-5f);
    EXPECT_NEAR(
        UvTexture::resolve(wrapNode(plain, "mirror"), cache, &notes).sample(cache, outside).x, 1.0f,
        1e-5f);
    // useMetadata without metadata: black (the fallback mode is the default input value too).
    UvTexture noMeta = UvTexture::resolve(textureNode(plain), cache, &notes);
    EXPECT_EQ(noMeta.wrapS, Wrap::Black);
    EXPECT_NEAR(noMeta.sample(cache, outside).x, 0.0f, 1e-5f);
    EXPECT_TRUE(notes.empty());
    UvTexture meta = UvTexture::resolve(wrapNode(tagged, "useMetadata"), cache, &notes);
    ASSERT_NE(meta.texture, nullptr);
    EXPECT_TRUE(meta.texture->info().hasWrapMetadata);
    EXPECT_EQ(meta.wrapS, Wrap::Repeat);
    EXPECT_EQ(meta.wrapT, Wrap::Mirror);
    // An unknown token is noted and treated as useMetadata.
    UvTexture bad = UvTexture::resolve(wrapNode(tagged, "wobble"), cache, &notes);
    EXPECT_EQ(bad.wrapS, Wrap::Repeat);
    EXPECT_EQ(notes.size(), 2u);
}

TEST_F(UvTextureTest, UsdWgCorpusColourSpaces) {
    const std::string root =
        PRINCIPLED_SOURCE_DIR "/../shared/usd-wg/test_assets/TextureFileFormatTests/";
    struct Case {
        const char* file;
        bool srgb;
    };
    // auto: 8-bit RGB(A) and sRGB ICC profiles decode; greyscale (ICC "Greyscale D50") and
    // png_rgb_32-bit (16-bit, ICC "Display P3 (Linear)") stay raw.
    const Case cases[] = {
        {"jpeg_rgb_8-bit.jpg", true},        {"jpeg_cmyk_8-bit.jpg", true},
        {"jpeg_grayscale_8-bit.jpg", false}, {"png_grayscale_8-bit.png", false},
        {"png_grayscale_16-bit.png", false}, {"png_rgb_8-bit.png", true},
        {"png_rgb_16-bit.png", true},        {"png_rgb_32-bit.png", false},
    };
    for (const Case& c : cases) {
        UvTexture t = UvTexture::resolve(textureNode(root + c.file), cache, &notes);
        ASSERT_NE(t.texture, nullptr) << c.file;
        EXPECT_EQ(t.decodeSrgb, c.srgb) << c.file;
    }
    EXPECT_TRUE(notes.empty());
}

TEST_F(UvTextureTest, MissingUdimTileGivesTheFallback) {
    ASSERT_TRUE(writeFlat(dir.file("u.1001.exr"), 3, glm::vec4(0.5f), OIIO::TypeDesc::FLOAT));
    UvTexture t =
        UvTexture::resolve(textureNode(dir.file("u.<UDIM>.exr"),
                                       {{hd::Token("fallback"), hd::Value(glm::vec4(0, 1, 0, 1))},
                                        {hd::Token("scale"), hd::Value(glm::vec4(2.0f))}}),
                           cache, &notes);
    ASSERT_NE(t.texture, nullptr);
    expectNear(t.sample(cache, mid), glm::vec4(1.0f, 1.0f, 1.0f, 2.0f));
    expectNear(t.sample(cache, glm::vec2(1.5f, 0.5f)), glm::vec4(0, 1, 0, 1));
    EXPECT_TRUE(notes.empty());
}
