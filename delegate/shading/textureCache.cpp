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

constexpr std::string_view kUdimToken = "<UDIM>";
constexpr int kUdimTiles = 100;  // 1001-1100: UsdPreviewSurface spec 2.5

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

// One OpenImageIO texture system per process, created on first use and never destroyed.
// Destroying one is unsafe here: OIIO 2.4's TextureSystem::destroy() deletes the
// implementation through its non-virtual base (a sized-delete mismatch that ASan reports and
// that corrupts jemalloc's heap inside Blender), and the per-thread micro-caches of reused TBB
// workers would outlive it (a crash when a second textured session renders in the process).
static TextureSystem* processTextureSystem() {
    static TextureSystem* system = TextureSystem::create(false);
    return system;
}

TextureCache::TextureCache(const Options& options) {
    // Options apply process-wide (the last cache created sets them).
    TextureSystem* system = processTextureSystem();
    system->attribute("max_memory_MB", options.maxMemoryMB);
    system->attribute("max_open_files", options.maxOpenFiles);
    system->attribute("automip", options.autoMip ? 1 : 0);
    // Scanline files (PNG, JPEG) are cut into 64x64 tiles so only the touched part is cached.
    system->attribute("autotile", 64);
    // UsdPreviewSurface colours are straight alpha: keep PNG/TIFF colours unpremultiplied.
    system->attribute("unassociatedalpha", 1);
    _system = system;
}

TextureCache::~TextureCache() = default;  // the process-wide system stays alive

TextureOpenResult TextureCache::open(const std::string& path) {
    std::lock_guard<std::mutex> lock(_mutex);
    return path.find(kUdimToken) == std::string::npos ? openFile(path) : openUdim(path);
}

TextureOpenResult TextureCache::openUdim(const std::string& pattern) {
    TextureOpenResult result;
    if (auto it = _textures.find(pattern); it != _textures.end()) {
        result.texture = it->second.get();
        return result;
    }
    if (auto f = _failures.find(pattern); f != _failures.end()) {
        result.error = f->second;
        return result;
    }
    auto set = std::make_unique<Texture>();
    set->udimTiles.assign(kUdimTiles, nullptr);
    const Texture* first = nullptr;
    size_t at = pattern.find(kUdimToken);
    for (int i = 0; i < kUdimTiles; ++i) {
        std::string tile = pattern;
        tile.replace(at, kUdimToken.size(), std::to_string(1001 + i));
        std::error_code ec;
        if (!std::filesystem::exists(tile, ec)) continue;
        TextureOpenResult r = openFile(tile);
        if (r.texture) {
            set->udimTiles[i] = r.texture;
            if (!first) first = r.texture;
        } else if (r.firstReport) {
            result.error += (result.error.empty() ? "" : "; ") + r.error;
        }
    }
    if (!first) {
        std::string e = "texture '" + pattern + "': no UDIM tile 1001-1100 found";
        if (!result.error.empty()) e += " (" + result.error + ")";
        _failures.emplace(pattern, e);
        result.error = e;
        result.firstReport = _reported.insert(pattern).second;
        return result;
    }
    std::vector<const Texture*> tiles = std::move(set->udimTiles);
    *set = *first;
    set->path = pattern;
    set->handle = nullptr;
    set->udimTiles = std::move(tiles);
    result.texture = set.get();
    result.firstReport = !result.error.empty();
    _textures.emplace(pattern, std::move(set));
    return result;
}

TextureOpenResult TextureCache::openFile(const std::string& path) {
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

bool TextureCache::lookup(const Texture& texture, Wrap wrapS, Wrap wrapT, glm::vec2 st,
                          const glm::vec4& footprint, glm::vec4* rgba) const {
    float s = std::isfinite(st.x) ? st.x : 0.0f;
    float t = std::isfinite(st.y) ? st.y : 0.0f;
    glm::vec4 d = footprint;
    for (int i = 0; i < 4; ++i)
        if (!std::isfinite(d[i])) d[i] = 0.0f;
    if (texture.udimTiles.empty()) return lookupFile(texture, wrapS, wrapT, s, t, d, rgba);
    // UDIM: tile 1001 + u + 10 v holds [u, u+1) x [v, v+1), v counted upwards like t.
    float fu = std::floor(s), fv = std::floor(t);
    if (fu < 0.0f || fu >= 10.0f || fv < 0.0f || fv >= 10.0f) return false;
    const Texture* tile = texture.udimTiles[static_cast<int>(fu) + 10 * static_cast<int>(fv)];
    if (!tile) return false;
    return lookupFile(*tile, Wrap::Clamp, Wrap::Clamp, s - fu, t - fv, d, rgba);
}

bool TextureCache::lookupFile(const Texture& texture, Wrap wrapS, Wrap wrapT, float s, float t,
                              const glm::vec4& d, glm::vec4* rgba) const {
    TextureSystem* system = ts(_system);
    TextureOpt opt;
    opt.swrap = toOiio(wrapS);
    opt.twrap = toOiio(wrapT);
    // Bilinear within a level (exact at texel centres), trilinear/anisotropic across levels.
    opt.interpmode = TextureOpt::InterpBilinear;
    opt.fill = 0.0f;
    // st (0,0) is the bottom-left texel in USD; OpenImageIO's t runs from the top row down.
    // Flipping t keeps black/clamp/repeat/mirror wrapping intact (all symmetric about 0 and 1).
    t = 1.0f - t;
    int n = std::min(texture.channels, 4);
    float px[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    if (!system->texture(static_cast<TextureSystem::TextureHandle*>(texture.handle),
                         system->get_perthread_info(), opt, s, t, d.x, -d.y, d.z, -d.w, n, px)) {
        (void)system->geterror();  // the file went bad after open(): no data, never a crash
        return false;
    }
    switch (n) {
        case 1:
            *rgba = {px[0], px[0], px[0], 1.0f};
            break;
        case 2:
            *rgba = {px[0], px[0], px[0], px[1]};
            break;
        case 3:
            *rgba = {px[0], px[1], px[2], 1.0f};
            break;
        default:
            *rgba = {px[0], px[1], px[2], px[3]};
            break;
    }
    return true;
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
