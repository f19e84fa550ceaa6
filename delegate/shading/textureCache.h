// SPDX-License-Identifier: Apache-2.0
// TextureCache: texture files resolved once. Point lookups (the renderer's: a hit has no
// derivatives) read the finest level held in memory (ResidentImage) with OpenImageIO's bilinear
// conventions; filtered lookups, and files beyond the resident budget, go through OpenImageIO's
// mip-mapped TextureSystem, which has its own memory limit. OpenImageIO is reached through the
// image I/O backend (delegate/imageio/imageIO.h), loaded by the first open().
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <glm/glm.hpp>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "delegate/shading/residentImage.h"
#include "delegate/shading/textureWrap.h"

namespace principled::shading {

/// What a file's metadata states about its encoding (see TextureCache::open for the rules).
enum class ColorTag : uint8_t { Unknown, Srgb, Linear };

/// What a file states about itself, as read by open() and refreshed when the file is re-read
/// after TextureCache::invalidate().
struct TextureInfo {
    int width = 0;
    int height = 0;
    int channels = 0;        ///< channels in the file (lookups read at most 4)
    int bitsPerChannel = 0;  ///< 8, 16, 32 (float) ...
    bool isFloat = false;
    ColorTag colorTag = ColorTag::Unknown;  ///< explicit colour-space metadata, if any
    bool hasWrapMetadata = false;           ///< the file carries "wrapmodes"
    Wrap metadataWrapS = Wrap::Black;
    Wrap metadataWrapT = Wrap::Black;
};

/// One reading of a file: its description and, when held in memory, its finest level, published
/// together so a lookup never pairs one reading's description with another's pixels. Immutable
/// once published. A version replaced by invalidate() or a re-read is retired, not freed: it
/// stays valid until TextureCache::collectRetired() or the cache's destruction.
struct TextureVersion {
    TextureInfo info;
    /// The finest level, serving point lookups; null when the file is served by the texture
    /// system (over the resident budget, unreadable pixels) or while `stale`.
    std::unique_ptr<const ResidentImage> pixels;
    bool stale = false;  ///< invalidated: the next open() or lookup re-reads the file
};

/// A texture file as the cache opened it. Owned by the cache; the object stays valid until the
/// cache is destroyed (invalidation re-reads the file into a new TextureVersion, same Texture).
struct Texture {
    std::string path;
    /// A `<UDIM>` set: tile 1001 + u + 10 v at index u + 10 v (null where the set has no
    /// file). Empty for a plain file.
    std::vector<const Texture*> udimTiles;

    /// The current description (a UDIM set's is its first tile's). Re-read with the pixels:
    /// after invalidate() it still states the previous reading until the next open() or
    /// lookup re-reads the file. The reference stays valid until TextureCache::collectRetired().
    const TextureInfo& info() const {
        return udimFirst ? udimFirst->info() : current.load(std::memory_order_acquire)->info;
    }
    /// The current resident pixels; null when served by the texture system, for a UDIM set,
    /// or after invalidate() until re-read. Valid until TextureCache::collectRetired().
    const ResidentImage* resident() const {
        return udimFirst ? nullptr : current.load(std::memory_order_acquire)->pixels.get();
    }

    // State kept by the cache. `current` is read lock-free; the rest changes under its lock.
    /// The published version (never null once open() has returned this Texture).
    std::atomic<const TextureVersion*> current{nullptr};
    std::unique_ptr<TextureVersion> owned;  ///< owns `current`
    bool loading = false;                   ///< a thread is reading the file without the lock
    const Texture* udimFirst = nullptr;     ///< a UDIM set: the tile that describes it
    /// The backend's texture handle, opened by the first lookup that needs the texture system.
    std::atomic<void*> handle{nullptr};
    std::atomic<bool> handleFailed{false};  ///< the texture system could not open the file
};

/// The result of opening a file.
struct TextureOpenResult {
    const Texture* texture = nullptr;  ///< null when the file cannot be read
    /// "texture 'path': reason" when texture is null; for a UDIM set with some unreadable
    /// tiles, their errors while texture is set.
    std::string error;
    bool firstReport = false;  ///< true the first time this error is returned
};

/// Shared texture store for all materials of a render delegate.
///
/// Thread safety: every member may be called from any thread at any time, invalidate() included
/// (collectRetired() has a precondition, below). Point lookups of resident pixels are lock-free
/// and free of reference counting: one acquire load of Texture::current. They lock only when
/// the texture is stale (after invalidate(): they re-read it) or needs the texture system (the
/// first such lookup opens the handle); OpenImageIO keeps per-thread state itself.
///
/// Files are read and decoded without the cache's lock: the opening thread marks the Texture
/// `loading` under the lock, reads, then publishes a new TextureVersion under the lock; others
/// asking for the same file wait for that one read (a file is decoded once), while other files
/// are read concurrently. invalidate() publishes stale versions and retires the old ones, whose
/// pixels lock-free readers may still be using; collectRetired() frees them at a quiescent point
/// (the render delegate's commitResources(): no render pass runs during a commit). This is
/// quiescent-state-based reclamation (McKenney & Slingwine 1998, "Read-Copy Update"), with
/// the quiescent point named by the caller instead of detected.
class TextureCache {
  public:
    struct Options {
        float maxMemoryMB = 1024.0f;  ///< tile memory held by OpenImageIO's cache
        int maxOpenFiles = 100;
        bool autoMip = true;  ///< build mip levels for files that have none (PNG, JPEG)
        /// Budget for the finest levels held in memory (all files of this cache together); a
        /// file that would exceed it is read through OpenImageIO's tile cache instead.
        double maxResidentMB = 4096.0;
        /// Decode PNG files with libpng (no OpenImageIO backend needed for them); false reads
        /// every file through the backend.
        bool nativePng = true;
    };

