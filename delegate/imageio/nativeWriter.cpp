// SPDX-License-Identifier: Apache-2.0
#include "delegate/imageio/nativeWriter.h"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <numeric>

namespace principled::imageio {

namespace {

// Little-endian appends (OpenEXR).
void putU32(std::vector<uint8_t>& b, uint32_t v) {
    for (int i = 0; i < 4; ++i) b.push_back(uint8_t(v >> (8 * i)));
}
void putI32(std::vector<uint8_t>& b, int32_t v) { putU32(b, uint32_t(v)); }
void putU64(std::vector<uint8_t>& b, uint64_t v) {
    for (int i = 0; i < 8; ++i) b.push_back(uint8_t(v >> (8 * i)));
}
void putF32(std::vector<uint8_t>& b, float f) {
    uint32_t v;
    std::memcpy(&v, &f, 4);
    putU32(b, v);
}
void putStr(std::vector<uint8_t>& b, const std::string& s) {
    b.insert(b.end(), s.begin(), s.end());
    b.push_back(0);
}
void attribute(std::vector<uint8_t>& b, const char* name, const char* type,
               const std::vector<uint8_t>& value) {
    putStr(b, name);
    putStr(b, type);
    putU32(b, uint32_t(value.size()));
    b.insert(b.end(), value.begin(), value.end());
}

bool writeFile(const std::string& path, const std::vector<uint8_t>& head,
               const std::vector<std::vector<uint8_t>>& parts, std::string* error) {
    std::FILE* f = std::fopen(path.c_str(), "wb");
    if (!f) {
        *error = std::string("cannot open for writing: ") + std::strerror(errno);
        return false;
    }
    bool ok = std::fwrite(head.data(), 1, head.size(), f) == head.size();
    for (const auto& p : parts) ok = ok && std::fwrite(p.data(), 1, p.size(), f) == p.size();
    ok = (std::fclose(f) == 0) && ok;
    if (!ok) *error = std::string("write failed: ") + std::strerror(errno);
    return ok;
}

}  // namespace

bool writeExrFloat(const std::string& path, int width, int height,
                   const std::vector<std::string>& names, const float* pixels,
                   std::string* error) {
    const size_t nch = names.size();
    if (width <= 0 || height <= 0 || nch == 0) {
        *error = "nothing to write";
        return false;
    }
    // Channels sorted by name (the order OpenEXR stores and reads them in).
    std::vector<size_t> order(nch);
    std::iota(order.begin(), order.end(), size_t(0));
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return names[a] < names[b]; });

    std::vector<uint8_t> h;
    putU32(h, 20000630);  // magic
    bool longNames = false;
    for (const auto& n : names) longNames |= n.size() > 31;
    putU32(h, 2u | (longNames ? 0x400u : 0u));  // version 2, scanline, single part

    std::vector<uint8_t> v;
    for (size_t c : order) {
        putStr(v, names[c]);
        putI32(v, 2);  // FLOAT
        v.push_back(0);  // pLinear
        v.insert(v.end(), 3, 0);  // reserved
        putI32(v, 1);  // xSampling
        putI32(v, 1);  // ySampling
    }
    v.push_back(0);
    attribute(h, "channels", "chlist", v);
    attribute(h, "compression", "compression", {3});  // ZIP_COMPRESSION: 16 lines per block
    v.clear();
    putI32(v, 0), putI32(v, 0), putI32(v, width - 1), putI32(v, height - 1);
    attribute(h, "dataWindow", "box2i", v);
    attribute(h, "displayWindow", "box2i", v);
    attribute(h, "lineOrder", "lineOrder", {0});  // INCREASING_Y
    v.clear();
    putF32(v, 1.0f);
    attribute(h, "pixelAspectRatio", "float", v);
    v.clear();
    putF32(v, 0.0f), putF32(v, 0.0f);
    attribute(h, "screenWindowCenter", "v2f", v);
    v.clear();
    putF32(v, 1.0f);
    attribute(h, "screenWindowWidth", "float", v);
    h.push_back(0);  // end of header

    constexpr int kLines = 16;
    const int blocks = (height + kLines - 1) / kLines;
    const size_t tableAt = h.size();
    h.resize(h.size() + 8 * size_t(blocks));  // offset table, filled below

    std::vector<std::vector<uint8_t>> chunks(static_cast<size_t>(blocks));
    std::vector<uint8_t> raw, tmp;
    uint64_t offset = h.size();
    for (int bi = 0; bi < blocks; ++bi) {
        int y0 = bi * kLines, y1 = std::min(height, y0 + kLines);
        raw.resize(size_t(y1 - y0) * width * nch * 4);
        uint8_t* out = raw.data();
        for (int y = y0; y < y1; ++y)
            for (size_t c : order)
                for (int x = 0; x < width; ++x) {
                    float f = pixels[(size_t(y) * width + x) * nch + c];
                    uint32_t u;
                    std::memcpy(&u, &f, 4);
                    for (int i = 0; i < 4; ++i) *out++ = uint8_t(u >> (8 * i));
                }
        // OpenEXR's ZIP: bytes split into even/odd halves, then a delta predictor, then zlib.
        const size_t n = raw.size();
        tmp.resize(n);
        uint8_t* t1 = tmp.data();
        uint8_t* t2 = tmp.data() + (n + 1) / 2;
        for (size_t i = 0; i < n; ++i) (i % 2 == 0 ? *t1++ : *t2++) = raw[i];
        int p = tmp[0];
        for (size_t i = 1; i < n; ++i) {
            int d = int(tmp[i]) - p + (128 + 256);
            p = tmp[i];
            tmp[i] = uint8_t(d);
        }
        uLongf packed = compressBound(uLong(n));
        std::vector<uint8_t>& chunk = chunks[size_t(bi)];
        chunk.resize(8 + packed);
        if (compress2(chunk.data() + 8, &packed, tmp.data(), uLong(n), 4) != Z_OK) {
            *error = "zlib compression failed";
            return false;
        }
        // A block that does not shrink is stored as it is (readers compare the sizes).
        if (packed >= n) {
            std::memcpy(chunk.data() + 8, raw.data(), n);
            packed = uLongf(n);
        }
        chunk.resize(8 + packed);
        std::vector<uint8_t> head;
        putI32(head, y0);
        putI32(head, int32_t(packed));
        std::memcpy(chunk.data(), head.data(), 8);
        std::vector<uint8_t> off;
        putU64(off, offset);
        std::memcpy(h.data() + tableAt + 8 * size_t(bi), off.data(), 8);
        offset += chunk.size();
    }
    return writeFile(path, h, chunks, error);
}

