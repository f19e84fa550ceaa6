// SPDX-License-Identifier: Apache-2.0
// ResidentImage: the finest level of a texture file held in memory at the file's precision
// (8-bit as uint8, 16-bit as uint16, anything else as float; at most 4 channels), read by point
// lookups with OpenImageIO's bilinear conventions, so they need no texture system.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "delegate/shading/textureWrap.h"

namespace principled::imageio {
class ImageReader;
struct ImageSpec;
}  // namespace principled::imageio

namespace principled::shading {

class ResidentImage {
  public:
    enum class Storage : uint8_t { UInt8, UInt16, Float };

    /// How a file with this spec is stored, and the bytes its finest level takes.
    static Storage storageFor(const imageio::ImageSpec& spec);
    static size_t bytesFor(const imageio::ImageSpec& spec);

    /// Reads all pixels of `reader` (level 0, the first min(channels, 4) channels). Null with
    /// *error when the file has no pixels or the read fails.
    static std::unique_ptr<ResidentImage> read(imageio::ImageReader& reader, std::string* error);

    /// Uninitialised pixels, for the caller to fill (row 0 = the top row of the file, channels
    /// interleaved): a multi-gigabyte texture is not written twice.
    ResidentImage(int width, int height, int channels, Storage storage);

    int width() const { return _width; }
    int height() const { return _height; }
    int channels() const { return _channels; }
    Storage storage() const { return _storage; }
    size_t bytes() const { return _bytes; }
    void* data() { return _pixels.get(); }

    /// Bilinear lookup on this level at OpenImageIO's (s, t): t runs down from the top row, texel
    /// (x, y) is centred at ((x + 0.5) / width, (y + 0.5) / height). Writes channels() values,
    /// 8/16-bit ones normalised to [0,1]. Black wrap reads texels outside the image as 0.
    void lookup(Wrap wrapS, Wrap wrapT, float s, float t, float* out) const {
        _lookup(*this, wrapS, wrapT, s, t, out);
    }

  private:
    using LookupFn = void (*)(const ResidentImage&, Wrap, Wrap, float, float, float*);
    template <typename T, int N>
    static void lookupImpl(const ResidentImage& image, Wrap wrapS, Wrap wrapT, float s, float t,
                           float* out);

    int _width = 0, _height = 0, _channels = 0;
    Storage _storage = Storage::Float;
    size_t _bytes = 0;
    std::unique_ptr<unsigned char[]> _pixels;
    LookupFn _lookup = nullptr;
};

}  // namespace principled::shading