    TextureCache();
    explicit TextureCache(const Options& options);
    ~TextureCache();
    TextureCache(const TextureCache&) = delete;
    TextureCache& operator=(const TextureCache&) = delete;

    /// Resolves a file (once per path; later calls return the same Texture) and reads its finest
    /// level into memory within Options::maxResidentMB (else it is left to the texture system). A
    /// missing or unreadable file gives texture == nullptr and an error naming the path and
    /// the reason; firstReport is true only on the first such result, so callers log it once.
    ///
    /// A path containing `<UDIM>` opens the tiles 1001-1100 that exist (spec 2.5: at most
    /// 10 in u, up to tile 1100); st (u, v) reads tile 1001 + floor(u) + 10 floor(v).
    ///
    /// The colour tag counts only explicit statements: an ICC profile named sRGB or linear, Exif
    /// ColorSpace = 1 (sRGB), a PNG gAMA of 2.2 or 1.0, or oiio:ColorSpace from formats that
    /// record it. OpenImageIO 2.4 labels every PNG and JPEG "sRGB" even when the file says
    /// nothing, so that label alone is ignored for them.
    TextureOpenResult open(const std::string& path);

    /// Filtered lookup at st (USD convention: (0,0) is the bottom-left of the image) with the
    /// screen-space footprint d = (ds/dx, dt/dx, ds/dy, dt/dy); zero means point sampling
    /// (bilinear on the finest level). Writes rgba expanded by the UsdUVTexture channel rules:
    /// 1 channel c -> (c,c,c,1), 2 -> (c0,c0,c0,c1), 3 -> (r,g,b,1), 4 -> rgba. Values are the
    /// file's decoded numbers (8/16-bit normalised to [0,1]); no colour-space conversion.
    /// Returns false (rgba untouched) where there is no data: outside a UDIM set's tiles, or a
    /// file that failed after open(). Non-finite st or footprints are treated as 0.
    bool lookup(const Texture& texture, Wrap wrapS, Wrap wrapT, glm::vec2 st,
                const glm::vec4& footprint, glm::vec4* rgba) const;

    /// lookup() with a point sample by default, giving (0,0,0,1) where there is no data.
    glm::vec4 sample(const Texture& texture, Wrap wrapS, Wrap wrapT, glm::vec2 st,
                     const glm::vec4& footprint = glm::vec4(0.0f)) const {
        glm::vec4 rgba(0.0f, 0.0f, 0.0f, 1.0f);
        lookup(texture, wrapS, wrapT, st, footprint, &rgba);
        return rgba;
    }

    /// Forgets failures and drops cached pixels (OpenImageIO's tiles; resident ones are
    /// retired) so files edited on disk are read again, with their description, by the next
    /// open() or lookup. Safe while lookups run on other threads: a lookup already holding the
    /// previous version finishes on it (retired, not freed), later ones read the file again.
    void invalidate();

    /// Notes a file another reader loads (a light's texture) so reloadChanged() watches it too;
    /// call it just before reading: the file is stamped as it is now (a light re-synced for
    /// another reason does not count as a change later).
    void watch(const std::string& path);
    /// Drops what this cache holds of the files it has opened or watches that changed on disk
    /// since they were first seen or last reloaded (modification or change time, inode or size;
    /// a file that appeared or vanished counts): their pixels and texture-system tiles, and the
    /// UDIM sets with such a tile (the next open() of the pattern builds the set again, so a
    /// tile that appeared joins it). Returns the changed paths (empty: nothing changed). A
    /// rewrite within one tick of a coarse file-system clock that keeps the size is not seen.
    std::vector<std::string> reloadChanged();
    /// invalidate() with every known file re-stamped as it is now; false (nothing done) when
    /// the cache never opened or watched a file.
    bool reloadAll();
    /// How many times `path` was reloaded (reloadChanged() found it changed, or reloadAll()
    /// ran): a reader that keeps what it read of a watched file (a light's image) reads it again
    /// only when this differs from the value it read it at.
    uint64_t fileVersion(const std::string& path) const;

