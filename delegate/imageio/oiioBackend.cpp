// SPDX-License-Identifier: Apache-2.0
// libprincipled_oiio.so: the image I/O backend over OpenImageIO (see imageIO.h). The only
// module of the project that links OpenImageIO; loaded with dlopen on first use.
#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/imageio.h>
#include <OpenImageIO/texture.h>

#include "delegate/imageio/imageIO.h"

namespace principled::imageio {

namespace {

OIIO::TypeDesc toOiio(PixelType t) {
    switch (t) {
        case PixelType::UInt8:
            return OIIO::TypeDesc::UINT8;
        case PixelType::UInt16:
            return OIIO::TypeDesc::UINT16;
        case PixelType::UInt32:
            return OIIO::TypeDesc::UINT32;
        case PixelType::Half:
            return OIIO::TypeDesc::HALF;
        case PixelType::Float:
        case PixelType::Other:
            break;
    }
    return OIIO::TypeDesc::FLOAT;
}

PixelType fromOiio(OIIO::TypeDesc t) {
    switch (t.basetype) {
        case OIIO::TypeDesc::UINT8:
            return PixelType::UInt8;
        case OIIO::TypeDesc::UINT16:
            return PixelType::UInt16;
        case OIIO::TypeDesc::UINT32:
            return PixelType::UInt32;
        case OIIO::TypeDesc::HALF:
            return PixelType::Half;
        case OIIO::TypeDesc::FLOAT:
            return PixelType::Float;
        default:
            return PixelType::Other;
    }
}

ImageSpec fromOiio(const OIIO::ImageSpec& s) {
    ImageSpec out;
    out.width = s.width;
    out.height = s.height;
    out.channels = s.nchannels;
    out.format = fromOiio(s.format);
    out.bitsPerChannel = static_cast<int>(s.format.size()) * 8;
    out.channelNames = s.channelnames;
    out.alphaChannel = s.alpha_channel;
    for (const auto& p : s.extra_attribs) {
        const OIIO::TypeDesc& t = p.type();
        if (t == OIIO::TypeString) {
            out.strings[p.name().string()] = p.get_string();
        } else if (t.aggregate == OIIO::TypeDesc::SCALAR && t.arraylen == 0) {
            if (t.is_floating_point())
                out.numbers[p.name().string()] = p.get_float();
            else if (t.basetype >= OIIO::TypeDesc::UINT8 && t.basetype <= OIIO::TypeDesc::INT64)
                out.numbers[p.name().string()] = p.get_int();
        }
    }
    return out;
}

std::string trimmed(std::string e) {
    while (!e.empty() && (e.back() == '\n' || e.back() == ' ')) e.pop_back();
    return e;
}

class OiioReader final : public ImageReader {
  public:
    explicit OiioReader(std::unique_ptr<OIIO::ImageInput> in)
        : _in(std::move(in)), _spec(fromOiio(_in->spec())) {
        _spec.fileFormat = _in->format_name();
    }
    const ImageSpec& spec() const override { return _spec; }
    bool read(PixelType as, int channels, void* pixels) override {
        return _in->read_image(0, 0, 0, std::clamp(channels, 1, _spec.channels), toOiio(as),
                               pixels);
    }
    std::string error() override { return trimmed(_in->geterror()); }

