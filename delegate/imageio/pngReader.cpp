// SPDX-License-Identifier: Apache-2.0
#include "delegate/imageio/pngReader.h"

#include <png.h>
#include <strings.h>

#include <cmath>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace principled::imageio {

namespace {

uint32_t be32(const unsigned char* p) {
    return uint32_t(p[0]) << 24 | uint32_t(p[1]) << 16 | uint32_t(p[2]) << 8 | uint32_t(p[3]);
}

// The 'desc' tag of an ICC profile (ICC.1:2001-04 §6.5.17 textDescriptionType, ICC.1:2010
// §10.15 multiLocalizedUnicodeType: its first record), as plain text; empty if absent.
std::string iccDescription(const unsigned char* p, size_t size) {
    if (size < 132) return {};
    const uint32_t count = be32(p + 128);  // ICC.1 §7.3: the tag table follows the 128-byte header
    for (uint32_t i = 0; i < count && 132 + 12 * size_t(i + 1) <= size; ++i) {
        const unsigned char* entry = p + 132 + 12 * size_t(i);
        if (be32(entry) != 0x64657363u) continue;  // 'desc'
        const size_t offset = be32(entry + 4), length = be32(entry + 8);
        if (offset + length > size || length < 12) return {};
        const unsigned char* tag = p + offset;
        if (be32(tag) == 0x64657363u) {  // 'desc': uint32 ASCII count (with NUL), ASCII
            size_t n = std::min<size_t>(be32(tag + 8), length - 12);
            std::string s(reinterpret_cast<const char*>(tag + 12), n);
            return s.substr(0, s.find('\0'));
        }
        if (be32(tag) == 0x6d6c7563u && length >= 28) {  // 'mluc': records of UTF-16BE text
            const size_t bytes = be32(tag + 20), start = be32(tag + 24);
            if (start + bytes > length) return {};
            std::string s;
            for (size_t k = 0; k + 1 < bytes; k += 2) {
                unsigned c = unsigned(tag[start + k]) << 8 | tag[start + k + 1];
                if (c == 0) break;
                if (c < 0x80) {
                    s += char(c);
                } else if (c < 0x800) {
                    s += char(0xc0 | c >> 6);
                    s += char(0x80 | (c & 0x3f));
                } else {
                    s += char(0xe0 | c >> 12);
                    s += char(0x80 | (c >> 6 & 0x3f));
                    s += char(0x80 | (c & 0x3f));
                }
            }
            return s;
        }
        return {};
    }
    return {};
}

// Exif ColorSpace (tag 0xA001, Exif 2.3 §4.6.5) from a TIFF-structured Exif block (the eXIf
// chunk): looked for in IFD0 and in the Exif IFD it points to (tag 0x8769). -1 if absent.
int exifColorSpace(const unsigned char* p, size_t size) {
    if (size < 8) return -1;
    const bool little = p[0] == 'I' && p[1] == 'I';
    if (!little && !(p[0] == 'M' && p[1] == 'M')) return -1;
    auto u16 = [&](size_t at) -> unsigned {
        return little ? unsigned(p[at]) | unsigned(p[at + 1]) << 8
                      : unsigned(p[at]) << 8 | unsigned(p[at + 1]);
    };
    auto u32 = [&](size_t at) -> size_t {
        return little ? size_t(u16(at)) | size_t(u16(at + 2)) << 16
                      : size_t(u16(at)) << 16 | size_t(u16(at + 2));
    };
    size_t ifd = u32(4);
    for (int depth = 0; depth < 2; ++depth) {
        if (ifd + 2 > size) return -1;
        const unsigned n = u16(ifd);
        size_t next = 0;
        for (unsigned i = 0; i < n && ifd + 2 + 12 * size_t(i + 1) <= size; ++i) {
            const size_t e = ifd + 2 + 12 * size_t(i);
            if (u16(e) == 0xA001 && u16(e + 2) == 3) return int(u16(e + 8));  // SHORT, inline
            if (u16(e) == 0x8769) next = u32(e + 8);
        }
        if (!next) return -1;
        ifd = next;
    }
    return -1;
}

// A simple property of an XMP packet, in either RDF form: prefix:name="v" or
// <prefix:name>v</prefix:name>, looked for where OpenImageIO's XMP decoder looks: between
// "<rdf:Description" and the next "</rdf:Description>" (a self-closing Description is not
// read); the last one found wins. Empty if absent.
std::string xmpProperty(const std::string& xmp, const std::string& name) {
    std::string found;
    for (size_t from = 0;;) {
        const size_t begin = xmp.find("<rdf:Description", from);
        if (begin == std::string::npos) break;
        const size_t end = xmp.find("</rdf:Description>", begin);
        if (end == std::string::npos) break;
        const std::string part = xmp.substr(begin, end - begin);
        from = end + 1;
        for (char quote : {'"', '\''}) {
            const size_t at = part.find(name + "=" + quote);
            if (at != std::string::npos) {
                const size_t v = at + name.size() + 2;
                found = part.substr(v, part.find(quote, v) - v);
            }
        }
        const size_t at = part.find("<" + name + ">");
        if (at != std::string::npos) {
            const size_t v = at + name.size() + 2;
            found = part.substr(v, part.find('<', v) - v);
        }
    }
    return found;
}

struct ErrorState {
    std::jmp_buf jump;
    char message[256] = "libpng error";
};

void onError(png_structp png, png_const_charp message) {
    auto* state = static_cast<ErrorState*>(png_get_error_ptr(png));
    std::snprintf(state->message, sizeof state->message, "%s", message ? message : "libpng error");
    std::longjmp(state->jump, 1);
}
void onWarning(png_structp, png_const_charp) {}

class PngReader final : public ImageReader {
  public:
    explicit PngReader(std::FILE* file) : _file(file) {}
    ~PngReader() override {
        if (_png) png_destroy_read_struct(&_png, &_info, nullptr);
        if (_file) std::fclose(_file);
    }

