// SPDX-License-Identifier: Apache-2.0
// UvTexture: one UsdUVTexture node resolved for lookups (file handle, wrap modes, colour
// space, scale and bias, fallback).
#pragma once

#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "delegate/hd/materialNetwork.h"
#include "delegate/shading/textureCache.h"

namespace principled::shading {

/// UsdUVTexture sourceColorSpace "auto" (spec 2.5): decode sRGB when the file says so, or when
/// it is 8-bit with 3 or 4 channels and says nothing. False for a null texture.
bool autoDecodesSrgb(const Texture* tex);

/// A UsdUVTexture node ready to sample. Plain data: copyable, no ownership of the texture.
struct UvTexture {
    const Texture* texture = nullptr;  ///< null: the file is missing or unreadable -> fallback
    Wrap wrapS = Wrap::Black;
    Wrap wrapT = Wrap::Black;
    bool decodeSrgb = false;  ///< sourceColorSpace resolved (raw | sRGB | auto)
    glm::vec4 scale{1.0f};
    glm::vec4 bias{0.0f};
    glm::vec4 fallback{0.0f, 0.0f, 0.0f, 1.0f};

    /// Resolves the node's inputs (UsdPreviewSurface spec 2.5, UsdUVTexture) and opens its
    /// file. Problems (unknown tokens, a missing file: reported once per file by the cache)
    /// are appended to *notes.
    static UvTexture resolve(const hd::MaterialNode& node, TextureCache& cache,
                             std::vector<std::string>* notes);

    /// The node's rgba output at st (bottom-left origin) with screen footprint
    /// (ds/dx, dt/dx, ds/dy, dt/dy): decoded (sRGB -> linear on rgb), then tex * scale + bias.
    /// A missing file or UDIM tile gives the fallback unchanged. Thread-safe, no allocation.
    glm::vec4 sample(const TextureCache& cache, glm::vec2 st,
                     const glm::vec4& footprint = glm::vec4(0.0f)) const;
};

}  // namespace principled::shading
