// SPDX-License-Identifier: Apache-2.0
#include "delegate/shading/textureCache.h"

#include "delegate/imageio/imageIO.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <thread>

#include "testImages.h"
#include "textureCacheStress.h"

using namespace principled::shading;
using principled::shading::test::TempDir;
using principled::shading::test::writeImage;

namespace {

constexpr int kSize = 4;

// Texel (x, row) with row 0 the top of the file: distinct 8-bit codes per texel.
glm::vec4 code(int x, int row) {
    return glm::vec4(10 + 60 * x, 10 + 60 * row, 200, 255 - 40 * x) / 255.0f;
}

std::vector<float> pixels(int channels) {
    std::vector<float> p;
    for (int row = 0; row < kSize; ++row)
        for (int x = 0; x < kSize; ++x)
            for (int c = 0; c < channels; ++c) p.push_back(code(x, row)[c]);
    return p;
}

// The st of texel (x, row) centre: st (0,0) is the bottom-left, rows count from the top.
glm::vec2 centre(int x, int row) {
    return {(x + 0.5f) / kSize, 1.0f - (row + 0.5f) / kSize};
}

void expectNear(const glm::vec4& a, const glm::vec4& b, float tol = 1e-5f) {
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(a[i], b[i], tol) << "channel " << i;
}

class TextureCacheTest : public ::testing::Test {
  protected:
    TempDir dir;
    TextureCache cache;
};

}  // namespace

TEST_F(TextureCacheTest, TexelCentresReturnStoredValuesAndTIsFlipped) {
    std::string png = dir.file("rgb8.png");
    ASSERT_TRUE(writeImage(png, kSize, kSize, 3, pixels(3), OIIO::TypeDesc::UINT8));
    TextureOpenResult r = cache.open(png);
    ASSERT_NE(r.texture, nullptr) << r.error;
    EXPECT_EQ(r.texture->info().channels, 3);
    EXPECT_EQ(r.texture->info().bitsPerChannel, 8);
    for (int row = 0; row < kSize; ++row)
        for (int x = 0; x < kSize; ++x) {
            glm::vec4 want = code(x, row);
            want.w = 1.0f;  // 3 channels: a = 1
            // Raw 8-bit codes / 255: OpenImageIO does not linearise PNG pixels itself.
            expectNear(cache.sample(*r.texture, Wrap::Black, Wrap::Black, centre(x, row)), want);
        }
    // st (0,0) corner texel is the bottom row of the file.
    glm::vec4 bottomLeft =
        cache.sample(*r.texture, Wrap::Clamp, Wrap::Clamp, glm::vec2(0.01f, 0.01f));
    EXPECT_NEAR(bottomLeft.y, code(0, kSize - 1).y, 1e-5f);
}

TEST_F(TextureCacheTest, SecondOpenReturnsTheSameHandle) {
    std::string png = dir.file("same.png");
    ASSERT_TRUE(writeImage(png, kSize, kSize, 3, pixels(3), OIIO::TypeDesc::UINT8));
    EXPECT_EQ(cache.open(png).texture, cache.open(png).texture);
}

TEST_F(TextureCacheTest, WrapModesOutsideTheUnitSquare) {
    std::string exr = dir.file("wrap.exr");
    ASSERT_TRUE(writeImage(exr, kSize, kSize, 4, pixels(4), OIIO::TypeDesc::FLOAT));
    const Texture* t = cache.open(exr).texture;
    ASSERT_NE(t, nullptr);
    // s = 1.125 is half a texel past the right edge: texel column 4.5 -> wraps.
    glm::vec2 st(1.0f + 0.5f / kSize, centre(0, 1).y);
    expectNear(cache.sample(*t, Wrap::Black, Wrap::Black, st), glm::vec4(0.0f));
    expectNear(cache.sample(*t, Wrap::Clamp, Wrap::Clamp, st), code(3, 1));
    expectNear(cache.sample(*t, Wrap::Repeat, Wrap::Repeat, st), code(0, 1));
    expectNear(cache.sample(*t, Wrap::Mirror, Wrap::Mirror, st), code(3, 1));
    // t below 0 (past the bottom row, which is file row 3).
    glm::vec2 below(centre(1, 0).x, -0.5f / kSize);
    expectNear(cache.sample(*t, Wrap::Clamp, Wrap::Clamp, below), code(1, 3));
    expectNear(cache.sample(*t, Wrap::Repeat, Wrap::Repeat, below), code(1, 0));
    expectNear(cache.sample(*t, Wrap::Mirror, Wrap::Mirror, below), code(1, 3));
    expectNear(cache.sample(*t, Wrap::Black, Wrap::Black, below), glm::vec4(0.0f));
    // Mirror over two periods: s = 1.875 is column 0.5 mirrored -> texel 0.
    expectNear(cache.sample(*t, Wrap::Mirror, Wrap::Mirror,
                            glm::vec2(2.0f - 0.5f / kSize, centre(0, 2).y)),
               code(0, 2));
}

TEST_F(TextureCacheTest, ChannelCountRules) {
    for (int n = 1; n <= 4; ++n) {
        std::string exr = dir.file("c" + std::to_string(n) + ".exr");
        ASSERT_TRUE(writeImage(exr, kSize, kSize, n, pixels(n), OIIO::TypeDesc::FLOAT));
        const Texture* t = cache.open(exr).texture;
        ASSERT_NE(t, nullptr);
        EXPECT_EQ(t->info().channels, n);
        EXPECT_TRUE(t->info().isFloat);
        glm::vec4 c = code(2, 1);
        glm::vec4 got = cache.sample(*t, Wrap::Black, Wrap::Black, centre(2, 1));
        switch (n) {
            case 1:
                expectNear(got, glm::vec4(c.x, c.x, c.x, 1.0f));
                break;
            case 2:
                expectNear(got, glm::vec4(c.x, c.x, c.x, c.y));
                break;
            case 3:
                expectNear(got, glm::vec4(c.x, c.y, c.z, 1.0f));
                break;
            default:
                expectNear(got, c);
                break;
        }
    }
}

TEST_F(TextureCacheTest, SixteenBitIsNormalised) {
    std::string png = dir.file("rgb16.png");
    ASSERT_TRUE(writeImage(png, kSize, kSize, 3, pixels(3), OIIO::TypeDesc::UINT16));
    const Texture* t = cache.open(png).texture;
    ASSERT_NE(t, nullptr);
    EXPECT_EQ(t->info().bitsPerChannel, 16);
    glm::vec4 want = code(1, 2);
    want.w = 1.0f;
    expectNear(cache.sample(*t, Wrap::Black, Wrap::Black, centre(1, 2)), want, 2e-5f);
}

