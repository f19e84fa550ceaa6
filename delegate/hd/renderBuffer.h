// SPDX-License-Identifier: Apache-2.0
// RenderBuffer: a 2D image a render pass writes into, one per AOV.
#pragma once

#include "delegate/hd/aov.h"
#include "delegate/hd/prim.h"

namespace principled::hd {

/// A render buffer. allocate() sizes it; map() exposes the resolved pixels (row-major, top
/// row first, componentCount(format()) values per pixel, float or int32 by format).
class RenderBuffer : public Bprim {
public:
    using Bprim::Bprim;

    virtual bool allocate(int width, int height, Format format, bool multiSampled) = 0;
    virtual int width() const = 0;
    virtual int height() const = 0;
    virtual Format format() const = 0;
    virtual bool isMultiSampled() const = 0;
    /// Resolved pixel data; valid until the next write or allocate.
    virtual const void* map() = 0;
    virtual void unmap() {}
    /// Brings the resolved image up to date with the accumulated samples.
    virtual void resolve() = 0;
    virtual bool isConverged() const = 0;

    void sync(SceneDelegate*, RenderParam*, DirtyBits* bits) override { *bits = 0; }
};

}  // namespace principled::hd
