// SPDX-License-Identifier: Apache-2.0
// EmbreeDevice: owns the RTCDevice and routes Embree's errors to stderr with their names.
#pragma once

#include <embree3/rtcore.h>

namespace principled::embree {

class EmbreeDevice {
public:
    EmbreeDevice();
    ~EmbreeDevice();
    EmbreeDevice(const EmbreeDevice&) = delete;
    EmbreeDevice& operator=(const EmbreeDevice&) = delete;
    RTCDevice get() const { return _device; }

private:
    RTCDevice _device = nullptr;
};

}  // namespace principled::embree
