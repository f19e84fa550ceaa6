// SPDX-License-Identifier: Apache-2.0
#include "delegate/shading/residentImage.h"

#include "delegate/imageio/imageIO.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

using namespace principled::shading;
using principled::imageio::ImageSpec;
using principled::imageio::PixelType;

namespace {

// A 3x2 one-channel float image with texel (x, y) = 10 y + x (row 0 the top row).
ResidentImage ramp() {
    ResidentImage image(3, 2, 1, ResidentImage::Storage::Float);
    float* p = static_cast<float*>(image.data());
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x) p[y * 3 + x] = float(10 * y + x);
    return image;
}

// The value at the centre of texel column x (any integer) in row 0.
float at(const ResidentImage& image, Wrap wrap, int x) {
    float v = -1.0f;
    image.lookup(wrap, Wrap::Clamp, (x + 0.5f) / image.width(), 0.5f / image.height(), &v);
    return v;
}

}  // namespace

TEST(ResidentImage, StorageKeepsTheFilePrecision) {
    ImageSpec spec;
    spec.width = 10;
    spec.height = 3;
    spec.channels = 6;  // at most 4 are kept
    spec.format = PixelType::UInt8;
    EXPECT_EQ(ResidentImage::storageFor(spec), ResidentImage::Storage::UInt8);
    EXPECT_EQ(ResidentImage::bytesFor(spec), 10u * 3 * 4);
    spec.format = PixelType::UInt16;
    spec.channels = 3;
    EXPECT_EQ(ResidentImage::storageFor(spec), ResidentImage::Storage::UInt16);
    EXPECT_EQ(ResidentImage::bytesFor(spec), 10u * 3 * 3 * 2);
    spec.format = PixelType::Half;
    EXPECT_EQ(ResidentImage::storageFor(spec), ResidentImage::Storage::Float);
    EXPECT_EQ(ResidentImage::bytesFor(spec), 10u * 3 * 3 * 4);
    spec.width = 0;
    EXPECT_EQ(ResidentImage::bytesFor(spec), 0u);
}

TEST(ResidentImage, TexelCentresAndBilinearBetweenThem) {
    ResidentImage image = ramp();
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x) {
            float v = -1.0f;
            image.lookup(Wrap::Black, Wrap::Black, (x + 0.5f) / 3, (y + 0.5f) / 2, &v);
            EXPECT_FLOAT_EQ(v, float(10 * y + x));
        }
    // Halfway between the four texels (0,0), (1,0), (0,1), (1,1): their mean.
    float v = -1.0f;
    image.lookup(Wrap::Black, Wrap::Black, 1.0f / 3, 0.5f, &v);
    EXPECT_FLOAT_EQ(v, (0 + 1 + 10 + 11) / 4.0f);
    // Black wrap fades towards 0 across the border: at the left edge half of texel 0.
    image.lookup(Wrap::Black, Wrap::Clamp, 0.0f, 0.25f, &v);
    EXPECT_FLOAT_EQ(v, 0.0f);  // texel 0 is 0
    image.lookup(Wrap::Black, Wrap::Clamp, 1.0f, 0.25f, &v);
    EXPECT_FLOAT_EQ(v, 1.0f);  // half of texel 2 (= 2)
}

TEST(ResidentImage, WrapModesPerTexel) {
    ResidentImage image = ramp();
    // Columns -4 .. 7 of a 3-texel row.
    const float black[] = {0, 0, 0, 0, 0, 1, 2, 0, 0, 0, 0, 0};
    const float clamp[] = {0, 0, 0, 0, 0, 1, 2, 2, 2, 2, 2, 2};
    const float repeat[] = {2, 0, 1, 2, 0, 1, 2, 0, 1, 2, 0, 1};
    const float mirror[] = {2, 2, 1, 0, 0, 1, 2, 2, 1, 0, 0, 1};
    for (int x = -4; x < 8; ++x) {
        EXPECT_FLOAT_EQ(at(image, Wrap::Black, x), black[x + 4]) << x;
        EXPECT_FLOAT_EQ(at(image, Wrap::Clamp, x), clamp[x + 4]) << x;
        EXPECT_FLOAT_EQ(at(image, Wrap::Repeat, x), repeat[x + 4]) << x;
        EXPECT_FLOAT_EQ(at(image, Wrap::Mirror, x), mirror[x + 4]) << x;
    }
}

TEST(ResidentImage, IntegerStorageIsNormalised) {
    ResidentImage a(1, 1, 2, ResidentImage::Storage::UInt8);
    static_cast<uint8_t*>(a.data())[0] = 255;
    static_cast<uint8_t*>(a.data())[1] = 51;
    float v[2];
    a.lookup(Wrap::Clamp, Wrap::Clamp, 0.3f, 0.7f, v);
    EXPECT_FLOAT_EQ(v[0], 1.0f);
    EXPECT_FLOAT_EQ(v[1], 0.2f);
    ResidentImage b(1, 1, 1, ResidentImage::Storage::UInt16);
    static_cast<uint16_t*>(b.data())[0] = 13107;
    b.lookup(Wrap::Repeat, Wrap::Repeat, 5.5f, -3.2f, v);
    EXPECT_FLOAT_EQ(v[0], 0.2f);
    EXPECT_EQ(b.bytes(), 2u);
}

TEST(ResidentImage, HugeAndNonFiniteCoordinatesStayInside) {
    ResidentImage image = ramp();
    for (Wrap w : {Wrap::Black, Wrap::Clamp, Wrap::Repeat, Wrap::Mirror})
        for (float s : {1e30f, -1e30f, NAN, INFINITY, -INFINITY, 3e9f}) {
            float v = -1.0f;
            image.lookup(w, w, s, s, &v);
            EXPECT_TRUE(std::isfinite(v));
        }
}
