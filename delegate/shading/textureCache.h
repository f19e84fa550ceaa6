// SPDX-License-Identifier: Apache-2.0
// TextureCache: texture files resolved once. Point lookups (the renderer's: a hit has no
// derivatives) read the finest level held in memory (ResidentImage) with OpenImageIO's bilinear
// conventions; filtered lookups, and files beyond the resident budget, go through OpenImageIO's
// mip-mapped TextureSystem, which has its own memory limit. OpenImageIO is reached through the
// image I/O backend (delegate/imageio/imageIO.h), loaded by the first open().
#pragma once

#include <atomic>
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

/// A texture file as the cache opened it. Owned by the cache; stays valid until the cache is
/// destroyed (invalidation re-reads pixels but keeps the object, and its description).
struct Texture {
    std::string path;
    int width = 0;
    int height = 0;
    int channels = 0;        ///< channels in the file (lookups read at most 4)
    int bitsPerChannel = 0;  ///< 8, 16, 32 (float) ...
    bool isFloat = false;
    ColorTag colorTag = ColorTag::Unknown;  ///< explicit colour-space metadata, if any
    bool hasWrapMetadata = false;           ///< the file carries "wrapmodes"
    Wrap metadataWrapS = Wrap::Black;
    Wrap metadataWrapT = Wrap::Black;
    /// A `<UDIM>` set: tile 1001 + u + 10 v at index u + 10 v (null where the set has no
    /// file); the fields above describe the first tile found. Empty for a plain file.
    std::vector<const Texture*> udimTiles;

    /// The finest level in memory, serving point lookups; null when the file is served by the
    /// texture system (over the resident budget, unreadable pixels, a UDIM set) or after
    /// invalidate() until re-read. The pixels are owned by `residentPixels` (changed only under
    /// the cache's lock).
    std::atomic<const ResidentImage*> resident{nullptr};
    std::unique_ptr<ResidentImage> residentPixels;
    std::atomic<bool> rereadPending{false};  ///< invalidated: re-read on next open or lookup
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
/// Thread safety: open() locks; sample() is lock-free in this class and may be called from any
/// number of render threads (OpenImageIO keeps per-thread state itself), except the first lookup
/// of a texture that needs the texture system (it opens the handle) or follows invalidate()
/// (it re-reads the file), which take the lock once. invalidate() frees resident pixels: it
/// must not run while lookups are in flight (call it between renders).
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

    /// Forgets failures and drops cached pixels (resident ones and OpenImageIO's tiles) so
    /// files edited on disk are read again by the next open() or lookup.
    void invalidate();

    /// Bytes of texture memory currently held: resident pixels plus OpenImageIO's tiles.
    size_t memoryUsed() const;
    /// Bytes of resident pixels alone (within Options::maxResidentMB).
    size_t residentBytes() const { return _residentBytes.load(std::memory_order_relaxed); }

  private:
    TextureOpenResult openFile(const std::string& path);     ///< _mutex held
    TextureOpenResult openUdim(const std::string& pattern);  ///< _mutex held
    bool lookupFile(const Texture& texture, Wrap wrapS, Wrap wrapT, float s, float t,
                    const glm::vec4& footprint, glm::vec4* rgba) const;
    /// Reads the file's pixels into memory if the budget allows (_mutex held). Returns a note
    /// for the log when it does not, else empty.
    std::string makeResident(Texture& texture, imageio::ImageReader& reader);
    /// The resident pixels for a point lookup, re-reading them after invalidate() (locks once).
    const ResidentImage* residentFor(const Texture& texture) const;
    void reread(Texture& texture);        ///< after invalidate() (_mutex held)
    void dropResident(Texture& texture);  ///< _mutex held
    /// The texture-system handle, opened on first use (locks once); null if it cannot be.
    void* handleFor(const Texture& texture) const;

    /// Loads the image I/O backend and takes its texture system (_mutex held). False with
    /// *error when the backend cannot be loaded.
    bool ensureSystem(std::string* error);

    Options _options;
    /// imageio::TextureSystem*, set by the first lookup that needs it (before any handle).
    std::atomic<void*> _system{nullptr};
    std::atomic<size_t> _residentBytes{0};
    mutable std::mutex _mutex;
    std::map<std::string, std::unique_ptr<Texture>> _textures;
    std::map<std::string, std::string> _failures;  ///< path -> error
    std::set<std::string> _reported;
};

}  // namespace principled::shading
