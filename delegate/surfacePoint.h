// SPDX-License-Identifier: Apache-2.0
// SurfacePoint: a point on a triangle of a GeometryRecord as materials see it, with primvars
// interpolated by its barycentrics. The integrator shades hits through it; mesh lights with a
// textured emission evaluate their material at sampled points through it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "delegate/sceneData.h"
#include "delegate/shading/shadingContext.h"

namespace principled::embree {

class SurfacePoint final : public shading::ShadingContext {
public:
    /// Triangle (or Embree primitive) `triangle` of `record`; u, v weight its corners 1 and 2;
    /// `instance`: the PointInstancer placement hit (its per-instance primvars), if any.
    SurfacePoint(const GeometryRecord& record, unsigned triangle, float u, float v,
                 const InstanceRecord* instance = nullptr)
        : _record(record), _triangle(triangle), _u(u), _v(v), _instance(instance) {}

    /// The prototype's own varying primvar of that name, else the instance's value (one per
    /// instance, from the instancer), else the prototype's constant one, else the geometry's
    /// points or normals.
    bool primvar(const hd::Token& name, int components, float* out) const override {
        const PrimvarChannel* ch = _record.primvar(name);
        if ((!ch || ch->constant) && instancePrimvar(name, components, out)) return true;
        if (!ch) return geometryPrimvar(name, components, out);
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
    bool instancePrimvar(const hd::Token& name, int components, float* out) const {
        if (!_instance || !_instance->primvars || _instance->instanceIndex < 0) return false;
        for (const PrimvarChannel& ch : *_instance->primvars) {
            if (ch.name != name) continue;
            const size_t at = size_t(_instance->instanceIndex) * size_t(ch.components);
            if (at + size_t(ch.components) > ch.data.size()) return false;
            for (int c = 0; c < components; ++c) out[c] = c < ch.components ? ch.data[at + size_t(c)] : 0.0f;
            return true;
        }
        return false;
    }

    /// "points" and "normals" read by a primvar reader: the object-space position and the
    /// interpolated (else geometric) normal of a triangle mesh at the point, as Hydra serves
    /// them to materials.
    bool geometryPrimvar(const hd::Token& name, int components, float* out) const {
        static const hd::Token kPoints("points"), kNormals("normals");
        if (_record.kind != GeometryRecord::Kind::Triangles || _triangle >= _record.triangles.size()) return false;
        const bool points = name == kPoints;
        if (!points && name != kNormals) return false;
        const glm::uvec3& t = _record.triangles[_triangle];
        const float w0 = 1.0f - _u - _v;
        glm::vec3 v;
        if (points) {
            v = w0 * _record.points[t.x] + _u * _record.points[t.y] + _v * _record.points[t.z];
        } else if (!_record.cornerNormals.empty()) {
            const glm::vec3* n = &_record.cornerNormals[3 * size_t(_triangle)];
            v = w0 * n[0] + _u * n[1] + _v * n[2];
        } else if (!_record.vertexNormals.empty()) {
            v = w0 * _record.vertexNormals[t.x] + _u * _record.vertexNormals[t.y] + _v * _record.vertexNormals[t.z];
        } else {
            v = glm::cross(_record.points[t.y] - _record.points[t.x], _record.points[t.z] - _record.points[t.x]);
        }
        if (!points) {
            const float l = glm::length(v);
            v = l > 0.0f && std::isfinite(l) ? v / l : glm::vec3(0.0f, 0.0f, 1.0f);
        }
        for (int c = 0; c < components; ++c) out[c] = c < 3 ? v[c] : 0.0f;
        return true;
    }

    const GeometryRecord& _record;
    unsigned _triangle;
    float _u, _v;
    const InstanceRecord* _instance = nullptr;
};

}  // namespace principled::embree