TEST_F(TextureCacheTest, StraightAlphaIsKept) {
    // A white texel at alpha 0.5 must stay white (UsdPreviewSurface colours are unpremultiplied).
    std::string png = dir.file("alpha.png");
    std::vector<float> px;
    for (int i = 0; i < kSize * kSize; ++i) px.insert(px.end(), {1.0f, 1.0f, 1.0f, 0.5f});
    ASSERT_TRUE(writeImage(png, kSize, kSize, 4, px, OIIO::TypeDesc::UINT8));
    const Texture* t = cache.open(png).texture;
    ASSERT_NE(t, nullptr);
    glm::vec4 c = cache.sample(*t, Wrap::Clamp, Wrap::Clamp, glm::vec2(0.5f));
    EXPECT_NEAR(c.x, 1.0f, 1e-5f);
    EXPECT_NEAR(c.w, 128.0f / 255.0f, 1e-5f);
}

TEST_F(TextureCacheTest, MissingAndUnreadableFilesAreReportedOnce) {
    std::string missing = dir.file("nope.png");
    TextureOpenResult a = cache.open(missing);
    EXPECT_EQ(a.texture, nullptr);
    EXPECT_NE(a.error.find(missing), std::string::npos) << a.error;
    EXPECT_NE(a.error.find("not found"), std::string::npos) << a.error;
    EXPECT_TRUE(a.firstReport);
    TextureOpenResult b = cache.open(missing);
    EXPECT_EQ(b.texture, nullptr);
    EXPECT_FALSE(b.firstReport);

    std::string garbage = dir.file("garbage.png");
    { std::ofstream(garbage) << "this is not a png"; }
    TextureOpenResult g = cache.open(garbage);
    EXPECT_EQ(g.texture, nullptr);
    EXPECT_NE(g.error.find(garbage), std::string::npos) << g.error;
    EXPECT_TRUE(g.firstReport);

    // After invalidate() a file that now exists is read.
    ASSERT_TRUE(writeImage(missing, kSize, kSize, 3, pixels(3), OIIO::TypeDesc::UINT8));
    cache.invalidate();
    EXPECT_NE(cache.open(missing).texture, nullptr);
}

TEST_F(TextureCacheTest, NonFiniteCoordinatesDoNotCrash) {
    std::string exr = dir.file("nan.exr");
    ASSERT_TRUE(writeImage(exr, kSize, kSize, 3, pixels(3), OIIO::TypeDesc::FLOAT));
    const Texture* t = cache.open(exr).texture;
    ASSERT_NE(t, nullptr);
    glm::vec4 c = cache.sample(*t, Wrap::Repeat, Wrap::Repeat, glm::vec2(NAN, INFINITY),
                               glm::vec4(NAN, 1e30f, -INFINITY, 0.0f));
    for (int i = 0; i < 4; ++i) EXPECT_TRUE(std::isfinite(c[i]));
}

TEST_F(TextureCacheTest, LargeFootprintFiltersTowardsTheMean) {
    // A 64x64 checker of 0/1: a footprint covering the whole image averages to ~0.5 via the
    // automatically built mip levels; a point sample returns a texel.
    constexpr int n = 64;
    std::vector<float> px;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) px.push_back(static_cast<float>((x + y) & 1));
    std::string exr = dir.file("checker.exr");
    ASSERT_TRUE(writeImage(exr, n, n, 1, px, OIIO::TypeDesc::FLOAT));
    const Texture* t = cache.open(exr).texture;
    ASSERT_NE(t, nullptr);
    glm::vec2 st(1.5f / n, 1.0f - 0.5f / n);  // texel (1, 0): value 1
    EXPECT_NEAR(cache.sample(*t, Wrap::Repeat, Wrap::Repeat, st).x, 1.0f, 1e-5f);
    float blurred =
        cache.sample(*t, Wrap::Repeat, Wrap::Repeat, st, glm::vec4(0.5f, 0.0f, 0.0f, 0.5f)).x;
    EXPECT_NEAR(blurred, 0.5f, 0.05f);
}

// Every texture of the usd-wg TextureFileFormatTests corpus opens and reads finite values.
TEST_F(TextureCacheTest, UsdWgTextureFileFormatsLoad) {
    const std::string root =
        PRINCIPLED_SOURCE_DIR "/../shared/usd-wg/test_assets/TextureFileFormatTests/";
    struct Case {
        const char* file;
        int channels;
        int bits;
    };
    const Case cases[] = {
        {"jpeg_cmyk_8-bit.jpg", 3, 8},  // OpenImageIO converts CMYK to RGB
        {"jpeg_grayscale_8-bit.jpg", 1, 8}, {"jpeg_rgb_8-bit.jpg", 3, 8},
        {"png_grayscale_8-bit.png", 2, 8},  {"png_grayscale_16-bit.png", 2, 16},
        {"png_rgb_8-bit.png", 4, 8},        {"png_rgb_16-bit.png", 4, 16},
        {"png_rgb_32-bit.png", 4, 16},  // named 32-bit (RGBA x 8), stored 16 bits per channel
    };
    for (const Case& c : cases) {
        TextureOpenResult r = cache.open(root + c.file);
        ASSERT_NE(r.texture, nullptr) << c.file << ": " << r.error;
        EXPECT_EQ(r.texture->info().channels, c.channels) << c.file;
        EXPECT_EQ(r.texture->info().bitsPerChannel, c.bits) << c.file;
        EXPECT_EQ(r.texture->info().width, 256) << c.file;
        for (float s : {0.1f, 0.5f, 0.9f}) {
            glm::vec4 v = cache.sample(*r.texture, Wrap::Repeat, Wrap::Repeat, glm::vec2(s, s));
            for (int i = 0; i < 4; ++i) {
                EXPECT_TRUE(std::isfinite(v[i])) << c.file;
                EXPECT_GE(v[i], 0.0f) << c.file;
                EXPECT_LE(v[i], 1.0f) << c.file;
            }
        }
    }
}

