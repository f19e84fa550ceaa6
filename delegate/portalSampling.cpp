// SPDX-License-Identifier: Apache-2.0
#include "delegate/portalSampling.h"

#include <algorithm>
#include <cmath>

#include "delegate/sphericalRectangle.h"

namespace principled::embree {

PortalSet::PortalSet(std::vector<Portal> portals) {
    for (Portal& q : portals)
        if (q.area > 0.0f && std::isfinite(q.area)) _portals.push_back(q);
}

float PortalSet::weightOf(const Portal& q, const glm::vec3& p) const {
    // p must lie on the side the light goes to; the weight is the solid angle the portal
    // subtends there.
    if (!(glm::dot(p - q.center, q.normal) > 0.0f)) return 0.0f;
    const SphericalRectangle r(p, q.center - q.axisU - q.axisV, 2.0f * q.axisU, 2.0f * q.axisV);
    return r.valid() ? float(r.solidAngle()) : 0.0f;
}

float PortalSet::weight(const glm::vec3& p) const {
    float sum = 0.0f;
    for (const Portal& q : _portals) sum += weightOf(q, p);
    return sum;
}

bool PortalSet::sample(const glm::vec3& p, const glm::vec2& u, glm::vec3* wi, float* pdf) const {
    const float total = weight(p);
    if (!(total > 0.0f)) return false;
    const Portal* chosen = nullptr;
    float target = u.x * total, sum = 0.0f, before = 0.0f, width = 0.0f;
    for (const Portal& q : _portals) {
        const float w = weightOf(q, p);
        if (w <= 0.0f) continue;
        chosen = &q;  // the last with weight, should rounding leave target at the sum
        before = sum;
        width = w;
        sum += w;
        if (target < sum) break;
    }
    if (!chosen) return false;
    // u.x within the chosen portal's share of [0, 1), rescaled: the point's first coordinate.
    const float s = std::clamp((target - before) / width, 0.0f, 0.99999994f);
    const SphericalRectangle r(p, chosen->center - chosen->axisU - chosen->axisV, 2.0f * chosen->axisU,
                               2.0f * chosen->axisV);
    if (!r.valid()) return false;
    const glm::vec3 x = r.sample(s, u.y);
    const glm::vec3 d = x - p;
    const float len = glm::length(d);
    if (!(len > 0.0f) || !std::isfinite(len)) return false;
    *wi = d / len;
    *pdf = this->pdf(p, *wi);
    return *pdf > 0.0f && std::isfinite(*pdf);
}

float PortalSet::pdf(const glm::vec3& p, const glm::vec3& wi) const {
    const float total = weight(p);
    if (!(total > 0.0f)) return 0.0f;
    float sum = 0.0f;
    for (const Portal& q : _portals) {
        const float w = weightOf(q, p);
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
        sum += (w / total) * (1.0f / w);  // uniform in the portal's solid angle w
    }
    return std::isfinite(sum) ? sum : 0.0f;
}

}  // namespace principled::embree
