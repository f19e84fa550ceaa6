// SPDX-License-Identifier: Apache-2.0
// SurfacePoint: a point on a triangle of a GeometryRecord as materials see it, with primvars
// interpolated by its barycentrics. The integrator shades hits through it; mesh lights with a
// textured emission evaluate their material at sampled points through it.
#pragma once

#include <algorithm>
#include <cstddef>

#include "delegate/sceneData.h"
#include "delegate/shading/shadingContext.h"

namespace principled::embree {

class SurfacePoint final : public shading::ShadingContext {
public:
    /// Triangle (or Embree primitive) `triangle` of `record`; u, v weight its corners 1 and 2.
    SurfacePoint(const GeometryRecord& record, unsigned triangle, float u, float v)
        : _record(record), _triangle(triangle), _u(u), _v(v) {}

    bool primvar(const hd::Token& name, int components, float* out) const override {
        const PrimvarChannel* ch = _record.primvar(name);
        if (!ch) return false;
        int n = std::min(components, ch->components);
        for (int c = 0; c < components; ++c) out[c] = 0.0f;
        if (ch->constant || ch->perPrimitive) {
            const float* d = &ch->data[ch->constant ? 0 : size_t(_triangle) * ch->components];
            for (int c = 0; c < n; ++c) out[c] = d[c];
            return true;
        }
        const float* d0 = _record.cornerValue(*ch, _triangle, 0);
        const float* d1 = _record.cornerValue(*ch, _triangle, 1);
        const float* d2 = _record.cornerValue(*ch, _triangle, 2);
        float w0 = 1.0f - _u - _v;
        for (int c = 0; c < n; ++c) out[c] = w0 * d0[c] + _u * d1[c] + _v * d2[c];
        return true;
    }

private:
    const GeometryRecord& _record;
    unsigned _triangle;
    float _u, _v;
};

}  // namespace principled::embree
