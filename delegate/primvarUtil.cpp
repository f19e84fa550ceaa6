// SPDX-License-Identifier: Apache-2.0
#include "delegate/primvarUtil.h"

#include <cmath>

#include "delegate/hd/sceneDelegate.h"
#include "delegate/hd/tokens.h"

namespace principled::embree {

using namespace hd;

namespace {

glm::vec3 safeNormalize(const glm::vec3& n) {
    float l = glm::length(n);
    return (l > 0.0f && std::isfinite(l)) ? n / l : glm::vec3(0.0f);
}

template <typename V, int N>
void flattenVec(const std::vector<V>& a, std::vector<float>* out) {
    out->resize(a.size() * N);
    for (size_t i = 0; i < a.size(); ++i)
        for (int c = 0; c < N; ++c) (*out)[i * N + c] = a[i][c];
}

}  // namespace

bool flattenFloats(const Value& v, std::vector<float>* out, int* components) {
    if (auto* a = getIf<std::vector<float>>(v)) {
        *out = *a;
        *components = 1;
    } else if (auto* a2 = getIf<std::vector<glm::vec2>>(v)) {
        flattenVec<glm::vec2, 2>(*a2, out);
        *components = 2;
    } else if (auto* a3 = getIf<std::vector<glm::vec3>>(v)) {
        flattenVec<glm::vec3, 3>(*a3, out);
        *components = 3;
    } else if (auto* a4 = getIf<std::vector<glm::vec4>>(v)) {
        flattenVec<glm::vec4, 4>(*a4, out);
        *components = 4;
    } else if (auto* ai = getIf<std::vector<int>>(v)) {
        out->assign(ai->begin(), ai->end());
        *components = 1;
    } else if (auto f = getFloat(v)) {
        *out = {*f};
        *components = 1;
    } else if (auto* v2 = getIf<glm::vec2>(v)) {
        *out = {v2->x, v2->y};
        *components = 2;
    } else if (auto* v3 = getIf<glm::vec3>(v)) {
        *out = {v3->x, v3->y, v3->z};
        *components = 3;
    } else if (auto* v4 = getIf<glm::vec4>(v)) {
        *out = {v4->x, v4->y, v4->z, v4->w};
        *components = 4;
    } else {
        return false;
    }
    return true;
}

bool expandToCorners(const std::vector<float>& values, int components, const std::vector<int>& indices,
                     Interpolation interp, const CornerLayout& layout, std::vector<float>* out) {
    if (components <= 0 || values.empty()) return false;
    size_t valueCount = values.size() / size_t(components);
    size_t expected = 1;
    switch (interp) {
        case Interpolation::Uniform: expected = layout.faceCount; break;
        case Interpolation::Varying:
        case Interpolation::Vertex: expected = layout.pointCount; break;
        case Interpolation::FaceVarying: expected = layout.faceVertexCount; break;
        default: expected = 1;
    }
    size_t available = indices.empty() ? valueCount : indices.size();
    if (available < expected) return false;
    const auto& tris = *layout.triangles;
    out->resize(tris.size() * 3 * size_t(components));
    for (size_t t = 0; t < tris.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            size_t element = 0;
            switch (interp) {
                case Interpolation::Uniform: element = size_t((*layout.triangleFace)[t]); break;
                case Interpolation::Varying:
                case Interpolation::Vertex: element = tris[t][k]; break;
                case Interpolation::FaceVarying: element = (*layout.corners)[t][k]; break;
                default: element = 0;
            }
            size_t i = element;
            if (!indices.empty()) {
                if (element >= indices.size() || indices[element] < 0) return false;
                i = size_t(indices[element]);
            }
            if (i >= valueCount) return false;
            for (int c = 0; c < components; ++c)
                (*out)[(3 * t + k) * components + c] = values[i * components + c];
        }
    return true;
}

std::optional<Interpolation> primvarInterpolation(const SceneDelegate* delegate, const Path& id,
                                                  const Token& name) {
    for (Interpolation i : {Interpolation::Constant, Interpolation::Uniform, Interpolation::Varying,
                            Interpolation::Vertex, Interpolation::FaceVarying})
        for (const auto& d : delegate->getPrimvarDescriptors(id, i))
            if (d.name == name) return i;
    return std::nullopt;
}

std::vector<glm::vec3> authoredCornerNormals(const SceneDelegate* delegate, const Path& id,
                                             const CornerLayout& layout, std::string* problem) {
    auto interp = primvarInterpolation(delegate, id, tokens::normals());
    if (!interp) return {};
    std::vector<int> indices;
    Value v = delegate->getIndexedPrimvar(id, tokens::normals(), &indices);
    std::vector<float> flat, corners;
    int components = 0;
    if (!flattenFloats(v, &flat, &components) || components != 3) {
        if (problem) *problem = "normals are not 3-component vectors; ignored (faceted shading)";
        return {};
    }
    if (!expandToCorners(flat, 3, indices, *interp, layout, &corners)) {
        if (problem) {
            const size_t values = indices.empty() ? flat.size() / 3 : indices.size();
            const size_t want = *interp == Interpolation::Vertex || *interp == Interpolation::Varying ? layout.pointCount
                                : *interp == Interpolation::Uniform                                  ? layout.faceCount
                                : *interp == Interpolation::FaceVarying                              ? layout.faceVertexCount
                                                                                                     : 1;
            *problem = "normals have " + std::to_string(values) + (indices.empty() ? " values" : " indices") +
                       " where their interpolation needs " + std::to_string(want) +
                       (indices.empty() ? "" : " (or an index is out of range)") + "; ignored (faceted shading)";
        }
        return {};
    }
    std::vector<glm::vec3> out(corners.size() / 3);
    for (size_t i = 0; i < out.size(); ++i)
        out[i] = safeNormalize({corners[3 * i], corners[3 * i + 1], corners[3 * i + 2]});
    return out;
}

std::vector<glm::vec3> smoothCornerNormals(const std::vector<glm::vec3>& points,
                                           const std::vector<glm::uvec3>& triangles) {
    std::vector<glm::vec3> vn(points.size(), glm::vec3(0.0f));
    for (const auto& t : triangles) {
        // Unnormalised cross product: area weighting.
        glm::vec3 n = glm::cross(points[t.y] - points[t.x], points[t.z] - points[t.x]);
        vn[t.x] += n;
        vn[t.y] += n;
        vn[t.z] += n;
    }
    std::vector<glm::vec3> out(triangles.size() * 3);
    for (size_t t = 0; t < triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) out[3 * t + k] = safeNormalize(vn[triangles[t][k]]);
    return out;
}

std::optional<glm::vec3> constantDisplayColor(const SceneDelegate* delegate, const Path& id) {
    Value v = delegate->get(id, tokens::displayColor());
    std::optional<glm::vec3> c;
    // One value: the constant colour. More are per-element values, which the material reads at
    // each hit (or, when they are invalid and ignored, nobody: their first is no colour of the
    // whole prim).
    if (auto* a = getIf<std::vector<glm::vec3>>(v); a && a->size() == 1)
        c = (*a)[0];
    else
        c = getVec3(v);
    // An authored NaN or infinity reads as 0 (a NaN base colour turned every sample invalid).
    if (c)
        for (int i = 0; i < 3; ++i)
            if (!std::isfinite((*c)[i])) (*c)[i] = 0.0f;
    return c;
}

}  // namespace principled::embree
