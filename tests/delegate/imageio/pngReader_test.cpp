// SPDX-License-Identifier: Apache-2.0
// The native PNG decode against OpenImageIO's (the backend's openTexture()): same spec, same
// colour metadata, same pixels, for the usd-wg PNGs read in place and for generated files of
// every PNG colour type and bit depth.
#include "delegate/imageio/pngReader.h"

#include <gtest/gtest.h>
#include <png.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <functional>
#include <random>
#include <string>
#include <vector>

using namespace principled::imageio;

namespace {

namespace fs = std::filesystem;

class TempDir {
  public:
    TempDir() {
        _path = fs::temp_directory_path() / ("principled_png_" + std::to_string(::getpid()) + "_" +
                                             std::to_string(counter()++));
        fs::create_directories(_path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(_path, ec);
    }
    std::string file(const std::string& name) const { return (_path / name).string(); }

  private:
    static int& counter() {
        static int n = 0;
        return n;
    }
    fs::path _path;
};

struct PngFile {
    int width = 5, height = 3;
    int colorType = PNG_COLOR_TYPE_RGB;
    int bitDepth = 8;
    bool interlaced = false;
    int paletteSize = 0;  // palette entries (colour type PALETTE)
    int transparent = 0;  // tRNS: palette alphas given, or 1 for a gray/RGB key colour
    std::function<void(png_structp, png_infop)> chunks;  // extra chunks before the pixels
};

// Writes a PNG with libpng: samples from a fixed random sequence (packed for < 8 bits).
bool writePng(const std::string& path, const PngFile& f, uint32_t seed = 1) {
    std::FILE* out = std::fopen(path.c_str(), "wb");
    if (!out) return false;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        std::fclose(out);
        return false;
    }
    png_init_io(png, out);
    png_set_IHDR(png, info, f.width, f.height, f.bitDepth, f.colorType,
                 f.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    std::mt19937 rng(seed);
    const int maxCode =
        f.colorType == PNG_COLOR_TYPE_PALETTE ? f.paletteSize - 1 : (1 << f.bitDepth) - 1;
    if (f.colorType == PNG_COLOR_TYPE_PALETTE) {
        std::vector<png_color> palette(f.paletteSize);
        for (auto& c : palette) c = {png_byte(rng()), png_byte(rng()), png_byte(rng())};
        png_set_PLTE(png, info, palette.data(), f.paletteSize);
        if (f.transparent) {
            std::vector<png_byte> alpha(f.transparent);
            for (auto& a : alpha) a = png_byte(rng());
            png_set_tRNS(png, info, alpha.data(), f.transparent, nullptr);
        }
    } else if (f.transparent) {
        png_color_16 key{};
        key.gray = key.red = key.green = key.blue = png_uint_16(1 % (maxCode + 1));
        png_set_tRNS(png, info, nullptr, 0, &key);
    }
    if (f.chunks) f.chunks(png, info);
    png_write_info(png, info);
    const int channels = png_get_channels(png, info);
    const size_t rowBytes = png_get_rowbytes(png, info);
    std::vector<std::vector<png_byte>> rows(f.height, std::vector<png_byte>(rowBytes, 0));
    for (auto& row : rows) {
        const int samples = f.width * channels;
        for (int i = 0; i < samples; ++i) {
            // Code 1 often, so the tRNS key colour occurs.
            unsigned v =
                rng() % 4 == 0 ? 1u % unsigned(maxCode + 1) : rng() % unsigned(maxCode + 1);
            if (f.bitDepth == 16) {
                row[2 * i] = png_byte(v >> 8);
                row[2 * i + 1] = png_byte(v);
            } else if (f.bitDepth == 8) {
                row[i] = png_byte(v);
            } else {
                const int perByte = 8 / f.bitDepth;
                row[i / perByte] |= png_byte(v << (8 - f.bitDepth * (i % perByte + 1)));
            }
        }
    }
    std::vector<png_bytep> pointers;
    for (auto& row : rows) pointers.push_back(row.data());
    png_write_image(png, pointers.data());
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return std::fclose(out) == 0;
}

// The keys the texture cache reads, plus the text ones a file may carry.
const char* const kStrings[] = {"oiio:ColorSpace", "ICCProfile:profile_description",
                                "photoshop:ICCProfile", "wrapmodes", "ImageDescription"};
const char* const kNumbers[] = {"oiio:Gamma", "Exif:ColorSpace"};

// Native and OpenImageIO decodes of `path` agree on spec, colour metadata and every sample.
void expectSameDecode(const std::string& path) {
    SCOPED_TRACE(path);
    std::string e;
    std::unique_ptr<ImageReader> native = openPng(path, &e);
    ASSERT_TRUE(native) << e;
    Backend* io = backend(&e);
    ASSERT_TRUE(io) << e;
    std::unique_ptr<ImageReader> oiio = io->openTexture(path, &e);
    ASSERT_TRUE(oiio) << e;
    const ImageSpec &a = native->spec(), &b = oiio->spec();
    ASSERT_EQ(a.width, b.width);
    ASSERT_EQ(a.height, b.height);
    ASSERT_EQ(a.channels, b.channels);
    ASSERT_EQ(a.format, b.format);
    EXPECT_EQ(a.bitsPerChannel, b.bitsPerChannel);
    EXPECT_EQ(a.fileFormat, b.fileFormat);
    EXPECT_EQ(a.alphaChannel, b.alphaChannel);
    for (const char* key : kStrings) EXPECT_EQ(a.string(key), b.string(key)) << key;
    for (const char* key : kNumbers) {
        EXPECT_EQ(a.numbers.count(key), b.numbers.count(key)) << key;
        EXPECT_NEAR(a.number(key), b.number(key), 1e-5) << key;
    }
    const size_t samples = size_t(a.width) * a.height * a.channels;
    const size_t bytes = samples * (a.format == PixelType::UInt16 ? 2 : 1);
    std::vector<unsigned char> pa(bytes, 0xab), pb(bytes, 0xcd);
    ASSERT_TRUE(native->read(a.format, a.channels, pa.data())) << native->error();
    ASSERT_TRUE(oiio->read(b.format, b.channels, pb.data())) << oiio->error();
    size_t differ = 0;
    for (size_t i = 0; i < bytes; ++i) differ += pa[i] != pb[i];
    EXPECT_EQ(differ, 0u) << "bytes that differ of " << bytes;
    // Float conversion too (what a float read would give).
    std::vector<float> fa(samples), fb(samples);
    ASSERT_TRUE(openPng(path, &e)->read(PixelType::Float, a.channels, fa.data()));
    ASSERT_TRUE(io->openTexture(path, &e)->read(PixelType::Float, b.channels, fb.data()));
    for (size_t i = 0; i < samples; ++i) ASSERT_NEAR(fa[i], fb[i], 1e-7f) << i;
}

}  // namespace

TEST(PngReader, UsdWgPngsDecodeAsOpenImageIODoes) {
    const fs::path root = PRINCIPLED_SOURCE_DIR "/../shared/usd-wg";
    std::error_code ec;
    int files = 0;
    for (auto it = fs::recursive_directory_iterator(root, ec);
         it != fs::recursive_directory_iterator(); it.increment(ec)) {
        if (it->path().extension() != ".png") continue;
        expectSameDecode(it->path().string());
        ++files;
    }
    EXPECT_GE(files, 10);
}

TEST(PngReader, EveryColourTypeAndBitDepth) {
    TempDir dir;
    struct Case {
        const char* name;
        PngFile file;
    };
    std::vector<Case> cases;
    for (int bits : {1, 2, 4, 8, 16}) {
        PngFile f;
        f.colorType = PNG_COLOR_TYPE_GRAY;
        f.bitDepth = bits;
        cases.push_back({"gray", f});
        f.transparent = 1;
        cases.push_back({"gray_trns", f});
        if (bits <= 8) {
            PngFile p;
            p.colorType = PNG_COLOR_TYPE_PALETTE;
            p.bitDepth = bits;
            p.paletteSize = 1 << bits;
            cases.push_back({"palette", p});
            p.transparent = std::max(1, p.paletteSize / 2);
            cases.push_back({"palette_trns", p});
        }
    }
    for (int bits : {8, 16}) {
        for (int type : {PNG_COLOR_TYPE_GRAY_ALPHA, PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGB_ALPHA}) {
            PngFile f;
            f.colorType = type;
            f.bitDepth = bits;
            cases.push_back({"type", f});
            f.interlaced = true;
            f.width = 13;
            f.height = 11;
            cases.push_back({"interlaced", f});
        }
        PngFile f;
        f.bitDepth = bits;
        f.transparent = 1;
        cases.push_back({"rgb_trns", f});
    }
    int i = 0;
    for (const Case& c : cases) {
        std::string path = dir.file(std::string(c.name) + "_" + std::to_string(i++) + ".png");
        ASSERT_TRUE(writePng(path, c.file, uint32_t(i))) << path;
        expectSameDecode(path);
    }
}

TEST(PngReader, ColourMetadataChunks) {
    TempDir dir;
    // The iCCP profile of a real file (sRGB IEC61966-2.1), re-embedded.
    std::vector<png_byte> icc;
    std::string iccName;
    {
        std::string src = PRINCIPLED_SOURCE_DIR
            "/../shared/usd-wg/test_assets/TextureFileFormatTests/png_rgb_8-bit.png";
        std::FILE* in = std::fopen(src.c_str(), "rb");
        ASSERT_NE(in, nullptr);
        png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
        png_infop info = png_create_info_struct(png);
        ASSERT_EQ(setjmp(png_jmpbuf(png)), 0);
        png_init_io(png, in);
        png_read_info(png, info);
        png_charp name = nullptr;
        int compression = 0;
        png_bytep data = nullptr;
        png_uint_32 size = 0;
        if (png_get_iCCP(png, info, &name, &compression, &data, &size)) {
            icc.assign(data, data + size);
            iccName = name;
        }
        png_destroy_read_struct(&png, &info, nullptr);
        std::fclose(in);
    }
    ASSERT_FALSE(icc.empty());
    // eXIf: a big-endian TIFF block, IFD0 -> Exif IFD (0x8769) -> ColorSpace (0xA001) = 1.
    const std::vector<png_byte> exif = {
        'M', 'M', 0,    42,   0, 0, 0, 8,                                  // header
        0,   1,   0x87, 0x69, 0, 4, 0, 0, 0, 1, 0, 0, 0, 26, 0, 0, 0, 0,   // IFD0, next 0
        0,   1,   0xA0, 0x01, 0, 3, 0, 0, 0, 1, 0, 1, 0, 0,  0, 0, 0, 0};  // Exif IFD
    // XMP packets: properties as attributes, as elements, and in a self-closing Description
    // (which OpenImageIO does not read, so neither must we).
    auto packet = [](const std::string& description) {
        return "<?xpacket begin=\"\" id=\"W5M0MpCehiHzreSzNTczkc9d\"?><x:xmpmeta "
               "xmlns:x=\"adobe:ns:meta/\"><rdf:RDF "
               "xmlns:rdf=\"http://www.w3.org/1999/02/22-rdf-syntax-ns#\">" +
               description + "</rdf:RDF></x:xmpmeta><?xpacket end=\"w\"?>";
    };
    const std::string ns =
        "rdf:about=\"\" xmlns:exif=\"http://ns.adobe.com/exif/1.0/\" "
        "xmlns:photoshop=\"http://ns.adobe.com/photoshop/1.0/\"";
    const std::string xmp = packet("<rdf:Description " + ns +
                                   " exif:ColorSpace=\"65535\" photoshop:ICCProfile=\"Display "
                                   "P3 (Linear)\"><dc:title/></rdf:Description>");
    const std::string xmpElements =
        packet("<rdf:Description " + ns +
               "><exif:ColorSpace>1</exif:ColorSpace><photoshop:ICCProfile>sRGB "
               "IEC61966-2.1</photoshop:ICCProfile></rdf:Description>");
    const std::string xmpSelfClosing =
        packet("<rdf:Description " + ns + " exif:ColorSpace=\"1\" photoshop:ICCProfile=\"x\"/>");
    auto text = [](png_structp png, png_infop info, int compression, const char* key,
                   const std::string& value) {
        png_text t{};
        t.compression = compression;
        t.key = const_cast<char*>(key);
        t.text = const_cast<char*>(value.c_str());
        if (compression == PNG_ITXT_COMPRESSION_NONE)
            t.itxt_length = value.size();
        else
            t.text_length = value.size();
        png_set_text(png, info, &t, 1);
    };
    const std::vector<std::pair<const char*, std::function<void(png_structp, png_infop)>>> cases = {
        {"none", nullptr},
        {"gamma1", [](png_structp p, png_infop i) { png_set_gAMA(p, i, 1.0); }},
        {"gamma22", [](png_structp p, png_infop i) { png_set_gAMA(p, i, 0.45455); }},
        {"gamma18", [](png_structp p, png_infop i) { png_set_gAMA(p, i, 1 / 1.8); }},
        {"gamma333", [](png_structp p, png_infop i) { png_set_gAMA(p, i, 0.3); }},
        {"gamma1234", [](png_structp p, png_infop i) { png_set_gAMA(p, i, 1 / 1.234); }},
        {"srgb", [](png_structp p, png_infop i) { png_set_sRGB(p, i, 0); }},
        {"srgb_gamma",
         [](png_structp p, png_infop i) {
             png_set_sRGB(p, i, 0);
             png_set_gAMA(p, i, 0.45455);  // libpng refuses a gamma that contradicts sRGB
         }},
        {"iccp",
         [&](png_structp p, png_infop i) {
             png_set_iCCP(p, i, iccName.c_str(), 0, icc.data(), png_uint_32(icc.size()));
         }},
        {"exif",
         [&](png_structp p, png_infop i) {
             png_set_eXIf_1(p, i, png_uint_32(exif.size()), const_cast<png_bytep>(exif.data()));
         }},
        {"xmp",
         [&](png_structp p, png_infop i) {
             text(p, i, PNG_ITXT_COMPRESSION_NONE, "XML:com.adobe.xmp", xmp);
         }},
        {"xmp_elements",
         [&](png_structp p, png_infop i) {
             text(p, i, PNG_ITXT_COMPRESSION_NONE, "XML:com.adobe.xmp", xmpElements);
         }},
        {"xmp_selfclosing",
         [&](png_structp p, png_infop i) {
             text(p, i, PNG_TEXT_COMPRESSION_zTXt, "XML:com.adobe.xmp", xmpSelfClosing);
         }},
        {"text",
         [&](png_structp p, png_infop i) {
             text(p, i, PNG_TEXT_COMPRESSION_NONE, "wrapmodes", "periodic,mirror");
             text(p, i, PNG_TEXT_COMPRESSION_zTXt, "Description", "a texture");
         }},
    };
    for (const auto& [name, chunks] : cases) {
        PngFile f;
        f.colorType = PNG_COLOR_TYPE_RGB_ALPHA;
        f.chunks = chunks;
        std::string path = dir.file(std::string(name) + ".png");
        ASSERT_TRUE(writePng(path, f)) << name;
        expectSameDecode(path);
    }
    // The values themselves (so a metadata key both decoders drop would still be noticed).
    std::string e;
    EXPECT_NEAR(openPng(dir.file("gamma1.png"), &e)->spec().number("oiio:Gamma"), 1.0, 1e-6);
    EXPECT_EQ(openPng(dir.file("iccp.png"), &e)->spec().string("ICCProfile:profile_description"),
              "sRGB IEC61966-2.1");
    EXPECT_EQ(openPng(dir.file("exif.png"), &e)->spec().number("Exif:ColorSpace"), 1.0);
    EXPECT_EQ(openPng(dir.file("xmp.png"), &e)->spec().string("photoshop:ICCProfile"),
              "Display P3 (Linear)");
    EXPECT_EQ(openPng(dir.file("text.png"), &e)->spec().string("wrapmodes"), "periodic,mirror");
    EXPECT_EQ(openPng(dir.file("xmp_elements.png"), &e)->spec().number("Exif:ColorSpace"), 1.0);
    EXPECT_EQ(openPng(dir.file("xmp_selfclosing.png"), &e)->spec().numbers.count("Exif:ColorSpace"),
              0u);
}

TEST(PngReader, NonPngAndBrokenFilesAreRefused) {
    TempDir dir;
    std::string e;
    EXPECT_EQ(openPng(dir.file("missing.png"), &e), nullptr);
    std::string text = dir.file("text.png");
    {
        std::FILE* f = std::fopen(text.c_str(), "wb");
        std::fputs("not a png at all", f);
        std::fclose(f);
    }
    EXPECT_EQ(openPng(text, &e), nullptr);
    // A PNG cut inside its pixel data: the header opens, the pixel read fails cleanly.
    std::string good = dir.file("good.png"), cut = dir.file("cut.png");
    PngFile f;
    f.width = 64;
    f.height = 64;
    ASSERT_TRUE(writePng(good, f));
    fs::copy_file(good, cut);
    fs::resize_file(cut, fs::file_size(good) / 2);
    std::unique_ptr<ImageReader> r = openPng(cut, &e);
    ASSERT_TRUE(r) << e;
    std::vector<unsigned char> px(64 * 64 * 3);
    EXPECT_FALSE(r->read(PixelType::UInt8, 3, px.data()));
    EXPECT_FALSE(r->error().empty());
}