TEST_F(TextureCacheTest, UdimTilesByStAndBottomUpRows) {
    // Tiles 1001 (u 0-1), 1002 (u 1-2) and 1011 (v 1-2); each 2x2, top file row 1, bottom 0,
    // red channel = tile number - 1000.
    auto tile = [&](int number) {
        std::vector<float> px;
        for (int row = 0; row < 2; ++row)
            for (int x = 0; x < 2; ++x)
                px.insert(px.end(), {float(number - 1000), row == 0 ? 1.0f : 0.0f, 0.0f});
        return writeImage(dir.file("t." + std::to_string(number) + ".exr"), 2, 2, 3, px,
                          OIIO::TypeDesc::FLOAT);
    };
    ASSERT_TRUE(tile(1001) && tile(1002) && tile(1011));
    TextureOpenResult r = cache.open(dir.file("t.<UDIM>.exr"));
    ASSERT_NE(r.texture, nullptr) << r.error;
    EXPECT_TRUE(r.error.empty());
    EXPECT_EQ(r.texture->info().channels, 3);
    ASSERT_EQ(r.texture->udimTiles.size(), 100u);
    const Texture& t = *r.texture;
    auto at = [&](float s, float tt) { return cache.sample(t, Wrap::Black, Wrap::Black, {s, tt}); };
    EXPECT_NEAR(at(0.5f, 0.25f).x, 1.0f, 1e-5f);
    EXPECT_NEAR(at(0.5f, 0.25f).y, 0.0f, 1e-5f);  // bottom half of tile 1001: bottom row
    EXPECT_NEAR(at(0.5f, 0.75f).y, 1.0f, 1e-5f);
    EXPECT_NEAR(at(1.5f, 0.5f).x, 2.0f, 1e-5f);
    EXPECT_NEAR(at(0.5f, 1.25f).x, 11.0f, 1e-5f);
    EXPECT_NEAR(at(0.5f, 1.25f).y, 0.0f, 1e-5f);
    glm::vec4 none(7.0f);
    EXPECT_FALSE(cache.lookup(t, Wrap::Black, Wrap::Black, {2.5f, 0.5f}, glm::vec4(0), &none));
    EXPECT_FALSE(cache.lookup(t, Wrap::Black, Wrap::Black, {-0.5f, 0.5f}, glm::vec4(0), &none));
    EXPECT_EQ(none, glm::vec4(7.0f));

    TextureOpenResult empty = cache.open(dir.file("none.<UDIM>.exr"));
    EXPECT_EQ(empty.texture, nullptr);
    EXPECT_NE(empty.error.find("none.<UDIM>.exr"), std::string::npos) << empty.error;
}

TEST(TextureCacheMemory, TileMemoryStaysNearTheLimit) {
    // A 2048x2048 RGB float texture is 48 MB; with a 16 MB limit random lookups keep evicting.
    // The file is tiled (64x64, uncompressed) so a miss reads one tile: an untiled file that
    // does not fit the cache re-reads whole scanline blocks and is ~100x slower per miss.
    TempDir dir;
    constexpr int n = 2048;
    std::vector<float> px(size_t(n) * n * 3, 0.5f);
    std::string exr = dir.file("big.exr");
    {
        auto out = OIIO::ImageOutput::create(exr);
        ASSERT_TRUE(out);
        OIIO::ImageSpec spec(n, n, 3, OIIO::TypeDesc::FLOAT);
        spec.tile_width = spec.tile_height = 64;
        spec.attribute("compression", "none");
        ASSERT_TRUE(out->open(exr, spec));
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
        ASSERT_TRUE(out->close());
    }
    TextureCache::Options options;
    options.maxMemoryMB = 16.0f;
    options.maxResidentMB = 0.0;  // OpenImageIO's tile cache is what this test measures
    TextureCache cache(options);
    const Texture* t = cache.open(exr).texture;
    ASSERT_NE(t, nullptr);
    uint32_t h = 1;
    for (int i = 0; i < 4000; ++i) {
        h = h * 1664525u + 1013904223u;  // Numerical Recipes LCG
        glm::vec2 st((h >> 8 & 0xfff) / 4096.0f, (h >> 20) / 4096.0f);
        EXPECT_NEAR(cache.sample(*t, Wrap::Repeat, Wrap::Repeat, st).x, 0.5f, 1e-6f);
    }
    EXPECT_GT(cache.memoryUsed(), 0u);
    EXPECT_LT(cache.memoryUsed(), size_t(20) << 20);  // 16 MB + a few tiles of slack
}

TEST_F(TextureCacheTest, ConcurrentOpensShareOneHandle) {
    std::string png = dir.file("shared.png");
    ASSERT_TRUE(writeImage(png, kSize, kSize, 3, pixels(3), OIIO::TypeDesc::UINT8));
    std::string missing = dir.file("absent.png");
    std::vector<const Texture*> got(8, nullptr);
    std::atomic<int> reports{0};
    std::vector<std::thread> threads;
    for (int i = 0; i < 8; ++i)
        threads.emplace_back([&, i] {
            got[i] = cache.open(png).texture;
            if (cache.open(missing).firstReport) ++reports;
            (void)cache.sample(*got[i], Wrap::Repeat, Wrap::Repeat, centre(i % kSize, 1));
        });
    for (auto& t : threads) t.join();
    for (const Texture* t : got) EXPECT_EQ(t, got[0]);
    EXPECT_EQ(reports.load(), 1);  // the missing file is reported by exactly one caller
}

// ---------------------------------------------------------------------------------------------
// Resident pixels (point lookups served from memory) against OpenImageIO's texture system.

namespace {

struct FileKind {
    const char* ext;
    OIIO::TypeDesc type;
    int bits;
};

// Random pixel values in [0,1] (row 0 = the top row); the writer quantises them to its type.
std::vector<float> randomPixels(int w, int h, int channels, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<float> px(size_t(w) * h * channels);
    for (float& v : px) v = u(rng);
    return px;
}

// USD st to compare at: random ones inside and well outside [0,1], and every texel centre and
// texel edge from two images before to two images after the texture on both axes.
std::vector<glm::vec2> probeSt(int w, int h, int randomCount) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-2.5f, 3.5f);
    std::vector<glm::vec2> st;
    for (int i = 0; i < randomCount; ++i) st.push_back({u(rng), u(rng)});
    for (int i = -2 * w; i <= 3 * w; ++i)
        for (int j = -2 * h; j <= 3 * h; ++j) {
            st.push_back({(i + 0.5f) / w, 1.0f - (j + 0.5f) / h});  // centre
            st.push_back({float(i) / w, 1.0f - float(j) / h});      // corner between texels
            st.push_back({float(i) / w, 1.0f - (j + 0.5f) / h});    // edge
        }
    return st;
}

const char* wrapName(Wrap w) {
    switch (w) {
        case Wrap::Black:
            return "black";
        case Wrap::Clamp:
            return "clamp";
        case Wrap::Repeat:
            return "repeat";
        case Wrap::Mirror:
            return "mirror";
    }
    return "?";
}

constexpr Wrap kWraps[] = {Wrap::Black, Wrap::Clamp, Wrap::Repeat, Wrap::Mirror};

}  // namespace

