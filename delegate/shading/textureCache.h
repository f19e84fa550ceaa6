// SPDX-License-Identifier: Apache-2.0
// TextureCache: texture files resolved once to OpenImageIO texture handles, looked up with
// mip-mapped, filtered reads through one TextureSystem that has a memory limit. OpenImageIO is
// reached through the image I/O backend (delegate/imageio/imageIO.h), loaded by the first open().
#pragma once

#include "delegate/shading/textureWrap.h"

#include <cstdint>
#include <glm/glm.hpp>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

namespace principled::shading {

/// What a file's metadata states about its encoding (see TextureCache::open for the rules).
enum class ColorTag : uint8_t { Unknown, Srgb, Linear };

/// A texture file as the cache opened it. Owned by the cache; stays valid until the cache is
/// destroyed (invalidation re-reads pixels but keeps the object).
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
    void* handle = nullptr;  ///< the backend's texture handle (null for a UDIM set)
    /// A `<UDIM>` set: tile 1001 + u + 10 v at index u + 10 v (null where the set has no
    /// file); the fields above describe the first tile found. Empty for a plain file.
    std::vector<const Texture*> udimTiles;
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
/// Thread safety: open() and invalidate() lock; sample() is lock-free in this class and may be
/// called from any number of render threads (OpenImageIO keeps per-thread state itself).
class TextureCache {
  public:
    struct Options {
        float maxMemoryMB = 1024.0f;  ///< tile memory held by OpenImageIO's cache
        int maxOpenFiles = 100;
        bool autoMip = true;  ///< build mip levels for files that have none (PNG, JPEG)
    };

    TextureCache();
    explicit TextureCache(const Options& options);
    ~TextureCache();
    TextureCache(const TextureCache&) = delete;
    TextureCache& operator=(const TextureCache&) = delete;

    /// Resolves a file to a handle (once per path; later calls return the same Texture). A
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

    /// Forgets failures and drops cached pixels so files edited on disk are read again.
    void invalidate();

    /// Bytes of tile memory currently held (for diagnostics).
    size_t memoryUsed() const;

  private:
    TextureOpenResult openFile(const std::string& path);     ///< _mutex held
    TextureOpenResult openUdim(const std::string& pattern);  ///< _mutex held
    bool lookupFile(const Texture& texture, Wrap wrapS, Wrap wrapT, float s, float t,
                    const glm::vec4& footprint, glm::vec4* rgba) const;

    /// Loads the image I/O backend and takes its texture system (_mutex held). False with
    /// *error when the backend cannot be loaded.
    bool ensureSystem(std::string* error);

    void* _system = nullptr;  ///< imageio::TextureSystem*, set by the first open()
    mutable std::mutex _mutex;
    std::map<std::string, std::unique_ptr<Texture>> _textures;
    std::map<std::string, std::string> _failures;  ///< path -> error
    std::set<std::string> _reported;
};

}  // namespace principled::shading
