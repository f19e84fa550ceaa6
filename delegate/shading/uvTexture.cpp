// SPDX-License-Identifier: Apache-2.0
#include "delegate/shading/uvTexture.h"

#include "delegate/shading/colorSpace.h"

namespace principled::shading {

using namespace hd;

namespace {

const Value* param(const MaterialNode& node, const char* name) {
    auto it = node.parameters.find(Token(name));
    return it == node.parameters.end() ? nullptr : &it->second;
}

glm::vec4 vec4Param(const MaterialNode& node, const char* name, glm::vec4 fallback) {
    const Value* v = param(node, name);
    if (!v) return fallback;
    if (auto* x = getIf<glm::vec4>(*v)) return *x;
    if (auto* x = getIf<glm::vec3>(*v)) return glm::vec4(*x, fallback.w);
    if (auto* x = getIf<glm::vec2>(*v)) return glm::vec4(x->x, x->y, fallback.z, fallback.w);
    if (auto f = getFloat(*v)) return glm::vec4(*f);
    return fallback;
}

std::string tokenParam(const MaterialNode& node, const char* name, const char* fallback) {
    const Value* v = param(node, name);
    if (!v) return fallback;
    auto s = getString(*v);
    return s ? *s : std::string(fallback);
}

// wrapS/wrapT token; useMetadata reads the file's wrap metadata and falls back to black.
Wrap resolveWrap(const std::string& token, bool metadata, Wrap metadataWrap,
                 const MaterialNode& node, const char* input, std::vector<std::string>* notes) {
    if (token == "black") return Wrap::Black;
    if (token == "clamp") return Wrap::Clamp;
    if (token == "repeat") return Wrap::Repeat;
    if (token == "mirror") return Wrap::Mirror;
    if (token != "useMetadata")
        notes->push_back((node.where.empty() ? "" : node.where + ": ") + node.path.str() + ": " + input + " '" + token +
                         "' is not black|clamp|repeat|mirror|useMetadata; using useMetadata");
    return metadata ? metadataWrap : Wrap::Black;
}

glm::vec4 finite(glm::vec4 v, glm::vec4 otherwise) {
    for (int i = 0; i < 4; ++i)
        if (!std::isfinite(v[i])) v[i] = otherwise[i];
    return v;
}

}  // namespace

UvTexture UvTexture::resolve(const MaterialNode& node, TextureCache& cache,
                             std::vector<std::string>* notes) {
    UvTexture t;
    t.scale = finite(vec4Param(node, "scale", glm::vec4(1.0f)), glm::vec4(1.0f));
    t.bias = finite(vec4Param(node, "bias", glm::vec4(0.0f)), glm::vec4(0.0f));
    t.fallback = finite(vec4Param(node, "fallback", glm::vec4(0, 0, 0, 1)), glm::vec4(0, 0, 0, 1));
    std::string file;
    if (const Value* v = param(node, "file"))
        if (auto s = getString(*v)) file = *s;
    TextureOpenResult opened = cache.open(file);
    if (opened.firstReport)
        notes->push_back(
            (node.where.empty() ? "" : node.where + ": ") + node.path.str() + ": " + opened.error +
            (opened.texture ? "; missing tiles use the fallback" : "; using the fallback"));
    t.texture = opened.texture;
    const Texture* tex = t.texture;
    // One description (open() re-read it if the file was invalidated): fields of one reading.
    const TextureInfo info = tex ? tex->info() : TextureInfo();
    t.wrapS = resolveWrap(tokenParam(node, "wrapS", "useMetadata"), tex && info.hasWrapMetadata,
                          info.metadataWrapS, node, "wrapS", notes);
    t.wrapT = resolveWrap(tokenParam(node, "wrapT", "useMetadata"), tex && info.hasWrapMetadata,
                          info.metadataWrapT, node, "wrapT", notes);
    std::string cs = tokenParam(node, "sourceColorSpace", "auto");
    if (cs == "raw") {
        t.decodeSrgb = false;
    } else if (cs == "sRGB") {
        t.decodeSrgb = true;
    } else {
        if (cs != "auto")
            notes->push_back((node.where.empty() ? "" : node.where + ": ") + node.path.str() + ": sourceColorSpace '" + cs +
                             "' is not raw|sRGB|auto; using auto");
        t.decodeSrgb = autoDecodesSrgb(tex);
    }
    return t;
}

bool autoDecodesSrgb(const Texture* tex) {
    // auto (spec 2.5): sRGB if the file says so, or if it is 8-bit with 3 or 4 channels.
    // A file that explicitly says linear stays raw, as USD's Hio does for a gamma of 1.
    if (!tex) return false;
    const TextureInfo info = tex->info();  // one reading's description
    bool eightBitColour = info.bitsPerChannel == 8 && !info.isFloat && (info.channels == 3 || info.channels == 4);
    return info.colorTag == ColorTag::Srgb || (info.colorTag == ColorTag::Unknown && eightBitColour);
}

glm::vec4 UvTexture::sample(const TextureCache& cache, glm::vec2 st,
                            const glm::vec4& footprint) const {
    if (!texture) return fallback;
    glm::vec4 c;
    if (!cache.lookup(*texture, wrapS, wrapT, st, footprint, &c)) return fallback;
    if (decodeSrgb) {
        // Decoded after filtering (as Cycles does for 8-bit sRGB): alpha is never encoded.
        c.x = srgbToLinear(c.x);
        c.y = srgbToLinear(c.y);
        c.z = srgbToLinear(c.z);
    }
    return c * scale + bias;  // UsdUVTexture: out = tex * scale + bias
}

}  // namespace principled::shading