// The resident bilinear equals OpenImageIO's texture-system lookup at a zero footprint (the
// same cache API with a resident budget of 0) for every wrap pair, 1-4 channels, 8-bit and
// 16-bit PNG, 8-bit TIFF, half and float EXR, and odd, one-texel and one-row sizes.
TEST(TextureCacheResident, PointLookupsEqualTheTextureSystem) {
    TempDir dir;
    TextureCache resident;  // the default budget holds every file below in memory
    TextureCache::Options viaOiio;
    viaOiio.maxResidentMB = 0.0;
    TextureCache oiio(viaOiio);
    const FileKind kinds[] = {{"png", OIIO::TypeDesc::UINT8, 8},
                              {"png", OIIO::TypeDesc::UINT16, 16},
                              {"tif", OIIO::TypeDesc::UINT8, 8},
                              {"exr", OIIO::TypeDesc::HALF, 16},
                              {"exr", OIIO::TypeDesc::FLOAT, 32}};
    const glm::ivec2 sizes[] = {{7, 5}, {1, 1}, {4, 1}, {16, 16}};
    int files = 0;
    size_t lookups = 0;
    for (const FileKind& kind : kinds)
        for (int n = 1; n <= 4; ++n)
            for (glm::ivec2 size : sizes) {
                std::string name = std::to_string(kind.bits) + "_" + std::to_string(n) + "_" +
                                   std::to_string(size.x) + "x" + std::to_string(size.y) + "." +
                                   kind.ext;
                std::string path = dir.file(name);
                ASSERT_TRUE(writeImage(path, size.x, size.y, n,
                                       randomPixels(size.x, size.y, n, 100 + files++), kind.type))
                    << name;
                TextureOpenResult a = resident.open(path), b = oiio.open(path);
                ASSERT_NE(a.texture, nullptr) << name << ": " << a.error;
                ASSERT_NE(b.texture, nullptr) << name << ": " << b.error;
                ASSERT_NE(a.texture->resident(), nullptr) << name;
                ASSERT_EQ(b.texture->resident(), nullptr) << name;
                EXPECT_EQ(a.texture->info().channels, n) << name;
                EXPECT_EQ(a.texture->info().bitsPerChannel, kind.bits) << name;
                const std::vector<glm::vec2> st = probeSt(size.x, size.y, 600);
                for (Wrap ws : kWraps)
                    for (Wrap wt : kWraps) {
                        float worst = 0.0f;
                        glm::vec2 worstSt(0.0f);
                        glm::vec4 worstA(0.0f), worstB(0.0f);
                        for (glm::vec2 p : st) {
                            glm::vec4 va(-1.0f), vb(-2.0f);
                            ASSERT_TRUE(resident.lookup(*a.texture, ws, wt, p, glm::vec4(0), &va));
                            ASSERT_TRUE(oiio.lookup(*b.texture, ws, wt, p, glm::vec4(0), &vb));
                            ++lookups;
                            for (int c = 0; c < 4; ++c)
                                if (std::abs(va[c] - vb[c]) > worst) {
                                    worst = std::abs(va[c] - vb[c]);
                                    worstSt = p;
                                    worstA = va;
                                    worstB = vb;
                                }
                        }
                        EXPECT_LE(worst, 1e-5f)
                            << name << " wrap " << wrapName(ws) << "," << wrapName(wt) << " at st ("
                            << worstSt.x << ", " << worstSt.y << "): resident (" << worstA.x
                            << ", " << worstA.y << ", " << worstA.z << ", " << worstA.w
                            << ") vs OpenImageIO (" << worstB.x << ", " << worstB.y << ", "
                            << worstB.z << ", " << worstB.w << ")";
                    }
                // A non-zero footprint still goes to the texture system, in both caches.
                glm::vec4 d(0.3f / size.x, 0.0f, 0.0f, 0.3f / size.y);
                expectNear(resident.sample(*a.texture, Wrap::Repeat, Wrap::Clamp, {0.3f, 0.6f}, d),
                           oiio.sample(*b.texture, Wrap::Repeat, Wrap::Clamp, {0.3f, 0.6f}, d),
                           0.0f);
            }
    EXPECT_GT(lookups, 100000u);
    EXPECT_GT(resident.residentBytes(), 0u);
    EXPECT_EQ(oiio.residentBytes(), 0u);
}

TEST(TextureCacheResident, FilesBeyondTheBudgetUseTheTextureSystem) {
    TempDir dir;
    // Two 16x16 RGBA float files of 4096 bytes each; the budget holds one.
    constexpr int n = 16;
    std::string first = dir.file("first.exr"), second = dir.file("second.exr");
    std::vector<float> px1 = randomPixels(n, n, 4, 1), px2 = randomPixels(n, n, 4, 2);
    ASSERT_TRUE(writeImage(first, n, n, 4, px1, OIIO::TypeDesc::FLOAT));
    ASSERT_TRUE(writeImage(second, n, n, 4, px2, OIIO::TypeDesc::FLOAT));
    TextureCache::Options options;
    options.maxResidentMB = 6000.0 / 1048576.0;
    TextureCache cache(options);
    const Texture* a = cache.open(first).texture;
    const Texture* b = cache.open(second).texture;
    ASSERT_NE(a, nullptr);
    ASSERT_NE(b, nullptr);
    EXPECT_NE(a->resident(), nullptr);
    EXPECT_EQ(b->resident(), nullptr);
    EXPECT_EQ(cache.residentBytes(), size_t(n) * n * 4 * sizeof(float));
    EXPECT_GE(cache.memoryUsed(), cache.residentBytes());
    // Both answer with the file's texels.
    for (int y = 0; y < n; y += 5)
        for (int x = 0; x < n; x += 3) {
            glm::vec2 st((x + 0.5f) / n, 1.0f - (y + 0.5f) / n);
            const float* p1 = &px1[(size_t(y) * n + x) * 4];
            const float* p2 = &px2[(size_t(y) * n + x) * 4];
            expectNear(cache.sample(*a, Wrap::Black, Wrap::Black, st),
                       glm::vec4(p1[0], p1[1], p1[2], p1[3]));
            expectNear(cache.sample(*b, Wrap::Black, Wrap::Black, st),
                       glm::vec4(p2[0], p2[1], p2[2], p2[3]));
        }
}

