// SPDX-License-Identifier: Apache-2.0
#include "delegate/shading/residentImage.h"

#include "delegate/imageio/imageIO.h"

#include <algorithm>
#include <cmath>

namespace principled::shading {

namespace {

size_t bytesPerValue(ResidentImage::Storage s) {
    switch (s) {
        case ResidentImage::Storage::UInt8:
            return 1;
        case ResidentImage::Storage::UInt16:
            return 2;
        case ResidentImage::Storage::Float:
            break;
    }
    return 4;
}

// Wraps texel index i of an axis of n texels; false where the texel reads as the fill value 0.
inline bool wrapTexel(Wrap w, int& i, int n) {
    if (static_cast<unsigned>(i) < static_cast<unsigned>(n)) return true;
    switch (w) {
        case Wrap::Black:
            return false;  // OpenImageIO WrapBlack: texels outside the image are the fill (0)
        case Wrap::Clamp:
            i = i < 0 ? 0 : n - 1;  // OpenImageIO WrapClamp: the nearest edge texel
            return true;
        case Wrap::Repeat:
            i %= n;  // OpenImageIO WrapPeriodic: i mod n
            if (i < 0) i += n;
            return true;
        case Wrap::Mirror: {
            // OpenImageIO WrapMirror: period 2n, reflected at the edges (edge texels repeat).
            const int period = 2 * n;
            i %= period;
            if (i < 0) i += period;
            if (i >= n) i = period - 1 - i;
            return true;
        }
    }
    return false;
}

// Texel value to float: OpenImageIO's 8/16-bit normalisation (code / 255, code / 65535).
inline float texel(uint8_t v) {
    return static_cast<float>(v) * (1.0f / 255.0f);
}
inline float texel(uint16_t v) {
    return static_cast<float>(v) * (1.0f / 65535.0f);
}
inline float texel(float v) {
    return v;
}

// Texel coordinates are kept within +-2^30 so the integer indices below cannot overflow
// (NaN goes to the low end); far beyond any texture's size, so no lookup changes.
constexpr float kMaxTexel = 1073741824.0f;
inline float limited(float x) {
    return x > -kMaxTexel ? (x < kMaxTexel ? x : kMaxTexel) : -kMaxTexel;
}

}  // namespace

ResidentImage::Storage ResidentImage::storageFor(const imageio::ImageSpec& spec) {
    switch (spec.format) {
        case imageio::PixelType::UInt8:
            return Storage::UInt8;
        case imageio::PixelType::UInt16:
            return Storage::UInt16;
        default:
            return Storage::Float;  // half, float, 32-bit integers, anything else
    }
}

size_t ResidentImage::bytesFor(const imageio::ImageSpec& spec) {
    if (spec.width < 1 || spec.height < 1 || spec.channels < 1) return 0;
    return size_t(spec.width) * size_t(spec.height) * size_t(std::min(spec.channels, 4)) *
           bytesPerValue(storageFor(spec));
}

std::unique_ptr<ResidentImage> ResidentImage::read(imageio::ImageReader& reader,
                                                   std::string* error) {
    const imageio::ImageSpec& spec = reader.spec();
    if (spec.width < 1 || spec.height < 1 || spec.channels < 1) {
        *error = "image has no pixels or no channels";
        return nullptr;
    }
    const int n = std::min(spec.channels, 4);
    const Storage storage = storageFor(spec);
    auto image = std::make_unique<ResidentImage>(spec.width, spec.height, n, storage);
    const imageio::PixelType as = storage == Storage::UInt8    ? imageio::PixelType::UInt8
                                  : storage == Storage::UInt16 ? imageio::PixelType::UInt16
                                                               : imageio::PixelType::Float;
    if (!reader.read(as, n, image->data())) {
        *error = reader.error();
        if (error->empty()) *error = "pixels cannot be read";
        return nullptr;
    }
    return image;
}

ResidentImage::ResidentImage(int width, int height, int channels, Storage storage)
    : _width(width), _height(height), _channels(std::clamp(channels, 1, 4)), _storage(storage) {
    _bytes = size_t(width) * size_t(height) * size_t(_channels) * bytesPerValue(storage);
    _pixels.reset(new unsigned char[_bytes]);  // not zeroed: read() overwrites every byte
    auto pick = [&](auto zero) -> LookupFn {
        using T = decltype(zero);
        switch (_channels) {
            case 1:
                return &lookupImpl<T, 1>;
            case 2:
                return &lookupImpl<T, 2>;
            case 3:
                return &lookupImpl<T, 3>;
            default:
                return &lookupImpl<T, 4>;
        }
    };
    switch (storage) {
        case Storage::UInt8:
            _lookup = pick(uint8_t{});
            break;
        case Storage::UInt16:
            _lookup = pick(uint16_t{});
            break;
        case Storage::Float:
            _lookup = pick(float{});
            break;
    }
}

template <typename T, int N>
void ResidentImage::lookupImpl(const ResidentImage& image, Wrap wrapS, Wrap wrapT, float s, float t,
                               float* out) {
    const int w = image._width, h = image._height;
    // OpenImageIO st_to_texel: texel x is centred at s = (x + 0.5) / width (same for t).
    const float fx = limited(s * static_cast<float>(w) - 0.5f);
    const float fy = limited(t * static_cast<float>(h) - 0.5f);
    const float x0f = std::floor(fx), y0f = std::floor(fy);
    const float ax = fx - x0f, ay = fy - y0f;  // weights of the right / lower neighbours
    int x0 = static_cast<int>(x0f), y0 = static_cast<int>(y0f);
    int x1 = x0 + 1, y1 = y0 + 1;
    const T* pixels = reinterpret_cast<const T*>(image._pixels.get());
    float v00[N], v10[N], v01[N], v11[N];  // v<dx><dy>: (x0, y0), (x1, y0), (x0, y1), (x1, y1)
    if (x0 >= 0 && x1 < w && y0 >= 0 && y1 < h) {
        const T* top = pixels + (size_t(y0) * size_t(w) + size_t(x0)) * N;
        const T* bottom = top + size_t(w) * N;
        for (int c = 0; c < N; ++c) {
            v00[c] = texel(top[c]);
            v10[c] = texel(top[N + c]);
            v01[c] = texel(bottom[c]);
            v11[c] = texel(bottom[N + c]);
        }
    } else {
        const bool inX0 = wrapTexel(wrapS, x0, w), inX1 = wrapTexel(wrapS, x1, w);
        const bool inY0 = wrapTexel(wrapT, y0, h), inY1 = wrapTexel(wrapT, y1, h);
        auto fetch = [&](bool inside, int x, int y, float* v) {
            if (!inside) {
                for (int c = 0; c < N; ++c) v[c] = 0.0f;
                return;
            }
            const T* p = pixels + (size_t(y) * size_t(w) + size_t(x)) * N;
            for (int c = 0; c < N; ++c) v[c] = texel(p[c]);
        };
        fetch(inX0 && inY0, x0, y0, v00);
        fetch(inX1 && inY0, x1, y0, v10);
        fetch(inX0 && inY1, x0, y1, v01);
        fetch(inX1 && inY1, x1, y1, v11);
    }
    // Bilinear interpolation of the four texels around (fx, fy) (OpenImageIO's bilerp order).
    for (int c = 0; c < N; ++c)
        out[c] = (1.0f - ay) * ((1.0f - ax) * v00[c] + ax * v10[c]) +
                 ay * ((1.0f - ax) * v01[c] + ax * v11[c]);
}

}  // namespace principled::shading
