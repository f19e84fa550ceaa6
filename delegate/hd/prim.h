// SPDX-License-Identifier: Apache-2.0
// The three prim families of a render index: rprims (geometry), sprims (state: camera,
// material, lights) and bprims (buffers). Render delegates derive concrete prims from these.
#pragma once

#include "delegate/hd/dirtyBits.h"
#include "delegate/hd/path.h"

namespace principled::hd {

class SceneDelegate;

/// Opaque per-delegate state handed to every prim's sync (Hydra's HdRenderParam).
class RenderParam {
public:
    virtual ~RenderParam() = default;
    /// A problem with user data found during sync: the prim keeps a fallback and the message
    /// reaches the host (the render delegate's param collects them; the base drops them).
    virtual void warn(const Path& /*id*/, const std::string& /*message*/) {}
};

/// Geometry. sync() runs in parallel with other rprims: touch only this prim's own state and
/// thread-safe delegate state.
class Rprim {
public:
    explicit Rprim(const Path& id) : _id(id) {}
    virtual ~Rprim() = default;
    const Path& id() const { return _id; }
    /// A small integer unique within the render index (the primId AOV); assigned at insert.
    int primId() const { return _primId; }
    void setPrimId(int id) { _primId = id; }

    virtual DirtyBits initialDirtyBits() const { return RprimDirty::AllDirty; }
    /// Pulls what *dirtyBits names and clears the bits it handled.
    virtual void sync(SceneDelegate* delegate, RenderParam* param, DirtyBits* dirtyBits) = 0;
    /// Releases delegate resources before destruction.
    virtual void finalize(RenderParam* param) { (void)param; }

private:
    Path _id;
    int _primId = -1;
};

/// State prims: cameras, materials, lights. Synced serially, before rprims.
class Sprim {
public:
    explicit Sprim(const Path& id) : _id(id) {}
    virtual ~Sprim() = default;
    const Path& id() const { return _id; }
    virtual DirtyBits initialDirtyBits() const { return SprimDirty::AllDirty; }
    virtual void sync(SceneDelegate* delegate, RenderParam* param, DirtyBits* dirtyBits) = 0;
    virtual void finalize(RenderParam* param) { (void)param; }

private:
    Path _id;
};

/// Buffer prims (render buffers). Synced first.
class Bprim {
public:
    explicit Bprim(const Path& id) : _id(id) {}
    virtual ~Bprim() = default;
    const Path& id() const { return _id; }
    virtual DirtyBits initialDirtyBits() const { return BprimDirty::AllDirty; }
    virtual void sync(SceneDelegate* delegate, RenderParam* param, DirtyBits* dirtyBits) = 0;
    virtual void finalize(RenderParam* param) { (void)param; }

private:
    Path _id;
};

}  // namespace principled::hd