TEST(TextureCacheResident, InvalidateRereadsEditedFiles) {
    TempDir dir;
    TextureCache cache;
    std::string path = dir.file("edited.exr");
    auto fill = [&](int size, float v) {
        return writeImage(path, size, size, 3, std::vector<float>(size_t(size) * size * 3, v),
                          OIIO::TypeDesc::FLOAT);
    };
    ASSERT_TRUE(fill(8, 0.25f));
    const Texture* t = cache.open(path).texture;
    ASSERT_NE(t, nullptr);
    ASSERT_NE(t->resident(), nullptr);
    EXPECT_NEAR(cache.sample(*t, Wrap::Clamp, Wrap::Clamp, {0.5f, 0.5f}).x, 0.25f, 1e-6f);
    EXPECT_EQ(cache.residentBytes(), size_t(8) * 8 * 3 * 4);

    // Edited on disk (another size too): invalidate() drops the pixels, the next lookup reads
    // the new file.
    ASSERT_TRUE(fill(4, 0.75f));
    cache.invalidate();
    EXPECT_EQ(t->resident(), nullptr);
    EXPECT_EQ(cache.residentBytes(), 0u);
    EXPECT_NEAR(cache.sample(*t, Wrap::Clamp, Wrap::Clamp, {0.5f, 0.5f}).x, 0.75f, 1e-6f);
    EXPECT_NE(t->resident(), nullptr);
    EXPECT_EQ(cache.residentBytes(), size_t(4) * 4 * 3 * 4);

    // ... or the next open(), which keeps the same Texture.
    ASSERT_TRUE(fill(4, 0.5f));
    cache.invalidate();
    EXPECT_EQ(cache.open(path).texture, t);
    EXPECT_NE(t->resident(), nullptr);
    EXPECT_NEAR(cache.sample(*t, Wrap::Clamp, Wrap::Clamp, {0.5f, 0.5f}).x, 0.5f, 1e-6f);

    // Filtered lookups (texture system) see the edit as well.
    ASSERT_TRUE(fill(4, 0.125f));
    cache.invalidate();
    EXPECT_NEAR(
        cache.sample(*t, Wrap::Clamp, Wrap::Clamp, {0.5f, 0.5f}, glm::vec4(0.1f, 0, 0, 0.1f)).x,
        0.125f, 1e-6f);
    EXPECT_NEAR(cache.sample(*t, Wrap::Clamp, Wrap::Clamp, {0.5f, 0.5f}).x, 0.125f, 1e-6f);
}

TEST(TextureCacheResident, ConcurrentLookupsAfterInvalidateRereadOnce) {
    TempDir dir;
    TextureCache cache;
    std::string path = dir.file("threads.png");
    ASSERT_TRUE(writeImage(path, kSize, kSize, 3, pixels(3), OIIO::TypeDesc::UINT8));
    const Texture* t = cache.open(path).texture;
    ASSERT_NE(t, nullptr);
    cache.invalidate();
    std::vector<std::thread> threads;
    std::atomic<int> wrong{0};
    for (int i = 0; i < 8; ++i)
        threads.emplace_back([&, i] {
            for (int k = 0; k < 1000; ++k) {
                int x = (i + k) % kSize, row = k % kSize;
                glm::vec4 got = cache.sample(*t, Wrap::Repeat, Wrap::Repeat, centre(x, row));
                if (std::abs(got.x - code(x, row).x) > 1e-5f) ++wrong;
            }
        });
    for (auto& th : threads) th.join();
    EXPECT_EQ(wrong.load(), 0);
    EXPECT_EQ(cache.residentBytes(), size_t(kSize) * kSize * 3);
}

// A reader holding the previous pixels across invalidate() keeps reading them (retired, not
// freed) until collectRetired(); the accounting moves them from resident to retired.
TEST(TextureCacheResident, InvalidateRetiresPixelsUntilCollected) {
    TempDir dir;
    TextureCache cache;
    std::string path = dir.file("held.exr");
    ASSERT_TRUE(writeImage(path, 8, 8, 3, std::vector<float>(8 * 8 * 3, 0.25f),
                           OIIO::TypeDesc::FLOAT));
    const Texture* t = cache.open(path).texture;
    ASSERT_NE(t, nullptr);
    const ResidentImage* held = t->resident();
    const TextureInfo* heldInfo = &t->info();
    ASSERT_NE(held, nullptr);
    const size_t bytes = held->bytes();
    EXPECT_EQ(bytes, size_t(8) * 8 * 3 * 4);

    ASSERT_TRUE(writeImage(path, 4, 4, 3, std::vector<float>(4 * 4 * 3, 0.75f),
                           OIIO::TypeDesc::FLOAT));
    cache.invalidate();
    EXPECT_EQ(cache.residentBytes(), 0u);
    EXPECT_EQ(cache.retiredBytes(), bytes);
    EXPECT_GE(cache.memoryUsed(), bytes);
    // The held pixels and description are those of the first reading, still readable.
    float px[4] = {0, 0, 0, 0};
    held->lookup(Wrap::Clamp, Wrap::Clamp, 0.5f, 0.5f, px);
    EXPECT_EQ(px[0], 0.25f);
    EXPECT_EQ(heldInfo->width, 8);
    // New lookups read the edited file.
    EXPECT_EQ(cache.sample(*t, Wrap::Clamp, Wrap::Clamp, {0.5f, 0.5f}).x, 0.75f);
    EXPECT_EQ(t->info().width, 4);
    EXPECT_EQ(cache.residentBytes(), size_t(4) * 4 * 3 * 4);

    EXPECT_EQ(cache.collectRetired(), bytes);
    EXPECT_EQ(cache.retiredBytes(), 0u);
    EXPECT_EQ(cache.collectRetired(), 0u);
    EXPECT_EQ(cache.sample(*t, Wrap::Clamp, Wrap::Clamp, {0.5f, 0.5f}).x, 0.75f);
}

