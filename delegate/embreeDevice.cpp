// SPDX-License-Identifier: Apache-2.0
#include "delegate/embreeDevice.h"

#include <cstdio>
#include <stdexcept>

namespace principled::embree {
namespace {

const char* errorName(RTCError e) {
    switch (e) {
        case RTC_ERROR_NONE: return "RTC_ERROR_NONE";
        case RTC_ERROR_UNKNOWN: return "RTC_ERROR_UNKNOWN";
        case RTC_ERROR_INVALID_ARGUMENT: return "RTC_ERROR_INVALID_ARGUMENT";
        case RTC_ERROR_INVALID_OPERATION: return "RTC_ERROR_INVALID_OPERATION";
        case RTC_ERROR_OUT_OF_MEMORY: return "RTC_ERROR_OUT_OF_MEMORY";
        case RTC_ERROR_UNSUPPORTED_CPU: return "RTC_ERROR_UNSUPPORTED_CPU";
        case RTC_ERROR_CANCELLED: return "RTC_ERROR_CANCELLED";
    }
    return "RTC_ERROR_?";
}

void onError(void*, RTCError code, const char* message) {
    std::fprintf(stderr, "principled: embree: %s: %s\n", errorName(code), message ? message : "");
}

}  // namespace

EmbreeDevice::EmbreeDevice() {
    _device = rtcNewDevice(nullptr);
    if (!_device) throw std::runtime_error("embree: cannot create a device (rtcNewDevice failed)");
    rtcSetDeviceErrorFunction(_device, onError, nullptr);
}

EmbreeDevice::~EmbreeDevice() { rtcReleaseDevice(_device); }

}  // namespace principled::embree