    // Reads the chunks before the pixels and sets up OpenImageIO's conversions; false with
    // *error on any libpng error.
    bool readInfo(std::string* error) {
        _png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &_errors, onError, onWarning);
        if (_png) _info = png_create_info_struct(_png);
        if (!_png || !_info) {
            *error = "libpng cannot allocate a reader";
            return false;
        }
        if (!header()) {
            *error = _errors.message;
            return false;
        }
        return true;
    }

    const ImageSpec& spec() const override { return _spec; }

    bool read(PixelType as, int channels, void* pixels) override {
        if (_done) {
            _error = "the pixels were read already";
            return false;
        }
        _done = true;
        if (as != PixelType::UInt8 && as != PixelType::UInt16 && as != PixelType::UInt32 &&
            as != PixelType::Float) {
            _error = "the PNG reader converts to 8/16/32-bit integers or float only";
            return false;
        }
        const size_t w = size_t(_spec.width), h = size_t(_spec.height);
        const int n = _spec.channels;
        const int bytes = _spec.bitsPerChannel / 8;
        const size_t rowBytes = w * size_t(n) * size_t(bytes);
        std::vector<unsigned char*> rows(h);
        // The caller's layout is the file's (all channels at the file's precision, the resident
        // texture case): libpng decodes straight into it, with no second copy of the image.
        if (channels == n && as == (bytes == 1 ? PixelType::UInt8 : PixelType::UInt16)) {
            for (size_t y = 0; y < h; ++y) rows[y] = static_cast<unsigned char*>(pixels) + y * rowBytes;
            if (!decode(rows.data())) {
                _error = _errors.message;
                return false;
            }
            return true;
        }
        std::vector<unsigned char> buffer(h * rowBytes);
        for (size_t y = 0; y < h; ++y) rows[y] = buffer.data() + y * rowBytes;
        if (!decode(rows.data())) {
            _error = _errors.message;
            return false;
        }
        channels = std::max(1, std::min(channels, n));
        const size_t count = w * h;
        // OpenImageIO's integer conversions: 8-bit x 257 to 16-bit, 16-bit rounded to 8-bit, and
        // code / (2^bits - 1) to float.
        const double scale = bytes == 1 ? 255.0 : 65535.0;
        for (size_t i = 0; i < count; ++i)
            for (int c = 0; c < channels; ++c) {
                const size_t src = i * size_t(n) + size_t(c),
                             dst = i * size_t(channels) + size_t(c);
                unsigned v = buffer[src];
                if (bytes == 2) {
                    uint16_t v16;  // native byte order (png_set_swap); memcpy: no aliasing cast
                    std::memcpy(&v16, buffer.data() + 2 * src, 2);
                    v = v16;
                }
                switch (as) {
                    case PixelType::UInt8:
                        static_cast<uint8_t*>(pixels)[dst] =
                            bytes == 1 ? uint8_t(v) : uint8_t(std::lround(v * 255.0 / 65535.0));
                        break;
                    case PixelType::UInt16:
                        static_cast<uint16_t*>(pixels)[dst] =
                            bytes == 1 ? uint16_t(v * 257) : uint16_t(v);
                        break;
                    case PixelType::UInt32:
                        static_cast<uint32_t*>(pixels)[dst] =
                            uint32_t(std::llround(v * (4294967295.0 / scale)));
                        break;
                    default:  // Float (checked above)
                        static_cast<float*>(pixels)[dst] = float(v / scale);
                        break;
                }
            }
        return true;
    }

    std::string error() override { return _error; }

  private:
    // libpng calls that may longjmp back here: no objects with destructors in these frames.
    bool header() {
        if (setjmp(_errors.jump)) return false;
        png_init_io(_png, _file);
        png_set_sig_bytes(_png, 8);
        png_read_info(_png, _info);
        // OpenImageIO's PNG reader: palette -> RGB, tRNS -> alpha, low-bit gray -> 8-bit, and
        // 16-bit samples in native byte order.
        png_set_expand(_png);
        if (png_get_bit_depth(_png, _info) == 16) {
            const uint16_t one = 1;
            if (*reinterpret_cast<const unsigned char*>(&one) == 1) png_set_swap(_png);
        }
        // Interlaced (Adam7) files: libpng assembles the passes into whole rows.
        png_set_interlace_handling(_png);
        png_read_update_info(_png, _info);
        describe();
        return true;
    }