// The description is re-read with the pixels: size, channels, precision and wrap metadata of
// the edited file, and lookups at its texel centres.
TEST(TextureCacheResident, RereadRefreshesTheDescription) {
    TempDir dir;
    TextureCache cache;
    std::string path = dir.file("resized.exr");
    ASSERT_TRUE(writeImage(path, 8, 8, 3, std::vector<float>(8 * 8 * 3, 0.5f),
                           OIIO::TypeDesc::HALF));
    const Texture* t = cache.open(path).texture;
    ASSERT_NE(t, nullptr);
    EXPECT_EQ(t->info().width, 8);
    EXPECT_EQ(t->info().channels, 3);
    EXPECT_EQ(t->info().bitsPerChannel, 16);
    EXPECT_FALSE(t->info().hasWrapMetadata);

    // 16 x 4, one float channel, texel (x, row) = x + 16 row, wrap metadata.
    const int w = 16, h = 4;
    std::vector<float> px;
    for (int row = 0; row < h; ++row)
        for (int x = 0; x < w; ++x) px.push_back(float(x + w * row));
    ASSERT_TRUE(writeImage(path, w, h, 1, px, OIIO::TypeDesc::FLOAT,
                           {{"wrapmodes", "periodic,mirror"}}));
    cache.invalidate();
    // Until re-read, the previous description stands.
    EXPECT_EQ(t->info().width, 8);
    ASSERT_EQ(cache.open(path).texture, t);
    const TextureInfo& info = t->info();
    EXPECT_EQ(info.width, w);
    EXPECT_EQ(info.height, h);
    EXPECT_EQ(info.channels, 1);
    EXPECT_EQ(info.bitsPerChannel, 32);
    EXPECT_TRUE(info.isFloat);
    EXPECT_TRUE(info.hasWrapMetadata);
    EXPECT_EQ(info.metadataWrapS, Wrap::Repeat);
    EXPECT_EQ(info.metadataWrapT, Wrap::Mirror);
    ASSERT_NE(t->resident(), nullptr);
    EXPECT_EQ(t->resident()->width(), w);
    EXPECT_EQ(t->resident()->channels(), 1);
    for (int row = 0; row < h; ++row)
        for (int x = 0; x < w; ++x) {
            glm::vec2 st((x + 0.5f) / w, 1.0f - (row + 0.5f) / h);
            float v = float(x + w * row);
            expectNear(cache.sample(*t, Wrap::Clamp, Wrap::Clamp, st), glm::vec4(v, v, v, 1.0f));
        }

    // A point lookup re-reads too (no open()): back to 3 channels, 2 x 2.
    ASSERT_TRUE(writeImage(path, 2, 2, 3, std::vector<float>(2 * 2 * 3, 0.125f),
                           OIIO::TypeDesc::FLOAT));
    cache.invalidate();
    expectNear(cache.sample(*t, Wrap::Clamp, Wrap::Clamp, {0.5f, 0.5f}),
               glm::vec4(0.125f, 0.125f, 0.125f, 1.0f));
    EXPECT_EQ(t->info().width, 2);
    EXPECT_EQ(t->info().channels, 3);
    EXPECT_FALSE(t->info().hasWrapMetadata);
}

// Render threads keep doing point lookups while the file is rewritten (size, channels and
// colour change) and invalidate() runs in a loop. The long run is texture_cache_stress.
TEST(TextureCacheResident, InvalidateDuringLookups) {
    principled::shading::test::invalidateWhileLooking(1.0, 3);
}

// Two threads opening two different large-ish files both get them, resident and correct; two
// threads opening the same file get one Texture, decoded once (one image's bytes resident).
TEST(TextureCacheResident, ConcurrentOpensOfDifferentFiles) {
    TempDir dir;
    TextureCache cache;
    const int w = 1024, h = 1024;
    std::string paths[2] = {dir.file("large0.exr"), dir.file("large1.exr")};
    for (int f = 0; f < 2; ++f) {
        std::vector<float> px;
        px.reserve(size_t(w) * h * 3);
        for (int row = 0; row < h; ++row)
            for (int x = 0; x < w; ++x) {
                px.push_back(float(x));
                px.push_back(float(row));
                px.push_back(float(f));
            }
        ASSERT_TRUE(writeImage(paths[f], w, h, 3, px, OIIO::TypeDesc::FLOAT));
    }
    const Texture* got[4] = {};
    std::vector<std::thread> threads;
    for (int i = 0; i < 4; ++i)  // threads 0, 2 open file 0; 1, 3 open file 1
        threads.emplace_back([&, i] { got[i] = cache.open(paths[i % 2]).texture; });
    for (auto& t : threads) t.join();
    ASSERT_NE(got[0], nullptr);
    ASSERT_NE(got[1], nullptr);
    EXPECT_NE(got[0], got[1]);
    EXPECT_EQ(got[2], got[0]);
    EXPECT_EQ(got[3], got[1]);
    const size_t image = size_t(w) * h * 3 * 4;
    EXPECT_EQ(cache.residentBytes(), 2 * image);  // each file decoded once
    for (int f = 0; f < 2; ++f) {
        ASSERT_NE(got[f]->resident(), nullptr);
        EXPECT_EQ(got[f]->info().width, w);
        const int x = 100 + 300 * f, row = 700 - 200 * f;
        glm::vec2 st((x + 0.5f) / w, 1.0f - (row + 0.5f) / h);
        expectNear(cache.sample(*got[f], Wrap::Clamp, Wrap::Clamp, st),
                   glm::vec4(float(x), float(row), float(f), 1.0f));
    }
}

// ---------------------------------------------------------------------------------------------
// PNG textures decoded natively (libpng) against the same files read through OpenImageIO.

namespace {

std::vector<std::string> usdWgPngs() {
    std::vector<std::string> out;
    std::error_code ec;
    namespace fs = std::filesystem;
    for (auto it = fs::recursive_directory_iterator(PRINCIPLED_SOURCE_DIR "/../shared/usd-wg", ec);
         it != fs::recursive_directory_iterator(); it.increment(ec))
        if (it->path().extension() == ".png") out.push_back(it->path().string());
    return out;
}

}  // namespace

// Same description (channels, bits, colour tag, wrap metadata) and the same point lookups at
// every texel centre, for the usd-wg PNGs and generated 8/16-bit ones with colour metadata.
TEST(TextureCacheNativePng, SameTextureAsThroughOpenImageIO) {
    TempDir dir;
    std::vector<std::string> files = usdWgPngs();
    ASSERT_GE(files.size(), 10u);
    const std::vector<std::pair<std::string, std::string>> tagged[] = {
        {}, {{"oiio:ColorSpace", "linear"}}, {{"wrapmodes", "periodic,clamp"}}};
    int k = 0;
    for (const auto& attributes : tagged)
        for (auto type : {OIIO::TypeDesc::UINT8, OIIO::TypeDesc::UINT16})
            for (int n = 1; n <= 4; ++n) {
                std::string path = dir.file("gen" + std::to_string(k++) + ".png");
                ASSERT_TRUE(writeImage(path, 6, 5, n, randomPixels(6, 5, n, 40 + k), type,
                                       attributes));
                files.push_back(path);
            }
    TextureCache native;
    TextureCache::Options viaOiio;
    viaOiio.nativePng = false;
    TextureCache oiio(viaOiio);
    for (const std::string& path : files) {
        SCOPED_TRACE(path);
        const Texture* a = native.open(path).texture;
        const Texture* b = oiio.open(path).texture;
        ASSERT_NE(a, nullptr);
        ASSERT_NE(b, nullptr);
        EXPECT_EQ(a->info().width, b->info().width);
        EXPECT_EQ(a->info().height, b->info().height);
        EXPECT_EQ(a->info().channels, b->info().channels);
        EXPECT_EQ(a->info().bitsPerChannel, b->info().bitsPerChannel);
        EXPECT_EQ(a->info().isFloat, b->info().isFloat);
        EXPECT_EQ(a->info().colorTag, b->info().colorTag);
        EXPECT_EQ(a->info().hasWrapMetadata, b->info().hasWrapMetadata);
        EXPECT_EQ(a->info().metadataWrapS, b->info().metadataWrapS);
        EXPECT_EQ(a->info().metadataWrapT, b->info().metadataWrapT);
        ASSERT_NE(a->resident(), nullptr);
        ASSERT_NE(b->resident(), nullptr);
        int differ = 0;
        for (int y = 0; y < a->info().height; ++y)
            for (int x = 0; x < a->info().width; ++x) {
                glm::vec2 st((x + 0.5f) / a->info().width, 1.0f - (y + 0.5f) / a->info().height);
                differ += native.sample(*a, Wrap::Black, Wrap::Black, st) !=
                          oiio.sample(*b, Wrap::Black, Wrap::Black, st);
            }
        EXPECT_EQ(differ, 0);
    }
}

