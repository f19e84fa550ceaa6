// SPDX-License-Identifier: Apache-2.0
// RenderPass: renders the render index's prims through a camera into bound AOV buffers.
#pragma once

#include <glm/glm.hpp>

#include "delegate/hd/aov.h"
#include "delegate/hd/framing.h"
#include "delegate/hd/path.h"

namespace principled::hd {

class RenderIndex;

/// What a pass renders: the camera prim, the image size and the AOV bindings.
struct RenderPassState {
    Path cameraId;  ///< a camera sprim in the render index
    int width = 0;
    int height = 0;
    AovBindingVector aovBindings;
    Framing framing;  ///< conform policy, pixel aspect ratio and data window (UsdRender)
};

/// One call to execute() runs one progressive iteration (blocking; parallel inside) and leaves
/// the bound buffers resolved. A host calls it until isConverged(). A pass restarts its
/// accumulation by itself when the scene, the settings, the camera or the bindings changed.
class RenderPass {
public:
    explicit RenderPass(RenderIndex* index) : _index(index) {}
    virtual ~RenderPass() = default;
    virtual void execute(const RenderPassState& state) = 0;
    virtual bool isConverged() const = 0;
    RenderIndex* renderIndex() const { return _index; }

private:
    RenderIndex* _index;
};

}  // namespace principled::hd
