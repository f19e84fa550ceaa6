// SPDX-License-Identifier: Apache-2.0
#include "delegate/shading/textureCache.h"

#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/strutil.h>
#include <OpenImageIO/texture.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

namespace principled::shading {

namespace {

using OIIO::TextureOpt;
using OIIO::TextureSystem;
using OIIO::ustring;

TextureSystem* ts(void* p) {
    return static_cast<TextureSystem*>(p);
}

TextureOpt::Wrap toOiio(Wrap w) {
    switch (w) {
        case Wrap::Black:
            return TextureOpt::WrapBlack;
        case Wrap::Clamp:
            return TextureOpt::WrapClamp;
        case Wrap::Repeat:
            return TextureOpt::WrapPeriodic;
        case Wrap::Mirror:
            return TextureOpt::WrapMirror;
    }
    return TextureOpt::WrapBlack;
}

// OpenImageIO writes "wrapmodes" as "swrap,twrap" with its own names (periodic, clamp, ...).
bool fromOiioName(std::string_view name, Wrap* out) {
    if (name == "black")
        *out = Wrap::Black;
    else if (name == "clamp")
        *out = Wrap::Clamp;
    else if (name == "periodic" || name == "periodic_pow2" || name == "periodic_sharedborder")
        *out = Wrap::Repeat;
    else if (name == "mirror")
        *out = Wrap::Mirror;
    else
        return false;
    return true;
}

// Errors are per thread in OpenImageIO: take and clear the pending message.
std::string takeError(TextureSystem* system) {
    std::string e = system->geterror();
    while (!e.empty() && (e.back() == '\n' || e.back() == ' ')) e.pop_back();
    return e;
}

std::string formatName(TextureSystem* system, TextureSystem::TextureHandle* handle,
                       TextureSystem::Perthread* thread) {
    OIIO::ustring name;
    if (!system->get_texture_info(handle, thread, 0, OIIO::ustring("fileformat"), OIIO::TypeString,
                                  &name))
        (void)takeError(system);
    return name.string();
}

bool contains(const std::string& text, std::string_view word) {
    return OIIO::Strutil::icontains(text, word);
}

ColorTag colorTag(const OIIO::ImageSpec& spec, const std::string& format) {
    std::string icc = std::string(spec.get_string_attribute("ICCProfile:profile_description")) +
                      " " + std::string(spec.get_string_attribute("photoshop:ICCProfile"));
    std::string cs = spec.get_string_attribute("oiio:ColorSpace");
    float gamma = spec.get_float_attribute("oiio:Gamma", 0.0f);
    // 0.1: the tolerance USD's Hio uses when it reads a file's gamma to decide sRGB or linear.
    if (std::abs(gamma - 1.0f) < 0.1f || contains(icc, "linear") ||
        OIIO::Strutil::iequals(cs, "linear") || OIIO::Strutil::iequals(cs, "scene_linear") ||
        OIIO::Strutil::iequals(cs, "lin_srgb"))
        return ColorTag::Linear;
    if (std::abs(gamma - 2.2f) < 0.1f || contains(icc, "sRGB") ||
        spec.get_int_attribute("Exif:ColorSpace", 0) == 1)
        return ColorTag::Srgb;
    // PNG and JPEG readers default the label to sRGB; other formats only report what they read.
    if (OIIO::Strutil::iequals(cs, "sRGB") && format != "png" && format != "jpeg")
        return ColorTag::Srgb;
    return ColorTag::Unknown;
}

}  // namespace

TextureCache::TextureCache() : TextureCache(Options()) {}

TextureCache::TextureCache(const Options& options) {
    // A private system (shared=false): its memory limit and options are ours alone.
    TextureSystem* system = TextureSystem::create(false);
    system->attribute("max_memory_MB", options.maxMemoryMB);
    system->attribute("max_open_files", options.maxOpenFiles);
    system->attribute("automip", options.autoMip ? 1 : 0);
    // Scanline files (PNG, JPEG) are cut into 64x64 tiles so only the touched part is cached.
    system->attribute("autotile", 64);
    // UsdPreviewSurface colours are straight alpha: keep PNG/TIFF colours unpremultiplied.
    system->attribute("unassociatedalpha", 1);
    _system = system;
}

TextureCache::~TextureCache() {
    if (_system) TextureSystem::destroy(ts(_system), true);
}

TextureOpenResult TextureCache::open(const std::string& path) {
    std::lock_guard<std::mutex> lock(_mutex);
    TextureOpenResult result;
    if (auto it = _textures.find(path); it != _textures.end()) {
        result.texture = it->second.get();
        return result;
    }
    auto fail = [&](std::string reason) {
        auto f = _failures.emplace(path, "texture '" + path + "': " + std::move(reason)).first;
        result.error = f->second;
        result.firstReport = _reported.insert(path).second;
        return result;
    };
    if (auto f = _failures.find(path); f != _failures.end()) {
        result.error = f->second;
        return result;
    }
    if (path.empty()) return fail("no file authored");
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) return fail("file not found");