// PNG textures never load the OpenImageIO backend for open() and point lookups (what a render
// asks). ctest runs every test in its own process; in a process where an earlier test loaded
// the backend, this one is skipped.
TEST(TextureCacheNativePng, PointLookupsDoNotLoadTheBackend) {
    if (principled::imageio::loadedBackend())
        GTEST_SKIP() << "the backend was loaded by an earlier test in this process";
    TempDir dir;
    std::string png = dir.file("only.png");
    ASSERT_TRUE(writeImage(png, kSize, kSize, 3, pixels(3), OIIO::TypeDesc::UINT8));
    TextureCache cache;
    TextureOpenResult r = cache.open(png);
    ASSERT_NE(r.texture, nullptr) << r.error;
    for (int row = 0; row < kSize; ++row)
        for (int x = 0; x < kSize; ++x) {
            glm::vec4 want = code(x, row);
            want.w = 1.0f;
            expectNear(cache.sample(*r.texture, Wrap::Repeat, Wrap::Repeat, centre(x, row)), want);
        }
    EXPECT_EQ(principled::imageio::loadedBackend(), nullptr);
    // A filtered lookup does need OpenImageIO's texture system, and loads it then.
    (void)cache.sample(*r.texture, Wrap::Repeat, Wrap::Repeat, {0.5f, 0.5f},
                       glm::vec4(0.25f, 0.0f, 0.0f, 0.25f));
    EXPECT_NE(principled::imageio::loadedBackend(), nullptr);
}

TEST(TextureCacheReload, ReloadChangedReadsAgainOnlyWhenAFileChanged) {
    TempDir dir;
    TextureCache cache;
    const std::string path = dir.file("edited.exr"), watched = dir.file("light.exr");
    auto fill = [&](const std::string& p, float v) {
        if (!writeImage(p, 4, 4, 3, std::vector<float>(4 * 4 * 3, v), OIIO::TypeDesc::FLOAT)) return false;
        // A new modification time even on file systems with coarse clocks.
        std::error_code ec;
        static int tick = 0;
        std::filesystem::last_write_time(p, std::filesystem::file_time_type::clock::now() + std::chrono::seconds(++tick), ec);
        return !ec;
    };
    ASSERT_TRUE(fill(path, 0.25f));
    const Texture* t = cache.open(path).texture;
    ASSERT_NE(t, nullptr);
    EXPECT_NEAR(cache.sample(*t, Wrap::Clamp, Wrap::Clamp, {0.5f, 0.5f}).x, 0.25f, 1e-6f);
    EXPECT_TRUE(cache.reloadChanged().empty());  // nothing edited: nothing re-read
    EXPECT_NE(t->resident(), nullptr);
    ASSERT_TRUE(fill(path, 0.75f));
    EXPECT_FALSE(cache.reloadChanged().empty());
    EXPECT_NEAR(cache.sample(*t, Wrap::Clamp, Wrap::Clamp, {0.5f, 0.5f}).x, 0.75f, 1e-6f);
    EXPECT_TRUE(cache.reloadChanged().empty());  // the new state is the one remembered
    // A watched file (a light's) that appears, changes or vanishes counts too.
    cache.watch(watched);
    EXPECT_TRUE(cache.reloadChanged().empty());
    ASSERT_TRUE(fill(watched, 1.0f));
    EXPECT_FALSE(cache.reloadChanged().empty());
    EXPECT_TRUE(cache.reloadChanged().empty());
    std::filesystem::remove(watched);
    EXPECT_FALSE(cache.reloadChanged().empty());
    // A file missing when first opened is read once it exists.
    const std::string late = dir.file("late.exr");
    EXPECT_EQ(cache.open(late).texture, nullptr);
    ASSERT_TRUE(fill(late, 0.5f));
    EXPECT_FALSE(cache.reloadChanged().empty());
    const Texture* l = cache.open(late).texture;
    ASSERT_NE(l, nullptr);
    EXPECT_NEAR(cache.sample(*l, Wrap::Clamp, Wrap::Clamp, {0.5f, 0.5f}).x, 0.5f, 1e-6f);
}

namespace {
// Writes a size x size float image of one value with a modification time `ahead` seconds from
// now (distinct times even on file systems with coarse clocks).
bool fillAhead(const std::string& p, int size, float v, int ahead) {
    if (!writeImage(p, size, size, 3, std::vector<float>(size_t(size) * size * 3, v), OIIO::TypeDesc::FLOAT))
        return false;
    std::error_code ec;
    std::filesystem::last_write_time(p, std::filesystem::file_time_type::clock::now() + std::chrono::seconds(ahead), ec);
    return !ec;
}
}  // namespace

TEST(TextureCacheReload, OnlyTheChangedFilesAreReadAgain) {
    TempDir dir;
    TextureCache cache;
    const std::string a = dir.file("a.exr"), b = dir.file("b.exr");
    ASSERT_TRUE(fillAhead(a, 4, 0.25f, 1));
    ASSERT_TRUE(fillAhead(b, 4, 0.5f, 1));
    const Texture* ta = cache.open(a).texture;
    const Texture* tb = cache.open(b).texture;
    ASSERT_TRUE(ta && tb);
    ASSERT_TRUE(ta->resident() && tb->resident());
    ASSERT_TRUE(fillAhead(a, 4, 0.75f, 2));
    const std::vector<std::string> changed = cache.reloadChanged();
    ASSERT_EQ(changed, std::vector<std::string>{a});
    EXPECT_EQ(ta->resident(), nullptr);  // dropped, read again on the next lookup
    EXPECT_NE(tb->resident(), nullptr);  // untouched
    EXPECT_NEAR(cache.sample(*ta, Wrap::Clamp, Wrap::Clamp, {0.5f, 0.5f}).x, 0.75f, 1e-6f);
    EXPECT_NEAR(cache.sample(*tb, Wrap::Clamp, Wrap::Clamp, {0.5f, 0.5f}).x, 0.5f, 1e-6f);
}

