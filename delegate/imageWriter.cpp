// SPDX-License-Identifier: Apache-2.0
#include "delegate/imageWriter.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <memory>

#include "delegate/imageio/imageIO.h"
#include "delegate/imageio/nativeWriter.h"

namespace principled::embree {

float linearToSrgb(float v) {
    if (!(v > 0.0f)) return 0.0f;
    if (v >= 1.0f) return 1.0f;
    // IEC 61966-2-1 sRGB encoding.
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

namespace {

std::string lowerExtension(const std::string& path) {
    auto dot = path.rfind('.');
    std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
    return ext;
}

}  // namespace

bool writeImage(const std::string& path, int width, int height,
                const std::vector<ImageLayer>& layers, std::string* error, float pixelAspectRatio) {
    if (layers.empty() || !layers[0].pixels) {
        *error = path + ": nothing to write";
        return false;
    }
    std::string ext = lowerExtension(path);
    size_t n = size_t(width) * size_t(height);
    std::vector<float> floats;
    std::vector<unsigned char> bytes;
    imageio::ImageSpec spec;
    spec.width = width;
    spec.height = height;
    const void* data = nullptr;
    if (ext == "exr") {
        std::vector<std::string> names;
        for (const auto& l : layers)
            for (const auto& c : l.channels) names.push_back(l.name.empty() ? c : l.name + "." + c);
        spec.channels = int(names.size());
        spec.format = imageio::PixelType::Float;
        spec.channelNames = names;
        spec.alphaChannel = -1;
        for (size_t i = 0; i < names.size(); ++i)
            if (names[i] == "A") spec.alphaChannel = int(i);
        spec.strings["compression"] = "zip";
        if (pixelAspectRatio != 1.0f) spec.numbers["PixelAspectRatio"] = pixelAspectRatio;
        floats.resize(n * names.size());
        size_t offset = 0;
        for (const auto& l : layers) {
            size_t c = l.channels.size();
            for (size_t p = 0; p < n; ++p)
                for (size_t k = 0; k < c; ++k) {
                    float v = l.pixels[p * c + k];
                    floats[p * names.size() + offset + k] = std::isfinite(v) ? v : 0.0f;
                }
            offset += c;
        }
        data = floats.data();
    } else if (ext == "png") {
        const ImageLayer& l = layers[0];
        // PNG is the picture people look at: RGB only. A visible dome has alpha 0 in the color
        // AOV, and viewers would show it as transparent (the EXR keeps alpha).
        int c = int(std::min<size_t>(l.channels.size(), 3));
        if (c < 3) {
            *error = path + ": PNG needs a colour layer with 3 or 4 channels";
            return false;
        }
        spec.channels = c;
        spec.format = imageio::PixelType::UInt8;
        bytes.resize(n * c);
        for (size_t p = 0; p < n; ++p)
            for (int k = 0; k < c; ++k) {
                float v = l.pixels[p * l.channels.size() + k];
                float e = linearToSrgb(v);
                bytes[p * c + k] = static_cast<unsigned char>(std::lround(e * 255.0f));
            }
        data = bytes.data();
    } else {
        *error = path + ": unsupported output format '." + ext + "' (expected .exr or .png)";
        return false;
    }
    std::string reason;
    // EXR and PNG are encoded with OpenEXRCore and libpng (nativeWriter.h), so writing the
    // output does not load OpenImageIO; PRINCIPLED_IMAGE_WRITER=oiio writes through the backend.
    const char* writer = std::getenv("PRINCIPLED_IMAGE_WRITER");
    if (!writer || std::string(writer) != "oiio") {
        bool ok = ext == "exr"
                      ? imageio::writeExrFloat(path, width, height, spec.channelNames,
                                               floats.data(), &reason, pixelAspectRatio)
                      : imageio::writePng8(path, width, height, spec.channels, bytes.data(),
                                           &reason);
        if (!ok) *error = path + ": " + reason;
        return ok;
    }
    imageio::Backend* io = imageio::backend(&reason);
    if (!io || !io->write(path, "", spec, data, &reason)) {
        *error = path + ": " + reason;
        return false;
    }
    return true;
}

}  // namespace principled::embree
