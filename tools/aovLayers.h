// SPDX-License-Identifier: Apache-2.0
// The image layers a render writes: color as the main RGBA, every other AOV as "name.R"...
#pragma once

#include <vector>

#include "delegate/imageWriter.h"

namespace principled::host {
class RenderSession;
}

namespace principled::tools {

/// Layers pointing at the session's resolved AOVs (valid until its next step). IDs become float
/// channels (exact below 2^24), held in `storage`.
struct AovLayers {
    std::vector<embree::ImageLayer> layers;
    std::vector<std::vector<float>> storage;
};
AovLayers aovLayers(const host::RenderSession& session);

}  // namespace principled::tools