TEST(TextureCacheReload, AForcedReloadRestampsAndAnEmptyCacheHasNothingToReload) {
    TempDir dir;
    TextureCache cache;
    EXPECT_FALSE(cache.reloadAll());  // nothing was ever read
    const std::string a = dir.file("a.exr");
    ASSERT_TRUE(fillAhead(a, 4, 0.25f, 1));
    ASSERT_TRUE(cache.open(a).texture);
    ASSERT_TRUE(fillAhead(a, 4, 0.5f, 2));
    EXPECT_TRUE(cache.reloadAll());
    EXPECT_TRUE(cache.reloadChanged().empty());  // the forced reload read the file as it is now
}

TEST(TextureCacheReload, UdimTilesThatAppearJoinTheSet) {
    TempDir dir;
    TextureCache cache;
    const std::string pattern = dir.file("t.<UDIM>.exr");
    EXPECT_EQ(cache.open(pattern).texture, nullptr);  // no tile yet
    ASSERT_TRUE(fillAhead(dir.file("t.1001.exr"), 4, 0.25f, 1));
    EXPECT_FALSE(cache.reloadChanged().empty());
    const Texture* set = cache.open(pattern).texture;
    ASSERT_NE(set, nullptr);
    glm::vec4 rgba(-1.0f);
    EXPECT_TRUE(cache.lookup(*set, Wrap::Clamp, Wrap::Clamp, {0.5f, 0.5f}, glm::vec4(0.0f), &rgba));
    EXPECT_NEAR(rgba.x, 0.25f, 1e-6f);
    EXPECT_FALSE(cache.lookup(*set, Wrap::Clamp, Wrap::Clamp, {1.5f, 0.5f}, glm::vec4(0.0f), &rgba));  // no 1002
    ASSERT_TRUE(fillAhead(dir.file("t.1002.exr"), 4, 0.75f, 2));
    EXPECT_FALSE(cache.reloadChanged().empty());
    const Texture* again = cache.open(pattern).texture;  // built again, with the new tile
    ASSERT_NE(again, nullptr);
    EXPECT_TRUE(cache.lookup(*again, Wrap::Clamp, Wrap::Clamp, {1.5f, 0.5f}, glm::vec4(0.0f), &rgba));
    EXPECT_NEAR(rgba.x, 0.75f, 1e-6f);
    // The old set stays usable for lookups that still hold it.
    EXPECT_TRUE(cache.lookup(*set, Wrap::Clamp, Wrap::Clamp, {0.5f, 0.5f}, glm::vec4(0.0f), &rgba));
}

TEST(TextureCacheReload, ANewCacheDoesNotGetTilesAnEarlierOneReadBeforeAnEdit) {
    // The texture system is process-wide: filtered lookups of a second cache must see a file
    // edited after a first cache read it.
    TempDir dir;
    const std::string a = dir.file("shared.exr");
    ASSERT_TRUE(fillAhead(a, 16, 0.25f, 1));
    const glm::vec4 footprint(0.1f, 0.0f, 0.0f, 0.1f);  // a filtered lookup: the texture system
    {
        TextureCache first;
        const Texture* t = first.open(a).texture;
        ASSERT_NE(t, nullptr);
        EXPECT_NEAR(first.sample(*t, Wrap::Clamp, Wrap::Clamp, {0.5f, 0.5f}, footprint).x, 0.25f, 1e-5f);
    }
    ASSERT_TRUE(fillAhead(a, 16, 0.75f, 3));
    TextureCache second;
    const Texture* t = second.open(a).texture;
    ASSERT_NE(t, nullptr);
    EXPECT_NEAR(second.sample(*t, Wrap::Clamp, Wrap::Clamp, {0.5f, 0.5f}, footprint).x, 0.75f, 1e-5f);
}

TEST(TextureCacheReload, SameSecondEditsAndDirectoriesAreHandled) {
    // (1) A second cache's filtered lookups see an edit made within the same second as a first
    // cache's read (OpenImageIO's own newer-than check counts whole seconds). (2) A watched
    // path that is a directory does not count as changed when files appear inside it.
    TempDir dir;
    const std::string a = dir.file("same.exr");
    auto fill = [&](float v) {
        return writeImage(a, 16, 16, 3, std::vector<float>(16 * 16 * 3, v), OIIO::TypeDesc::FLOAT);
    };
    const glm::vec4 footprint(0.1f, 0.0f, 0.0f, 0.1f);
    ASSERT_TRUE(fill(0.25f));
    {
        TextureCache first;
        const Texture* t = first.open(a).texture;
        ASSERT_NE(t, nullptr);
        EXPECT_NEAR(first.sample(*t, Wrap::Clamp, Wrap::Clamp, {0.5f, 0.5f}, footprint).x, 0.25f, 1e-5f);
    }
    ASSERT_TRUE(fill(0.75f));  // no time pushed: most likely the same second
    TextureCache second;
    const Texture* t = second.open(a).texture;
    ASSERT_NE(t, nullptr);
    EXPECT_NEAR(second.sample(*t, Wrap::Clamp, Wrap::Clamp, {0.5f, 0.5f}, footprint).x, 0.75f, 1e-5f);

    const std::string sub = dir.file("folder");
    std::filesystem::create_directories(sub);
    second.watch(sub);
    { std::ofstream(sub + "/note.txt") << "x"; }
    EXPECT_TRUE(second.reloadChanged().empty());
}

TEST(TextureCacheReload, AWatcherThatReadsAgainLeavesNothingToReload) {
    // A light re-synced for another reason reads its image again (watch() first): a reload
    // after that has nothing to do.
    TempDir dir;
    TextureCache cache;
    const std::string sky = dir.file("sky.exr");
    ASSERT_TRUE(fillAhead(sky, 4, 0.25f, 1));
    cache.watch(sky);
    ASSERT_TRUE(fillAhead(sky, 4, 0.5f, 2));
    cache.watch(sky);  // the light read it again
    EXPECT_TRUE(cache.reloadChanged().empty());
    ASSERT_TRUE(fillAhead(sky, 4, 0.75f, 3));
    EXPECT_FALSE(cache.reloadChanged().empty());  // an edit since is still seen
}