namespace {

void putBE32(std::vector<uint8_t>& b, uint32_t v) {
    for (int i = 3; i >= 0; --i) b.push_back(uint8_t(v >> (8 * i)));
}

void pngChunk(std::vector<uint8_t>& b, const char* type, const uint8_t* data, size_t size) {
    putBE32(b, uint32_t(size));
    size_t at = b.size();
    b.insert(b.end(), type, type + 4);
    if (size) b.insert(b.end(), data, data + size);
    uLong crc = crc32(0L, Z_NULL, 0);
    crc = crc32(crc, b.data() + at, uInt(4 + size));
    putBE32(b, uint32_t(crc));
}

}  // namespace

bool writePng8(const std::string& path, int width, int height, int channels,
               const uint8_t* pixels, std::string* error) {
    if (width <= 0 || height <= 0 || (channels != 3 && channels != 4)) {
        *error = "PNG needs 3 or 4 channels";
        return false;
    }
    std::vector<uint8_t> b = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    std::vector<uint8_t> ihdr;
    putBE32(ihdr, uint32_t(width));
    putBE32(ihdr, uint32_t(height));
    ihdr.push_back(8);                            // bit depth
    ihdr.push_back(channels == 4 ? 6 : 2);        // RGBA or RGB
    ihdr.push_back(0), ihdr.push_back(0), ihdr.push_back(0);  // deflate, adaptive, no interlace
    pngChunk(b, "IHDR", ihdr.data(), ihdr.size());
    // Each row: filter type 1 (Sub: the difference to the pixel on the left).
    const size_t row = size_t(width) * channels;
    std::vector<uint8_t> filtered((row + 1) * height);
    for (int y = 0; y < height; ++y) {
        uint8_t* o = &filtered[(row + 1) * y];
        const uint8_t* in = pixels + row * y;
        o[0] = 1;
        for (size_t i = 0; i < row; ++i)
            o[1 + i] = uint8_t(in[i] - (i >= size_t(channels) ? in[i - channels] : 0));
    }
    uLongf packed = compressBound(uLong(filtered.size()));
    std::vector<uint8_t> idat(packed);
    if (compress2(idat.data(), &packed, filtered.data(), uLong(filtered.size()), 6) != Z_OK) {
        *error = "zlib compression failed";
        return false;
    }
    pngChunk(b, "IDAT", idat.data(), packed);
    pngChunk(b, "IEND", nullptr, 0);
    return writeFile(path, b, {}, error);
}

}  // namespace principled::imageio
