// SPDX-License-Identifier: Apache-2.0
// AOVs: pixel formats, AOV descriptors and the bindings of AOV names to render buffers.
#pragma once

#include <vector>

#include "delegate/hd/token.h"
#include "delegate/hd/value.h"

namespace principled::hd {

class RenderBuffer;

enum class Format { Invalid, Float32, Float32Vec2, Float32Vec3, Float32Vec4, Int32 };

inline int componentCount(Format f) {
    switch (f) {
        case Format::Float32: return 1;
        case Format::Float32Vec2: return 2;
        case Format::Float32Vec3: return 3;
        case Format::Float32Vec4: return 4;
        case Format::Int32: return 1;
        default: return 0;
    }
}

/// How an AOV is stored: format, whether samples are averaged (multiSampled) or the first
/// sample wins (IDs, depth), and the value of pixels no ray hit.
struct AovDescriptor {
    Format format = Format::Invalid;
    bool multiSampled = true;
    Value clearValue;
};

/// Binds an AOV name to a render buffer the host owns.
struct AovBinding {
    Token aovName;
    RenderBuffer* renderBuffer = nullptr;
};
using AovBindingVector = std::vector<AovBinding>;

}  // namespace principled::hd
