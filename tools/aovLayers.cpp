// SPDX-License-Identifier: Apache-2.0
#include "tools/aovLayers.h"

#include "plugins/renderSession.h"

namespace principled::tools {

AovLayers aovLayers(const host::RenderSession& session) {
    AovLayers out;
    size_t n = size_t(session.width()) * session.height();
    for (const auto& img : session.aovs()) {
        embree::ImageLayer l;
        l.name = img.name == "color" ? "" : img.name;
        static const char* rgba[] = {"R", "G", "B", "A"};
        if (img.components == 1)
            l.channels = {img.isInt ? "id" : "Z"};
        else
            for (int c = 0; c < img.components; ++c) l.channels.push_back(rgba[c]);
        if (img.name == "depth" || img.name == "cameraDepth") l.channels = {"Z"};
        if (img.name == "alpha") l.channels = {"A"};
        if (img.name == "sampleCount" || img.name == "variance") l.channels = {"V"};
        if (img.isInt) {
            // The inner vector's buffer stays put when the outer vector grows.
            out.storage.emplace_back(n);
            const int32_t* ids = static_cast<const int32_t*>(img.pixels);
            for (size_t i = 0; i < n; ++i) out.storage.back()[i] = float(ids[i]);
            l.pixels = out.storage.back().data();
        } else {
            l.pixels = static_cast<const float*>(img.pixels);
        }
        out.layers.push_back(l);
    }
    return out;
}

}  // namespace principled::tools
