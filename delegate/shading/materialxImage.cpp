// SPDX-License-Identifier: Apache-2.0
#include "delegate/shading/materialxImage.h"

#include <cmath>

namespace principled::shading {

using namespace hd;

namespace {

const Value* param(const MaterialNode& node, const std::string& name) {
    auto it = node.parameters.find(Token(name));
    return it == node.parameters.end() ? nullptr : &it->second;
}

std::string stringParam(const MaterialNode& node, const std::string& name,
                        const std::string& fallback) {
    if (const Value* v = param(node, name))
        if (auto s = getString(*v)) return *s;
    return fallback;
}

glm::vec2 vec2Param(const MaterialNode& node, const char* name, glm::vec2 fallback) {
    const Value* v = param(node, name);
    if (!v) return fallback;
    glm::vec2 out = fallback;
    if (auto* x = getIf<glm::vec2>(*v))
        out = *x;
    else if (auto f = getFloat(*v))
        out = glm::vec2(*f);
    return std::isfinite(out.x) && std::isfinite(out.y) ? out : fallback;
}

// The `default` input as the lookup's fallback: a colour3 keeps alpha 1, a float is splatted.
glm::vec4 defaultValue(const MaterialNode& node) {
    const Value* v = param(node, "default");
    glm::vec4 d(0.0f, 0.0f, 0.0f, 1.0f);
    if (!v) return d;
    if (auto* c4 = getIf<glm::vec4>(*v))
        d = *c4;
    else if (auto* c3 = getIf<glm::vec3>(*v))
        d = glm::vec4(*c3, 1.0f);
    else if (auto* c2 = getIf<glm::vec2>(*v))
        d = glm::vec4(c2->x, c2->y, 0.0f, 1.0f);
    else if (auto f = getFloat(*v))
        d = glm::vec4(*f);
    for (int i = 0; i < 4; ++i)
        if (!std::isfinite(d[i])) d[i] = 0.0f;
    return d;
}

void note(const MaterialNode& node, std::vector<std::string>* notes, const std::string& text) {
    notes->push_back((node.where.empty() ? "" : node.where + ": ") + node.path.str() + ": " + text);
}

// MaterialX address modes (spec "Standard Source Nodes", image) onto the cache's wrap modes.
Wrap addressMode(const MaterialNode& node, const char* input, bool nonZeroDefault,
                 std::vector<std::string>* notes) {
    std::string mode = stringParam(node, input, "periodic");
    if (mode == "periodic") return Wrap::Repeat;
    if (mode == "clamp") return Wrap::Clamp;
    if (mode == "mirror") return Wrap::Mirror;
    if (mode == "constant") {
        if (nonZeroDefault)
            note(node, notes,
                 std::string(input) + " 'constant' reads black outside [0,1], not the default");
        return Wrap::Black;
    }
    note(node, notes,
         std::string(input) + " '" + mode + "' is not periodic|clamp|mirror|constant; periodic");
    return Wrap::Repeat;
}

}  // namespace

UvTexture resolveMaterialXImage(const MaterialNode& node, TextureCache& cache,
                                std::vector<std::string>* notes) {
    UvTexture t;
    t.fallback = defaultValue(node);
    std::string file = stringParam(node, "file", "");
    TextureOpenResult opened = cache.open(file);
    if (opened.firstReport)
        note(node, notes,
             opened.error +
                 (opened.texture ? "; missing tiles use the default" : "; using the default"));
    t.texture = opened.texture;
    bool nonZeroDefault = glm::vec3(t.fallback) != glm::vec3(0.0f);
    t.wrapS = addressMode(node, "uaddressmode", nonZeroDefault, notes);
    t.wrapT = addressMode(node, "vaddressmode", nonZeroDefault, notes);
    std::string filter = stringParam(node, "filtertype", "linear");
    if (filter != "linear" && filter != "cubic")
        note(node, notes, "filtertype '" + filter + "' not supported; filtered as linear");
    std::string cs = stringParam(node, "colorSpace:file", "");
    const std::string& id = node.identifier.str();
    bool colourType = id.size() > 7 && (id.compare(id.size() - 7, 7, "_color3") == 0 ||
                                        id.compare(id.size() - 7, 7, "_color4") == 0);
    if (!colourType) {
        // MaterialX: colour spaces apply to color3/color4 values only; data images stay raw.
        t.decodeSrgb = false;
    } else if (cs == "srgb_texture" || cs == "sRGB") {
        t.decodeSrgb = true;
    } else if (cs == "lin_rec709" || cs == "lin_srgb" || cs == "raw" || cs == "linear") {
        t.decodeSrgb = false;
    } else {
        if (!cs.empty())
            note(node, notes, "colorspace '" + cs + "' not supported; decoded as for 'auto'");
        t.decodeSrgb = autoDecodesSrgb(t.texture);
    }
    return t;
}

Transform2d tiledImageTransform(const MaterialNode& node) {
    glm::vec2 tiling = vec2Param(node, "uvtiling", glm::vec2(1.0f));
    glm::vec2 offset = vec2Param(node, "uvoffset", glm::vec2(0.0f));
    glm::vec2 imageSize = vec2Param(node, "realworldimagesize", glm::vec2(1.0f));
    glm::vec2 tileSize = vec2Param(node, "realworldtilesize", glm::vec2(1.0f));
    glm::vec2 k(imageSize.x != 0.0f ? tileSize.x / imageSize.x : 1.0f,
                imageSize.y != 0.0f ? tileSize.y / imageSize.y : 1.0f);
    // MaterialX NG_tiledimage: (uv * uvtiling - uvoffset) / realworldimagesize * realworldtilesize.
    return Transform2d::make(0.0f, tiling * k, -offset * k);
}

Transform2d place2dTransform(const MaterialNode& node) {
    glm::vec2 pivot = vec2Param(node, "pivot", glm::vec2(0.0f));
    glm::vec2 scale = vec2Param(node, "scale", glm::vec2(1.0f));
    glm::vec2 offset = vec2Param(node, "offset", glm::vec2(0.0f));
    float degrees = 0.0f;
    if (const Value* v = param(node, "rotate"))
        if (auto f = getFloat(*v); f && std::isfinite(*f)) degrees = *f;
    int order = 0;
    if (const Value* v = param(node, "operationorder"))
        order = static_cast<int>(getFloat(*v).value_or(0.0f));
    for (int i = 0; i < 2; ++i)
        if (scale[i] == 0.0f) scale[i] = 1.0f;
    float r = glm::radians(degrees), c = std::cos(r), s = std::sin(r);
    // MaterialX rotate2d: (c x + s y, -s x + c y), i.e. clockwise for a positive angle.
    glm::mat2 rotation(glm::vec2(c, -s), glm::vec2(s, c));
    glm::mat2 inverseScale(glm::vec2(1.0f / scale.x, 0.0f), glm::vec2(0.0f, 1.0f / scale.y));
    Transform2d t;
    if (order == 1) {  // TRS: R(uv - pivot - offset) / scale + pivot
        t.linear = inverseScale * rotation;
        t.translation = -(t.linear * (pivot + offset)) + pivot;
    } else {  // SRT: R((uv - pivot) / scale) - offset + pivot
        t.linear = rotation * inverseScale;
        t.translation = -(t.linear * pivot) - offset + pivot;
    }
    return t;
}

}  // namespace principled::shading