    /// Frees the versions (pixels and descriptions) retired by invalidate() and re-reads.
    /// Call it at a quiescent point, e.g. between render passes: no lookup may be in flight
    /// and no TextureInfo reference or ResidentImage pointer taken before the call may be used
    /// after it. Returns the pixel bytes freed.
    size_t collectRetired();

    /// Bytes of texture memory currently held: resident pixels (retired ones included) plus
    /// OpenImageIO's tiles.
    size_t memoryUsed() const;
    /// Bytes of current resident pixels (within Options::maxResidentMB; includes reads in
    /// progress, which reserve their bytes first).
    size_t residentBytes() const { return _residentBytes.load(std::memory_order_relaxed); }
    /// Bytes of retired resident pixels awaiting collectRetired() (outside the budget).
    size_t retiredBytes() const { return _retiredBytes.load(std::memory_order_relaxed); }

  private:
    struct Reading;  ///< a file read without the lock (textureCache.cpp)
    TextureOpenResult openFile(const std::string& path);     ///< locks; reads unlocked
    TextureOpenResult openUdim(const std::string& pattern);  ///< locks; reads unlocked
    bool lookupFile(const Texture& texture, Wrap wrapS, Wrap wrapT, float s, float t,
                    const glm::vec4& footprint, glm::vec4* rgba) const;
    /// Opens, describes and (within the budget, reserved first) decodes a file. No lock held.
    Reading read(const std::string& path);
    /// Decodes the pixels if the budget allows (no lock held). Returns a note for the log when
    /// it does not, else empty.
    std::string makeResident(Reading& reading, imageio::ImageReader& reader);
    /// The current version; a stale one is re-read first (locks; waits for a read in progress).
    const TextureVersion& currentVersion(const Texture& texture) const {
        const TextureVersion* v = texture.current.load(std::memory_order_acquire);
        return v->stale ? refreshed(texture) : *v;
    }
    const TextureVersion& refreshed(const Texture& texture) const;
    /// Re-reads a stale texture (lock held on entry and exit; released while reading) and
    /// publishes the reading, or keeps the texture stale if invalidate() ran meanwhile.
    /// Returns the reading either way (owned by the texture or the retired list).
    const TextureVersion* reread(Texture& texture, std::unique_lock<std::mutex>& lock);
    /// Makes `version` current and retires the previous one (_mutex held).
    void publish(Texture& texture, std::unique_ptr<TextureVersion> version);
    /// The texture-system handle, opened on first use (locks once); null if it cannot be.
    void* handleFor(const Texture& texture) const;

    /// Loads the image I/O backend and takes its texture system (_mutex held). False with
    /// *error when the backend cannot be loaded.
    bool ensureSystem(std::string* error);

    Options _options;
    /// imageio::TextureSystem*, set by the first lookup that needs it (before any handle).
    std::atomic<void*> _system{nullptr};
    std::atomic<size_t> _residentBytes{0};
    std::atomic<size_t> _retiredBytes{0};
    mutable std::mutex _mutex;
    mutable std::condition_variable _loaded;  ///< a Texture's `loading` was cleared
    uint64_t _generation = 0;                 ///< invalidate() calls so far
    std::map<std::string, std::unique_ptr<Texture>> _textures;
    std::vector<std::unique_ptr<TextureVersion>> _retired;  ///< replaced, freed by collectRetired()
    std::map<std::string, std::string> _failures;  ///< path -> error
    std::set<std::string> _reported;
    /// What each file opened or watched looked like on disk (reloadChanged()).
    struct FileStamp {
        bool exists = false;
        int64_t modified = 0, changed = 0;  ///< mtime and ctime, nanoseconds
        uint64_t inode = 0;
        uintmax_t size = 0;
        bool operator==(const FileStamp&) const = default;
    };
    static FileStamp stampOf(const std::string& path);
    void remember(const std::string& path);  ///< stamps a path seen for the first time (locks)
    /// invalidate() for `changed` paths only (null: all), UDIM sets with a changed tile included.
    void invalidatePaths(const std::set<std::string>* changed);
    static std::string udimTilePath(const std::string& pattern, int index);  ///< tile 1001 + index
    std::map<std::string, FileStamp> _stamps;
    std::map<std::string, uint64_t> _fileVersions;  ///< reloadChanged() counts per path
    uint64_t _reloadAlls = 0;                       ///< reloadAll() calls that did something
    std::vector<std::unique_ptr<Texture>> _retiredSets;  ///< UDIM sets rebuilt since (kept for lookups in flight)
};

}  // namespace principled::shading
