// SPDX-License-Identifier: Apache-2.0
// EmbreeInstance: one rprim's bottom-level scene (its own BVH) and the instance geometry that
// places it in the top-level scene. A transform edit touches only the instance.
#pragma once

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

namespace principled::embree {

class EmbreeInstance {
public:
    EmbreeInstance() = default;
    ~EmbreeInstance() { release(); }
    EmbreeInstance(const EmbreeInstance&) = delete;
    EmbreeInstance& operator=(const EmbreeInstance&) = delete;

    /// Replaces the bottom-level geometry (takes ownership of geom; commits it and the BLAS).
    /// The first call also creates and attaches the instance to the top-level scene.
    void setGeometry(RTCDevice device, RTCScene top, RTCGeometry geom, void* userData);
    void setTransform(const glm::mat4& objectToWorld);
    void setEnabled(bool enabled);
    /// Detaches and releases everything.
    void release();

    unsigned instanceId() const { return _instId; }
    /// The bottom-level scene (PointInstancer instances share it), nullptr if none.
    RTCScene blas() const { return _blas; }
    bool valid() const { return _blas != nullptr; }

private:
    RTCScene _top = nullptr;
    RTCScene _blas = nullptr;
    RTCGeometry _instance = nullptr;
    unsigned _instId = RTC_INVALID_GEOMETRY_ID;
};

}  // namespace principled::embree
