// SPDX-License-Identifier: Apache-2.0
#include "delegate/portalSampling.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "delegate/sphericalRectangle.h"

namespace principled::embree {

namespace {

// Distinguishes portal sets in the per-thread view below (an address may be reused).
std::atomic<uint64_t> nextSetId{1};

}  // namespace

// The portals as seen from one point, kept per thread: a vertex's NEE sample, its mixture density
// and the MIS weight of the BSDF ray that leaves it all ask about the same point, and each
// spherical rectangle costs four arc cosines to set up.
struct PortalView {
    uint64_t set = 0;
    glm::vec3 p{0.0f};
    float total = 0.0f;
    std::vector<float> weights;
    std::vector<SphericalRectangle> rects;
};

PortalSet::PortalSet(std::vector<Portal> portals) : _id(nextSetId.fetch_add(1)) {
    for (Portal& q : portals)
        if (q.area > 0.0f && std::isfinite(q.area)) _portals.push_back(q);
}

const PortalView& PortalSet::view(const glm::vec3& p) const {
    thread_local PortalView v;
    if (v.set == _id && v.p == p) return v;
    v.set = _id;
    v.p = p;
    v.total = 0.0f;
    v.weights.clear();
    v.rects.clear();
    for (const Portal& q : _portals) {
        // p must lie on the side the light goes to; the weight is the solid angle there.
        if (glm::dot(p - q.center, q.normal) > 0.0f) {
            v.rects.emplace_back(p, q.center - q.axisU - q.axisV, 2.0f * q.axisU, 2.0f * q.axisV);
            v.weights.push_back(v.rects.back().valid() ? float(v.rects.back().solidAngle()) : 0.0f);
        } else {
            v.rects.emplace_back();
            v.weights.push_back(0.0f);
        }
        v.total += v.weights.back();
    }
    return v;
}

float PortalSet::weight(const glm::vec3& p) const { return view(p).total; }

bool PortalSet::sample(const glm::vec3& p, const glm::vec2& u, glm::vec3* wi, float* pdf) const {
    const PortalView& v = view(p);
    if (!(v.total > 0.0f)) return false;
    size_t chosen = _portals.size();
    float target = u.x * v.total, sum = 0.0f, before = 0.0f, width = 0.0f;
    for (size_t k = 0; k < _portals.size(); ++k) {
        const float w = v.weights[k];
        if (w <= 0.0f) continue;
        chosen = k;  // the last with weight, should rounding leave target at the sum
        before = sum;
        width = w;
        sum += w;
        if (target < sum) break;
    }
    if (chosen == _portals.size()) return false;
    // u.x within the chosen portal's share of [0, 1), rescaled: the point's first coordinate.
    const float s = std::clamp((target - before) / width, 0.0f, 0.99999994f);
    const glm::vec3 x = v.rects[chosen].sample(s, u.y);
    const glm::vec3 d = x - p;
    const float len = glm::length(d);
    if (!(len > 0.0f) || !std::isfinite(len)) return false;
    *wi = d / len;
    *pdf = this->pdf(p, *wi);
    return *pdf > 0.0f && std::isfinite(*pdf);
}

float PortalSet::pdf(const glm::vec3& p, const glm::vec3& wi) const {
    const PortalView& v = view(p);
    if (!(v.total > 0.0f)) return 0.0f;
    float sum = 0.0f;
    for (size_t k = 0; k < _portals.size(); ++k) {
        const Portal& q = _portals[k];
        const float w = v.weights[k];
        if (w <= 0.0f) continue;
        // Where the ray from p along wi crosses the portal's plane, against the light's travel.
        const float cosine = glm::dot(wi, q.normal);
        if (!(cosine < 0.0f)) continue;
        const float t = glm::dot(q.center - p, q.normal) / cosine;
        if (!(t > 0.0f)) continue;
        const glm::vec3 r = p + t * wi - q.center;
        const float a = glm::dot(r, q.axisU) / glm::dot(q.axisU, q.axisU);
        const float b = glm::dot(r, q.axisV) / glm::dot(q.axisV, q.axisV);
        if (std::abs(a) > 1.0f || std::abs(b) > 1.0f) continue;
        sum += (w / v.total) * (1.0f / w);  // uniform in the portal's solid angle w
    }
    return std::isfinite(sum) ? sum : 0.0f;
}

}  // namespace principled::embree