  private:
    std::unique_ptr<OIIO::ImageInput> _in;
    ImageSpec _spec;
};

OIIO::TextureOpt::Wrap wrap(int w) {
    switch (w) {
        case 1:
            return OIIO::TextureOpt::WrapClamp;
        case 2:
            return OIIO::TextureOpt::WrapPeriodic;
        case 3:
            return OIIO::TextureOpt::WrapMirror;
        default:
            return OIIO::TextureOpt::WrapBlack;
    }
}

// One OpenImageIO texture system per process, created on first use and never destroyed.
// Destroying one is unsafe here: OIIO 2.4's TextureSystem::destroy() deletes the
// implementation through its non-virtual base (a sized-delete mismatch that ASan reports and
// that corrupts jemalloc's heap inside Blender), and the per-thread micro-caches of reused TBB
// workers would outlive it (a crash when a second textured session renders in the process).
class OiioTextureSystem final : public TextureSystem {
  public:
    OiioTextureSystem() : _ts(OIIO::TextureSystem::create(false)) {
        // Scanline files (PNG, JPEG) are cut into 64x64 tiles so only the touched part is cached.
        _ts->attribute("autotile", 64);
        // UsdPreviewSurface colours are straight alpha: keep PNG/TIFF colours unpremultiplied.
        _ts->attribute("unassociatedalpha", 1);
    }
    void configure(float maxMemoryMB, int maxOpenFiles, bool autoMip) override {
        _ts->attribute("max_memory_MB", maxMemoryMB);
        _ts->attribute("max_open_files", maxOpenFiles);
        _ts->attribute("automip", autoMip ? 1 : 0);
    }
    void* open(const std::string& path, ImageSpec* spec, std::string* error) override {
        OIIO::TextureSystem::Perthread* thread = _ts->get_perthread_info();
        OIIO::TextureSystem::TextureHandle* handle =
            _ts->get_texture_handle(OIIO::ustring(path), thread);
        OIIO::ImageSpec s;
        if (!handle || !_ts->get_imagespec(handle, thread, 0, s)) {
            *error = trimmed(_ts->geterror());  // errors are per thread: take and clear
            return nullptr;
        }
        *spec = fromOiio(s);
        OIIO::ustring name;
        if (_ts->get_texture_info(handle, thread, 0, OIIO::ustring("fileformat"), OIIO::TypeString,
                                  &name))
            spec->fileFormat = name.string();
        else
            (void)_ts->geterror();
        return handle;
    }
    bool lookup(void* handle, int wrapS, int wrapT, float s, float t, float dsdx, float dtdx,
                float dsdy, float dtdy, int channels, float* out) override {
        OIIO::TextureOpt opt;
        opt.swrap = wrap(wrapS);
        opt.twrap = wrap(wrapT);
        // Bilinear within a level (exact at texel centres), trilinear/anisotropic across levels.
        opt.interpmode = OIIO::TextureOpt::InterpBilinear;
        opt.fill = 0.0f;
        if (!_ts->texture(static_cast<OIIO::TextureSystem::TextureHandle*>(handle),
                          _ts->get_perthread_info(), opt, s, t, dsdx, dtdx, dsdy, dtdy, channels,
                          out)) {
            (void)_ts->geterror();  // the file went bad after open(): no data, never a crash
            return false;
        }
        return true;
    }
    void invalidateAll() override { _ts->invalidate_all(true); }
    void invalidate(const std::string& path, bool force) override { _ts->invalidate(OIIO::ustring(path), force); }
    size_t memoryUsed() override {
        // ImageCache "stat:cache_memory_used" (int64) is the tile memory currently resident.
        long long used = 0;
        _ts->getattribute("stat:cache_memory_used", OIIO::TypeDesc::INT64, &used);
        return static_cast<size_t>(std::max(0LL, used));
    }

  private:
    OIIO::TextureSystem* _ts;
};

class OiioBackend final : public Backend {
  public:
    OiioBackend() : _description("OpenImageIO " + std::string(OIIO_VERSION_STRING)) {}

    std::unique_ptr<ImageReader> open(const std::string& path, std::string* error) override {
        auto in = OIIO::ImageInput::open(path);
        if (!in) {
            *error = trimmed(OIIO::geterror());
            return nullptr;
        }
        return std::make_unique<OiioReader>(std::move(in));
    }

    std::unique_ptr<ImageReader> openTexture(const std::string& path,
                                             std::string* error) override {
        // The texture system's "unassociatedalpha" (OiioTextureSystem) for a single file.
        OIIO::ImageSpec config;
        config.attribute("oiio:UnassociatedAlpha", 1);
        auto in = OIIO::ImageInput::open(path, &config);
        if (!in) {
            *error = trimmed(OIIO::geterror());
            return nullptr;
        }
        return std::make_unique<OiioReader>(std::move(in));
    }

    bool write(const std::string& path, const std::string& formatFrom, const ImageSpec& spec,
               const void* pixels, std::string* error) override {
        OIIO::ImageSpec s(spec.width, spec.height, spec.channels, toOiio(spec.format));
        if (!spec.channelNames.empty()) s.channelnames = spec.channelNames;
        s.alpha_channel = spec.alphaChannel;
        for (const auto& [k, v] : spec.strings) s.attribute(k, v);
        for (const auto& [k, v] : spec.numbers) {
            if (v == std::floor(v) && std::abs(v) < 2147483647.0)
                s.attribute(k, static_cast<int>(v));
            else
                s.attribute(k, static_cast<float>(v));
        }
        auto out = OIIO::ImageOutput::create(formatFrom.empty() ? path : formatFrom);
        if (!out) {
            *error = trimmed(OIIO::geterror());
            return false;
        }
        if (!out->open(path, s) || !out->write_image(s.format, pixels) || !out->close()) {
            *error = trimmed(out->geterror());
            return false;
        }
        return true;
    }

    TextureSystem& textureSystem() override {
        static OiioTextureSystem* system = new OiioTextureSystem();  // never destroyed
        return *system;
    }

    const char* description() const override { return _description.c_str(); }

  private:
    std::string _description;
};

}  // namespace

}  // namespace principled::imageio

extern "C" __attribute__((visibility("default"))) int principled_imageio_abi_version() {
    return principled::imageio::kAbiVersion;
}

extern "C" __attribute__((visibility("default"))) principled::imageio::Backend*
principled_imageio_backend() {
    static auto* backend = new principled::imageio::OiioBackend();  // never destroyed
    return backend;
}
