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

}  // namespace

std::vector<glm::vec3> authoredCornerNormals(const SceneDelegate* delegate, const Path& id,
                                             size_t pointCount, size_t faceCount,
                                             const std::vector<glm::uvec3>& corners,
                                             const std::vector<glm::uvec3>& triangles,
                                             const std::vector<int>& triangleFace) {
    std::optional<Interpolation> interp;
    for (Interpolation i : {Interpolation::Constant, Interpolation::Uniform, Interpolation::Varying,
                            Interpolation::Vertex, Interpolation::FaceVarying}) {
        for (const auto& d : delegate->getPrimvarDescriptors(id, i))
            if (d.name == tokens::normals()) interp = i;
    }
    if (!interp) return {};
    std::vector<int> indices;
    Value v = delegate->getIndexedPrimvar(id, tokens::normals(), &indices);
    const auto* values = getIf<std::vector<glm::vec3>>(v);
    if (!values || values->empty()) return {};
    size_t cornerCount = 0;
    for (const auto& c : corners) cornerCount = std::max<size_t>(cornerCount, c.z + 1);
    // Element count the interpolation expects.
    size_t expected = 1;
    switch (*interp) {
        case Interpolation::Uniform: expected = faceCount; break;
        case Interpolation::Varying:
        case Interpolation::Vertex: expected = pointCount; break;
        case Interpolation::FaceVarying: expected = cornerCount; break;
        default: expected = 1;
    }
    auto lookup = [&](size_t element, glm::vec3* out) {
        size_t i = element;
        if (!indices.empty()) {
            if (element >= indices.size() || indices[element] < 0) return false;
            i = static_cast<size_t>(indices[element]);
        }
        if (i >= values->size()) return false;
        *out = safeNormalize((*values)[i]);
        return true;
    };
    size_t available = indices.empty() ? values->size() : indices.size();
    if (*interp != Interpolation::FaceVarying && available < expected) return {};
    std::vector<glm::vec3> out(triangles.size() * 3);
    for (size_t t = 0; t < triangles.size(); ++t) {
        for (int k = 0; k < 3; ++k) {
            size_t element = 0;
            switch (*interp) {
                case Interpolation::Uniform: element = triangleFace[t]; break;
                case Interpolation::Varying:
                case Interpolation::Vertex: element = triangles[t][k]; break;
                case Interpolation::FaceVarying: element = corners[t][k]; break;
                default: element = 0;
            }
            if (!lookup(element, &out[3 * t + k])) return {};
        }
    }
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
    if (auto* a = getIf<std::vector<glm::vec3>>(v); a && !a->empty()) return (*a)[0];
    if (auto c = getVec3(v)) return *c;
    return std::nullopt;
}

}  // namespace principled::embree