    TextureSystem* system = ts(_system);
    ustring name(path);
    TextureSystem::Perthread* thread = system->get_perthread_info();
    TextureSystem::TextureHandle* handle = system->get_texture_handle(name, thread);
    OIIO::ImageSpec spec;
    if (!handle || !system->get_imagespec(handle, thread, 0, spec)) {
        std::string e = takeError(system);
        return fail(e.empty() ? std::string("cannot be read") : e);
    }
    if (spec.nchannels < 1 || spec.width < 1 || spec.height < 1)
        return fail("image has no pixels or no channels");

    auto tex = std::make_unique<Texture>();
    tex->path = path;
    tex->width = spec.width;
    tex->height = spec.height;
    tex->channels = spec.nchannels;
    tex->bitsPerChannel = static_cast<int>(spec.format.size()) * 8;
    tex->isFloat = spec.format.is_floating_point();
    tex->colorTag = colorTag(spec, formatName(system, handle, thread));
    std::string wrap = spec.get_string_attribute("wrapmodes");
    if (!wrap.empty()) {
        auto comma = wrap.find(',');
        std::string s = wrap.substr(0, comma);
        std::string t = comma == std::string::npos ? s : wrap.substr(comma + 1);
        tex->hasWrapMetadata =
            fromOiioName(s, &tex->metadataWrapS) && fromOiioName(t, &tex->metadataWrapT);
        if (!tex->hasWrapMetadata) tex->metadataWrapS = tex->metadataWrapT = Wrap::Black;
    }
    tex->handle = handle;
    const Texture* out = tex.get();
    _textures.emplace(path, std::move(tex));
    result.texture = out;
    return result;
}

glm::vec4 TextureCache::sample(const Texture& texture, Wrap wrapS, Wrap wrapT, glm::vec2 st,
                               const glm::vec4& footprint) const {
    TextureSystem* system = ts(_system);
    TextureOpt opt;
    opt.swrap = toOiio(wrapS);
    opt.twrap = toOiio(wrapT);
    // Bilinear within a level (exact at texel centres), trilinear/anisotropic across levels.
    opt.interpmode = TextureOpt::InterpBilinear;
    opt.fill = 0.0f;
    float s = std::isfinite(st.x) ? st.x : 0.0f;
    float t = std::isfinite(st.y) ? st.y : 0.0f;
    glm::vec4 d = footprint;
    for (int i = 0; i < 4; ++i)
        if (!std::isfinite(d[i])) d[i] = 0.0f;
    // st (0,0) is the bottom-left texel in USD; OpenImageIO's t runs from the top row down.
    // Flipping t keeps black/clamp/repeat/mirror wrapping intact (all symmetric about 0 and 1).
    t = 1.0f - t;
    int n = std::min(texture.channels, 4);
    float px[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    bool ok = system->texture(static_cast<TextureSystem::TextureHandle*>(texture.handle),
                              system->get_perthread_info(), opt, s, t, d.x, -d.y, d.z, -d.w, n, px);
    if (!ok) {
        (void)system->geterror();  // the file went bad after open(): black, never a crash
        return glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    }
    switch (n) {
        case 1:
            return {px[0], px[0], px[0], 1.0f};
        case 2:
            return {px[0], px[0], px[0], px[1]};
        case 3:
            return {px[0], px[1], px[2], 1.0f};
        default:
            return {px[0], px[1], px[2], px[3]};
    }
}

void TextureCache::invalidate() {
    std::lock_guard<std::mutex> lock(_mutex);
    _failures.clear();
    _reported.clear();
    ts(_system)->invalidate_all(true);
}

size_t TextureCache::memoryUsed() const {
    // ImageCache "stat:cache_memory_used" (int64) is the tile memory currently resident.
    long long used = 0;
    ts(_system)->getattribute("stat:cache_memory_used", OIIO::TypeDesc::INT64, &used);
    return static_cast<size_t>(std::max(0LL, used));
}

}  // namespace principled::shading