    bool decode(unsigned char** rows) {
        if (setjmp(_errors.jump)) return false;
        png_read_image(_png, rows);
        return true;
    }

    // Called inside header()'s setjmp scope; libpng getters here do not longjmp.
    void describe() {
        _spec.width = int(png_get_image_width(_png, _info));
        _spec.height = int(png_get_image_height(_png, _info));
        _spec.channels = int(png_get_channels(_png, _info));
        const int bits = png_get_bit_depth(_png, _info);
        _spec.format = bits == 16 ? PixelType::UInt16 : PixelType::UInt8;
        _spec.bitsPerChannel = bits == 16 ? 16 : 8;
        _spec.fileFormat = "png";
        static const char* const rgba[] = {"R", "G", "B", "A"};
        if (_spec.channels == 2) {
            _spec.channelNames = {"Y", "A"};
            _spec.alphaChannel = 1;
        } else {
            for (int c = 0; c < _spec.channels && c < 4; ++c) _spec.channelNames.push_back(rgba[c]);
            _spec.alphaChannel = _spec.channels == 4 ? 3 : -1;
        }
        // OpenImageIO 2.4: "sRGB" unless gAMA (without an sRGB chunk) states a gamma.
        _spec.strings["oiio:ColorSpace"] = "sRGB";
        int intent = 0;
        double gamma = 0.0;
        if (!png_get_sRGB(_png, _info, &intent) && png_get_gAMA(_png, _info, &gamma) && gamma > 0) {
            // gAMA stores the encoding exponent; OpenImageIO reports its inverse to 2 decimals.
            const float g = std::round(float(1.0 / gamma) * 100.0f) / 100.0f;
            _spec.numbers["oiio:Gamma"] = g;
            char name[32];
            std::snprintf(name, sizeof name, "Gamma%.2g", double(g));
            _spec.strings["oiio:ColorSpace"] = g == 1.0f ? "linear" : name;
        }
        png_charp iccName = nullptr;
        int compression = 0;
        png_bytep icc = nullptr;
        png_uint_32 iccSize = 0;
        if (png_get_iCCP(_png, _info, &iccName, &compression, &icc, &iccSize) && icc) {
            std::string description = iccDescription(icc, iccSize);
            if (!description.empty()) _spec.strings["ICCProfile:profile_description"] = description;
        }
        png_bytep exif = nullptr;
        png_uint_32 exifSize = 0;
        if (png_get_eXIf_1(_png, _info, &exifSize, &exif) && exif) {
            int cs = exifColorSpace(exif, exifSize);
            if (cs >= 0) _spec.numbers["Exif:ColorSpace"] = cs;
        }
        png_textp text = nullptr;
        int texts = 0;
        png_get_text(_png, _info, &text, &texts);
        for (int i = 0; i < texts; ++i) {
            if (!text[i].key || !text[i].text) continue;
            std::string key = text[i].key,
                        value(text[i].text,
                              text[i].text_length ? text[i].text_length : text[i].itxt_length);
            if (key == "XML:com.adobe.xmp") {
                std::string cs = xmpProperty(value, "exif:ColorSpace");
                if (!cs.empty()) _spec.numbers["Exif:ColorSpace"] = std::atof(cs.c_str());
                std::string profile = xmpProperty(value, "photoshop:ICCProfile");
                if (!profile.empty()) _spec.strings["photoshop:ICCProfile"] = profile;
                continue;
            }
            if (strcasecmp(key.c_str(), "Description") == 0)
                key = "ImageDescription";
            else if (strcasecmp(key.c_str(), "Author") == 0)
                key = "Artist";
            else if (strcasecmp(key.c_str(), "Title") == 0)
                key = "DocumentName";
            _spec.strings[key] = value;
        }
    }

    std::FILE* _file = nullptr;
    png_structp _png = nullptr;
    png_infop _info = nullptr;
    ErrorState _errors;
    ImageSpec _spec;
    std::string _error;
    bool _done = false;
};

}  // namespace

std::unique_ptr<ImageReader> openPng(const std::string& path, std::string* error) {
    std::FILE* file = std::fopen(path.c_str(), "rb");
    if (!file) {
        *error = "cannot be opened";
        return nullptr;
    }
    unsigned char signature[8];
    if (std::fread(signature, 1, 8, file) != 8 || png_sig_cmp(signature, 0, 8) != 0) {
        std::fclose(file);
        *error = "not a PNG file";
        return nullptr;
    }
    auto reader = std::make_unique<PngReader>(file);
    if (!reader->readInfo(error)) return nullptr;
    return reader;
}

}  // namespace principled::imageio
