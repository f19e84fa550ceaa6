// SPDX-License-Identifier: Apache-2.0
#include "delegate/shading/textureCache.h"

#include "delegate/imageio/imageIO.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <sys/stat.h>
#include <new>

namespace principled::shading {

namespace {

constexpr std::string_view kUdimToken = "<UDIM>";
constexpr int kUdimTiles = 100;  // 1001-1100: UsdPreviewSurface spec 2.5

imageio::TextureSystem* ts(void* p) {
    return static_cast<imageio::TextureSystem*>(p);
}

// The backend's wrap codes: 0 black, 1 clamp, 2 periodic, 3 mirror.
int toBackend(Wrap w) {
    switch (w) {
        case Wrap::Black:
            return 0;
        case Wrap::Clamp:
            return 1;
        case Wrap::Repeat:
            return 2;
        case Wrap::Mirror:
            return 3;
    }
    return 0;
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

std::string lower(std::string_view s) {
    std::string out(s);
    for (auto& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
}

bool contains(const std::string& text, std::string_view word) {
    return lower(text).find(lower(word)) != std::string::npos;
}

bool iequals(const std::string& a, std::string_view b) {
    return lower(a) == lower(b);
}

ColorTag colorTag(const imageio::ImageSpec& spec, const std::string& format) {
    std::string icc = spec.string("ICCProfile:profile_description") + " " +
                      spec.string("photoshop:ICCProfile");
    std::string cs = spec.string("oiio:ColorSpace");
    float gamma = static_cast<float>(spec.number("oiio:Gamma", 0.0));
    // 0.1: the tolerance USD's Hio uses when it reads a file's gamma to decide sRGB or linear.
    if (std::abs(gamma - 1.0f) < 0.1f || contains(icc, "linear") || iequals(cs, "linear") ||
        iequals(cs, "scene_linear") || iequals(cs, "lin_srgb"))
        return ColorTag::Linear;
    if (std::abs(gamma - 2.2f) < 0.1f || contains(icc, "sRGB") ||
        static_cast<int>(spec.number("Exif:ColorSpace", 0.0)) == 1)
        return ColorTag::Srgb;
    // PNG and JPEG readers default the label to sRGB; other formats only report what they read.
    if (iequals(cs, "sRGB") && format != "png" && format != "jpeg") return ColorTag::Srgb;
    return ColorTag::Unknown;
}

// The options of the most recently created cache: they apply process-wide (one texture system
// per process, in the backend), set when the backend is loaded or at once if it already is.
std::mutex gOptionsMutex;
TextureCache::Options gOptions;

}  // namespace

TextureCache::TextureCache() : TextureCache(Options()) {}

// The texture system is OpenImageIO's, one per process, created by the image I/O backend on
// first use and never destroyed (see delegate/imageio/oiioBackend.cpp). The backend is loaded
// by the first open(), so a scene without textures never loads it.
TextureCache::TextureCache(const Options& options) : _options(options) {
    std::lock_guard lock(gOptionsMutex);
    gOptions = options;
    if (imageio::Backend* io = imageio::loadedBackend())
        io->textureSystem().configure(options.maxMemoryMB, options.maxOpenFiles, options.autoMip);
}

TextureCache::~TextureCache() = default;  // the process-wide system stays alive

bool TextureCache::ensureSystem(std::string* error) {
    if (_system.load(std::memory_order_acquire)) return true;
    imageio::Backend* io = imageio::backend(error);
    if (!io) return false;
    imageio::TextureSystem& system = io->textureSystem();
    {
        std::lock_guard lock(gOptionsMutex);
        system.configure(gOptions.maxMemoryMB, gOptions.maxOpenFiles, gOptions.autoMip);
    }
    _system.store(&system, std::memory_order_release);
    return true;
}

TextureOpenResult TextureCache::open(const std::string& path) {
    return path.find(kUdimToken) == std::string::npos ? openFile(path) : openUdim(path);
}

TextureOpenResult TextureCache::openUdim(const std::string& pattern) {
    TextureOpenResult result;
    {
        std::lock_guard lock(_mutex);
        if (auto it = _textures.find(pattern); it != _textures.end()) {
            result.texture = it->second.get();
            return result;
        }
        if (auto f = _failures.find(pattern); f != _failures.end()) {
            result.error = f->second;
            return result;
        }
    }
    // The tiles are opened (and read) one by one without the lock; openFile() reads each file
    // once even when another thread opens the same set at the same time.
    std::vector<const Texture*> tiles(kUdimTiles, nullptr);
    const Texture* first = nullptr;
    size_t at = pattern.find(kUdimToken);
    for (int i = 0; i < kUdimTiles; ++i) {
        std::string tile = pattern;
        tile.replace(at, kUdimToken.size(), std::to_string(1001 + i));
        std::error_code ec;
        if (!std::filesystem::exists(tile, ec)) {
            remember(tile);  // stamped as missing: reloadChanged() sees it appear
            continue;
        }
        TextureOpenResult r = openFile(tile);
        if (r.texture) {
            tiles[i] = r.texture;
            if (!first) first = r.texture;
        } else if (r.firstReport) {
            result.error += (result.error.empty() ? "" : "; ") + r.error;
        }
    }
    std::lock_guard lock(_mutex);
    if (auto it = _textures.find(pattern); it != _textures.end()) {
        // Another thread opened the same set meanwhile (its tiles are the same Textures).
        result.texture = it->second.get();
        result.firstReport = !result.error.empty();
        return result;
    }
    if (!first) {
        std::string e = "texture '" + pattern + "': no UDIM tile 1001-1100 found";
        if (!result.error.empty()) e += " (" + result.error + ")";
        _failures.emplace(pattern, e);
        result.error = e;
        result.firstReport = _reported.insert(pattern).second;
        return result;
    }
    // The set is described by its first tile; it has no pixels or handle of its own.
    auto set = std::make_unique<Texture>();
    set->path = pattern;
    set->udimTiles = std::move(tiles);
    set->udimFirst = first;
    result.texture = set.get();
    result.firstReport = !result.error.empty();
    _textures.emplace(pattern, std::move(set));
    return result;
}

// A file read without the cache's lock: its description and, within the budget, its pixels
// (whose bytes are already counted in _residentBytes).
struct TextureCache::Reading {
    bool ok = false;
    std::string error;  ///< the reason when !ok
    std::string note;   ///< for the log: why the pixels are not resident
    TextureInfo info;
    std::unique_ptr<ResidentImage> pixels;
};

TextureCache::Reading TextureCache::read(const std::string& path) {
    Reading r;
    try {
        std::error_code ec;
        if (!std::filesystem::is_regular_file(path, ec)) {
            r.error = "file not found";
            return r;
        }
        // The file is opened as the texture system would open it (straight alpha; PNG decoded
        // natively to the same pixels and metadata, without loading the backend) and its finest
        // level read into memory; the texture system is used only when a lookup needs it
        // (handleFor).
        std::string e;
        std::unique_ptr<imageio::ImageReader> reader =
            imageio::openTexture(path, &e, _options.nativePng);
        if (!reader) {
            r.error = e.empty() ? std::string("cannot be read") : e;
            return r;
        }
        const imageio::ImageSpec& spec = reader->spec();
        if (spec.channels < 1 || spec.width < 1 || spec.height < 1) {
            r.error = "image has no pixels or no channels";
            return r;
        }
        // A header can claim any size: more than 2^31 pixels, or more than 10,000 bytes of pixels
        // per byte of file (beyond deflate's ~1000:1 on a constant image), is refused before a
        // lookup makes the texture system allocate it (a 67-byte PNG claiming 1e6 x 1e6 ran out
        // of memory).
        const double pixels = double(spec.width) * double(spec.height);
        const double rawBytes = pixels * spec.channels * std::max(1, spec.bitsPerChannel / 8);
        const double fileBytes = double(std::filesystem::file_size(path, ec));
        if (pixels > 2147483648.0 || (!ec && rawBytes > 1e4 * fileBytes + 268435456.0)) {
            r.error = "image header claims " + std::to_string(spec.width) + " x " + std::to_string(spec.height) +
                      " pixels, implausible for a file of " + std::to_string(size_t(fileBytes)) + " bytes";
            return r;
        }
        TextureInfo& info = r.info;
        info.width = spec.width;
        info.height = spec.height;
        info.channels = spec.channels;
        info.bitsPerChannel = spec.bitsPerChannel;
        info.isFloat =
            spec.format == imageio::PixelType::Float || spec.format == imageio::PixelType::Half;
        info.colorTag = colorTag(spec, spec.fileFormat);
        std::string wrap = spec.string("wrapmodes");
        if (!wrap.empty()) {
            auto comma = wrap.find(',');
            std::string s = wrap.substr(0, comma);
            std::string t = comma == std::string::npos ? s : wrap.substr(comma + 1);
            info.hasWrapMetadata =
                fromOiioName(s, &info.metadataWrapS) && fromOiioName(t, &info.metadataWrapT);
            if (!info.hasWrapMetadata) info.metadataWrapS = info.metadataWrapT = Wrap::Black;
        }
        r.ok = true;
        r.note = makeResident(r, *reader);
    } catch (const std::exception& x) {
        // Never leave a Texture `loading` for good: the waiting threads get this error.
        if (r.pixels) _residentBytes.fetch_sub(r.pixels->bytes(), std::memory_order_relaxed);
        r = Reading();
        r.error = std::string("cannot be read (") + x.what() + ")";
    }
    return r;
}

TextureOpenResult TextureCache::openFile(const std::string& path) {
    TextureOpenResult result;
    remember(path);
    std::unique_lock lock(_mutex);
    for (;;) {
        auto it = _textures.find(path);
        if (it == _textures.end()) break;
        Texture& tex = *it->second;
        if (tex.loading) {  // first read by another thread: wait for it, then look again
            _loaded.wait(lock);
            continue;
        }
        if (tex.current.load(std::memory_order_relaxed)->stale) reread(tex, lock);
        result.texture = &tex;
        return result;
    }
    auto fail = [&](const std::string& reason, bool remember) {
        std::string e = "texture '" + path + "': " + reason;
        if (remember) _failures.emplace(path, e);
        result.error = std::move(e);
        result.firstReport = _reported.insert(path).second;
        return result;
    };
    if (auto f = _failures.find(path); f != _failures.end()) {
        result.error = f->second;
        return result;
    }
    if (path.empty()) return fail("no file authored", true);

    // Claim the path (others opening it wait on `loading`), read without the lock, publish.
    Texture* tex = _textures.emplace(path, std::make_unique<Texture>()).first->second.get();
    tex->path = path;
    tex->loading = true;
    const uint64_t generation = _generation;
    lock.unlock();
    Reading r = read(path);
    lock.lock();
    tex->loading = false;
    _loaded.notify_all();
    if (!r.ok) {
        _textures.erase(path);  // no one holds it: it is handed out only once published
        // A failure seen before an invalidate() that ran meanwhile is not remembered.
        return fail(r.error, generation == _generation);
    }
    auto version = std::make_unique<TextureVersion>();
    version->info = r.info;
    if (generation != _generation) {
        // invalidate() ran while the file was read: the pixels may predate an edit.
        version->stale = true;
        if (r.pixels) _residentBytes.fetch_sub(r.pixels->bytes(), std::memory_order_relaxed);
    } else {
        version->pixels = std::move(r.pixels);
    }
    publish(*tex, std::move(version));
    if (!r.note.empty())
        std::fprintf(stderr, "principled: texture '%s': %s\n", path.c_str(), r.note.c_str());
    result.texture = tex;
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
    // Bilinear within a level (exact at texel centres), trilinear/anisotropic across levels
    // (the backend's options), black fill.
    // st (0,0) is the bottom-left texel in USD; OpenImageIO's t runs from the top row down.
    // Flipping t keeps black/clamp/repeat/mirror wrapping intact (all symmetric about 0 and 1).
    t = 1.0f - t;
    // One acquire load: the description and pixels below are of the same reading of the file.
    const TextureVersion& version = currentVersion(texture);
    int n = std::min(version.info.channels, 4);
    float px[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    const bool point = d.x == 0.0f && d.y == 0.0f && d.z == 0.0f && d.w == 0.0f;
    if (const ResidentImage* image = point ? version.pixels.get() : nullptr) {
        // The same bilinear on the finest level that OpenImageIO gives a zero footprint.
        image->lookup(wrapS, wrapT, s, t, px);
        n = image->channels();
    } else {
        void* handle = handleFor(texture);
        // False when the file went bad after open(): no data, never a crash.
        if (!handle || !ts(_system.load(std::memory_order_acquire))
                            ->lookup(handle, toBackend(wrapS), toBackend(wrapT), s, t, d.x, -d.y,
                                     d.z, -d.w, n, px))
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

std::string TextureCache::makeResident(Reading& reading, imageio::ImageReader& reader) {
    const size_t bytes = ResidentImage::bytesFor(reader.spec());
    const double budget = std::max(0.0, _options.maxResidentMB) * 1048576.0;
    // Reserve the bytes before decoding, so files decoded at the same time stay within budget.
    size_t used = _residentBytes.load(std::memory_order_relaxed);
    do {
        if (double(used) + double(bytes) > budget) {
            if (budget == 0.0) return {};  // resident pixels switched off: nothing to note
            char note[160];
            std::snprintf(note, sizeof note,
                          "%.1f MB would exceed the resident budget (%.1f of %.1f MB used); "
                          "read through OpenImageIO's tile cache",
                          double(bytes) / 1048576.0, double(used) / 1048576.0,
                          budget / 1048576.0);
            return note;
        }
    } while (!_residentBytes.compare_exchange_weak(used, used + bytes, std::memory_order_relaxed));
    std::string e;
    std::unique_ptr<ResidentImage> image;
    try {
        image = ResidentImage::read(reader, &e);
    } catch (const std::bad_alloc&) {
        // Out of memory for the whole image: the tile cache still serves it, in bounded memory.
        e = "out of memory for " + std::to_string(bytes / 1048576) + " MB";
    } catch (...) {
        _residentBytes.fetch_sub(bytes, std::memory_order_relaxed);
        throw;
    }
    if (!image) {
        _residentBytes.fetch_sub(bytes, std::memory_order_relaxed);
        return "pixels not held in memory (" + e + "); read through OpenImageIO";
    }
    // bytesFor() and bytes() count the same; keep the reservation equal to what is held.
    if (image->bytes() != bytes) {
        _residentBytes.fetch_add(image->bytes(), std::memory_order_relaxed);
        _residentBytes.fetch_sub(bytes, std::memory_order_relaxed);
    }
    reading.pixels = std::move(image);
    return {};
}

void TextureCache::publish(Texture& texture, std::unique_ptr<TextureVersion> version) {
    const TextureVersion* now = version.get();
    if (texture.owned) {
        if (texture.owned->pixels) {
            const size_t bytes = texture.owned->pixels->bytes();
            _residentBytes.fetch_sub(bytes, std::memory_order_relaxed);
            _retiredBytes.fetch_add(bytes, std::memory_order_relaxed);
        }
        // Lock-free readers may still hold it: freed by collectRetired() or the destructor.
        _retired.push_back(std::move(texture.owned));
    }
    texture.owned = std::move(version);
    texture.current.store(now, std::memory_order_release);
}

const TextureVersion* TextureCache::reread(Texture& texture, std::unique_lock<std::mutex>& lock) {
    texture.loading = true;
    const uint64_t generation = _generation;
    lock.unlock();
    Reading r = read(texture.path);
    lock.lock();
    texture.loading = false;
    _loaded.notify_all();
    auto version = std::make_unique<TextureVersion>();
    // A file that is gone or unreadable now keeps its last description and stays non-resident:
    // the texture system reports it as it did before resident pixels (its lookups fail and the
    // material uses its fallback).
    version->info = r.ok ? r.info : texture.owned->info;
    version->pixels = std::move(r.pixels);
    const TextureVersion* read = version.get();
    if (generation == _generation) {
        publish(texture, std::move(version));
    } else {
        // invalidate() ran while the file was read, perhaps after an edit: the texture stays
        // stale (the next access reads again), but this reading is as recent as the call that
        // asked for it, so it serves that call from the retired list.
        auto stale = std::make_unique<TextureVersion>();
        stale->info = version->info;
        stale->stale = true;
        if (version->pixels) {
            const size_t bytes = version->pixels->bytes();
            _residentBytes.fetch_sub(bytes, std::memory_order_relaxed);
            _retiredBytes.fetch_add(bytes, std::memory_order_relaxed);
        }
        _retired.push_back(std::move(version));
        publish(texture, std::move(stale));
    }
    if (!r.note.empty())
        std::fprintf(stderr, "principled: texture '%s': %s\n", texture.path.c_str(),
                     r.note.c_str());
    return read;
}

const TextureVersion& TextureCache::refreshed(const Texture& texture) const {
    std::unique_lock lock(_mutex);
    // The cache owns every Texture it hands out; only its lazily filled parts change here.
    auto& tex = const_cast<Texture&>(texture);
    while (tex.loading) _loaded.wait(lock);  // another thread is re-reading it
    const TextureVersion* v = tex.current.load(std::memory_order_relaxed);
    if (v->stale) v = const_cast<TextureCache*>(this)->reread(tex, lock);
    return *v;
}

void* TextureCache::handleFor(const Texture& texture) const {
    if (void* h = texture.handle.load(std::memory_order_acquire)) return h;
    if (texture.handleFailed.load(std::memory_order_acquire) || !texture.udimTiles.empty())
        return nullptr;
    std::lock_guard lock(_mutex);
    if (void* h = texture.handle.load(std::memory_order_acquire)) return h;
    if (texture.handleFailed.load(std::memory_order_relaxed)) return nullptr;
    auto* self = const_cast<TextureCache*>(this);  // lazily filled state, under the lock
    auto& tex = const_cast<Texture&>(texture);
    std::string e;
    imageio::ImageSpec spec;
    // The texture system is process-wide: another cache (an earlier render delegate) may have
    // left tiles of this file from before an edit. OpenImageIO's own newer-than check counts
    // whole seconds, so this cache's first handle of a file drops them unconditionally.
    void* h = nullptr;
    if (self->ensureSystem(&e)) {
        ts(_system.load())->invalidate(texture.path, true);
        h = ts(_system.load())->open(texture.path, &spec, &e);
    }
    if (!h) {
        tex.handleFailed.store(true, std::memory_order_release);
        // Once per file (this path runs once: handleFailed is set above).
        std::fprintf(stderr, "principled: texture '%s': OpenImageIO's texture system cannot open it%s%s; "
                             "its filtered lookups give the fallback\n",
                     texture.path.c_str(), e.empty() ? "" : ": ", e.c_str());
        return nullptr;
    }
    tex.handle.store(h, std::memory_order_release);
    return h;
}

void TextureCache::invalidate() { invalidatePaths(nullptr); }

void TextureCache::invalidatePaths(const std::set<std::string>* changed) {
    auto hit = [&](const std::string& path) { return !changed || changed->count(path) > 0; };
    std::vector<std::string> systemPaths;  // files whose texture-system tiles go too
    {
        std::lock_guard<std::mutex> lock(_mutex);
        ++_generation;  // reads in progress publish stale versions
        // A failure may be a file that exists now (or a UDIM set that has a tile now).
        _failures.clear();
        _reported.clear();
        for (auto it = _textures.begin(); it != _textures.end();) {
            Texture& texture = *it->second;
            if (!texture.udimTiles.empty()) {
                // A set whose tiles changed (one may have appeared) is built again by the next
                // open() of its pattern; lookups still holding the old one keep it (retired with
                // the cache, a few hundred bytes each).
                bool touched = !changed;
                for (int i = 0; i < kUdimTiles && !touched; ++i) touched = hit(udimTilePath(it->first, i));
                if (touched) {
                    _retiredSets.push_back(std::move(it->second));
                    it = _textures.erase(it);
                    continue;
                }
                ++it;
                continue;
            }
            if (hit(it->first)) {
                texture.handleFailed.store(false, std::memory_order_release);
                systemPaths.push_back(it->first);
                const TextureVersion* old = texture.owned.get();
                if (old && !old->stale) {  // not being read for the first time, not already stale
                    // Same description, no pixels: lookups that load it re-read the file.
                    auto stale = std::make_unique<TextureVersion>();
                    stale->info = old->info;
                    stale->stale = true;
                    publish(texture, std::move(stale));
                }
            }
            ++it;
        }
    }
    // Process-wide, like the texture system; nothing to drop before the backend is loaded.
    if (imageio::Backend* io = imageio::loadedBackend()) {
        if (!changed)
            io->textureSystem().invalidateAll();
        else
            for (const std::string& path : *changed) io->textureSystem().invalidate(path, true);
    }
}

std::string TextureCache::udimTilePath(const std::string& pattern, int index) {
    std::string tile = pattern;
    const size_t at = tile.find(kUdimToken);
    if (at != std::string::npos) tile.replace(at, kUdimToken.size(), std::to_string(1001 + index));
    return tile;
}

TextureCache::FileStamp TextureCache::stampOf(const std::string& path) {
    // One stat: modification and change times to the nanosecond, inode and size (a file
    // replaced by a rename, or rewritten, moves at least one of them).
    FileStamp s;
    struct stat st {};
    // Not a regular file (a directory, whose times move with its entries): stamped like a
    // missing one, so only becoming a file counts as a change.
    if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return s;
    s.exists = true;
    s.modified = int64_t(st.st_mtim.tv_sec) * 1000000000 + st.st_mtim.tv_nsec;
    s.changed = int64_t(st.st_ctim.tv_sec) * 1000000000 + st.st_ctim.tv_nsec;
    s.inode = uint64_t(st.st_ino);
    s.size = uintmax_t(st.st_size);
    return s;
}

void TextureCache::remember(const std::string& path) {
    {
        std::lock_guard lock(_mutex);
        if (_stamps.count(path)) return;
    }
    const FileStamp stamp = stampOf(path);  // the file system is asked without the lock
    std::lock_guard lock(_mutex);
    _stamps.emplace(path, stamp);  // (another thread may have stamped it meanwhile: kept)
}

void TextureCache::watch(const std::string& path) {
    // The watcher (a light) is about to read the file: its stamp is the file as it is now.
    const FileStamp stamp = stampOf(path);
    std::lock_guard lock(_mutex);
    // A file this cache also serves keeps its first stamp (its pixels may be older than now).
    if (_textures.count(path) && _stamps.count(path)) return;
    _stamps[path] = stamp;
}

std::vector<std::string> TextureCache::reloadChanged() {
    std::vector<std::pair<std::string, FileStamp>> known;
    {
        std::lock_guard lock(_mutex);
        known.assign(_stamps.begin(), _stamps.end());
    }
    // The file system is asked without the lock (lookups go on meanwhile).
    std::vector<std::pair<std::string, FileStamp>> now;
    for (const auto& [path, stamp] : known)
        if (FileStamp current = stampOf(path); !(current == stamp)) now.emplace_back(path, current);
    std::vector<std::string> changed;
    if (now.empty()) return changed;
    std::set<std::string> paths;
    {
        std::lock_guard lock(_mutex);
        for (auto& [path, stamp] : now) {
            _stamps[path] = stamp;
            ++_fileVersions[path];
            paths.insert(path);
        }
    }
    invalidatePaths(&paths);
    changed.assign(paths.begin(), paths.end());
    return changed;
}

bool TextureCache::reloadAll() {
    std::vector<std::string> known;
    {
        std::lock_guard lock(_mutex);
        if (_stamps.empty() && _textures.empty()) return false;  // nothing was ever read
        for (const auto& [path, stamp] : _stamps) known.push_back(path);
    }
    std::vector<std::pair<std::string, FileStamp>> now;
    for (const auto& path : known) now.emplace_back(path, stampOf(path));
    {
        std::lock_guard lock(_mutex);
        for (auto& [path, stamp] : now) _stamps[path] = stamp;  // what is read next is what is on disk now
        ++_reloadAlls;
    }
    invalidate();
    return true;
}

uint64_t TextureCache::fileVersion(const std::string& path) const {
    std::lock_guard lock(_mutex);
    const auto it = _fileVersions.find(path);
    // Both counts only grow, so their sum changes whenever either does.
    return _reloadAlls + (it == _fileVersions.end() ? 0 : it->second);
}

size_t TextureCache::collectRetired() {
    std::vector<std::unique_ptr<TextureVersion>> retired;
    {
        std::lock_guard lock(_mutex);
        retired.swap(_retired);
    }
    size_t freed = 0;
    for (const auto& v : retired)
        if (v->pixels) freed += v->pixels->bytes();
    _retiredBytes.fetch_sub(freed, std::memory_order_relaxed);
    return freed;  // `retired` frees them here, outside the lock
}

size_t TextureCache::memoryUsed() const {
    imageio::Backend* io = imageio::loadedBackend();
    return residentBytes() + retiredBytes() + (io ? io->textureSystem().memoryUsed() : 0);
}

}  // namespace principled::shading
