// SPDX-License-Identifier: Apache-2.0
#include "delegate/lightTree.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace principled::embree {

LightTree::LightTree(std::vector<Item> items, float sceneRadius2) : _sceneRadius2(sceneRadius2) {
    if (items.empty()) return;
    uint32_t maxLight = 0;
    for (const Item& it : items) maxLight = std::max(maxLight, it.light);
    _leafOf.assign(size_t(maxLight) + 1, -1);
    _nodes.reserve(2 * items.size() - 1);  // no reallocation: build() keeps node references
    _nodes.push_back(Node{});
    _nodes[0].parent = -1;
    build(items, 0, items.size(), 0);
}

void LightTree::build(std::vector<Item>& items, size_t begin, size_t end, int32_t self) {
    // `self` is allocated (and its parent set) by the caller: siblings side by side.
    if (end - begin == 1) {
        const Item& it = items[begin];
        Node& n = _nodes[size_t(self)];
        n.center = it.center;
        n.radius2 = it.radius2;
        const float r = std::sqrt(it.radius2);
        n.lo = it.center - r;
        n.hi = it.center + r;
        n.floor2 = it.radius2;  // inner nodes: the least of their lights'

        n.power = it.power;
        n.cone = it.cone;
        n.left = -1;
        n.light = it.light;
        _leafOf[it.light] = self;
        return;
    }
    // Split at the median along the longest axis of the centres' bounds.
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (size_t i = begin; i < end; ++i) {
        lo = glm::min(lo, items[i].center);
        hi = glm::max(hi, items[i].center);
    }
    const glm::vec3 extent = hi - lo;
    const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
    const size_t mid = begin + (end - begin) / 2;
    std::nth_element(items.begin() + std::ptrdiff_t(begin), items.begin() + std::ptrdiff_t(mid),
                     items.begin() + std::ptrdiff_t(end),
                     [axis](const Item& a, const Item& b) { return a.center[axis] < b.center[axis]; });
    const int32_t left = int32_t(_nodes.size());
    _nodes.resize(_nodes.size() + 2);
    _nodes[size_t(left)].parent = _nodes[size_t(left) + 1].parent = self;
    build(items, begin, mid, left);
    build(items, mid, end, left + 1);
    // The cluster's box holds both children's; its sphere is around the box.
    const Node& a = _nodes[size_t(left)];
    const Node& b = _nodes[size_t(left) + 1];
    Node& n = _nodes[size_t(self)];
    n.lo = glm::min(a.lo, b.lo);
    n.hi = glm::max(a.hi, b.hi);
    n.center = 0.5f * (n.lo + n.hi);
    const float diagonal2 = glm::dot(n.hi - n.lo, n.hi - n.lo);
    n.radius2 = 0.25f * diagonal2;
    n.floor2 = std::min(a.floor2, b.floor2);  // > 0: every light's radius^2 is
    n.power = _nodes[size_t(left)].power + _nodes[size_t(left) + 1].power;
    n.cone = merge(a.cone, b.cone);
    n.left = left;
    n.light = 0;
}

LightTree::Cone LightTree::merge(const Cone& a, const Cone& b) {
    if (a.all()) return a;
    if (b.all()) return b;
    Cone out;
    out.cosThetaE = std::min(a.cosThetaE, b.cosThetaE);  // the wider emission spread
    const float thetaA = std::acos(std::clamp(a.cosThetaO, -1.0f, 1.0f));
    const float thetaB = std::acos(std::clamp(b.cosThetaO, -1.0f, 1.0f));
    const float thetaD = std::acos(std::clamp(glm::dot(a.axis, b.axis), -1.0f, 1.0f));
    constexpr float kPi = 3.14159265358979323846f;
    // One cone holds the other (with the slack below: acos cannot tell axes within ~2e-4 apart).
    if (std::min(thetaD + thetaB, kPi) <= thetaA)
        return Cone{a.axis, std::cos(std::min(thetaA + 1e-3f, kPi)), out.cosThetaE};
    if (std::min(thetaD + thetaA, kPi) <= thetaB)
        return Cone{b.axis, std::cos(std::min(thetaB + 1e-3f, kPi)), out.cosThetaE};
    const float thetaO = 0.5f * (thetaA + thetaD + thetaB);
    if (thetaO >= kPi) return Cone{a.axis, -1.0f, out.cosThetaE};
    // Turn a's axis toward b's by thetaO - thetaA (Rodrigues, about a x b).
    const float turn = thetaO - thetaA;
    const glm::vec3 w = glm::cross(a.axis, b.axis);
    const float lw = glm::length(w);
    if (!(lw > 1e-7f)) return Cone{a.axis, -1.0f, out.cosThetaE};  // opposite axes (or rounding)
    const glm::vec3 k = w / lw;
    const glm::vec3 axis = a.axis * std::cos(turn) + glm::cross(k, a.axis) * std::sin(turn) +
                           k * glm::dot(k, a.axis) * (1.0f - std::cos(turn));
    // A little slack for the rounding of the rotation: the merged cone must hold both.
    out.axis = glm::normalize(axis);
    out.cosThetaO = std::cos(std::min(thetaO + 1e-3f, kPi));
    return out;
}

float LightTree::orientation(const Cone& k, const glm::vec3& c, float r2, const glm::vec3& p) {
    if (k.all()) return 1.0f;
    const glm::vec3 v = p - c;
    const float d2 = glm::dot(v, v);
    if (!(d2 > r2)) return 1.0f;  // p inside the bounding sphere: any direction may reach it
    auto sinOf = [](float cosine) { return std::sqrt(std::max(0.0f, 1.0f - cosine * cosine)); };
    const float cosW = glm::dot(k.axis, v) / std::sqrt(d2);
    // theta_x = max(0, theta_w - theta_o), then theta' = max(0, theta_x - theta_u), sin theta_u = r / d.
    const float cosX = cosW >= k.cosThetaO ? 1.0f : cosW * k.cosThetaO + sinOf(cosW) * sinOf(k.cosThetaO);
    const float cosU = std::sqrt(std::max(0.0f, 1.0f - r2 / d2));
    const float cosP = cosX >= cosU ? 1.0f : cosX * cosU + sinOf(cosX) * std::sqrt(r2 / d2);
    // Inside the cone but more than 90 degrees off (a spot cone wider than a hemisphere): a
    // small positive weight, not 0, so the light stays reachable.
    return cosP > k.cosThetaE ? std::max(cosP, 1e-3f) : 0.0f;
}

bool LightTree::behind(const Node& n, const glm::vec3& p, const glm::vec3& nrm) {
    // The box's farthest extent along nrm (centre plus half extents weighed by |nrm|).
    const glm::vec3 c = 0.5f * (n.lo + n.hi), e = 0.5f * (n.hi - n.lo);
    return glm::dot(c - p, nrm) + glm::dot(e, glm::abs(nrm)) < 0.0f;
}

float LightTree::sphereWeight(const Node& n, const glm::vec3& p, const glm::vec3& nrm) const {
    if (behind(n, p, nrm)) return 0.0f;
    const float facing = orientation(n.cone, n.center, n.radius2, p);
    if (!(facing > 0.0f)) return 0.0f;
    const glm::vec3 d = n.center - p;
    const float w = n.power * (_sceneRadius2 / std::max(glm::dot(d, d), n.radius2)) * facing;
    return std::isfinite(w) ? w : n.power;
}

float LightTree::weight(const Node& n, const glm::vec3& p, const glm::vec3& nrm) const {
    if (behind(n, p, nrm)) return 0.0f;
    const float facing = orientation(n.cone, n.center, n.radius2, p);
    if (!(facing > 0.0f)) return 0.0f;
    const glm::vec3 d = glm::max(glm::max(n.lo - p, p - n.hi), glm::vec3(0.0f));  // to the box
    const float w = n.power * (_sceneRadius2 / std::max(glm::dot(d, d), n.floor2)) * facing;
    return std::isfinite(w) ? w : n.power;
}

bool LightTree::segmentMeetsBox(const Node& n, const glm::vec3& o, const glm::vec3& d, float tmax) {
    // Slabs (Kay & Kajiya 1986, "Ray Tracing Complex Scenes", section 3), padded by a relative
    // 1e-5 so that rounding cannot drop an emitter the exact test would hit.
    float t0 = 0.0f, t1 = tmax;
    for (int a = 0; a < 3; ++a) {
        const float pad = 1e-5f * (n.hi[a] - n.lo[a]) + 1e-7f * std::abs(o[a]);
        const float lo = n.lo[a] - pad, hi = n.hi[a] + pad;
        if (d[a] == 0.0f) {
            if (o[a] < lo || o[a] > hi) return false;
            continue;
        }
        const float inv = 1.0f / d[a];
        float ta = (lo - o[a]) * inv, tb = (hi - o[a]) * inv;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb * 1.00001f);
        if (!(t0 <= t1)) return false;
    }
    return true;
}

float LightTree::leftChance(const Node& n, const glm::vec3& p, const glm::vec3& nrm) const {
    const Node& a = _nodes[size_t(n.left)];
    const Node& b = _nodes[size_t(n.left) + 1];
    const float wa = weight(a, p, nrm), wb = weight(b, p, nrm);
    const float sum = wa + wb;
    // Weights are positive and finite; a sum that is not (overflow) falls back to power.
    return sum > 0.0f && std::isfinite(sum) ? wa / sum : a.power / (a.power + b.power);
}

float LightTree::rootWeight(const glm::vec3& p, const glm::vec3& n) const {
    return _nodes.empty() ? 0.0f : sphereWeight(_nodes[0], p, n);
}

uint32_t LightTree::pick(const glm::vec3& p, float u, const glm::vec3& nrm) const {
    size_t n = 0;
    while (_nodes[n].left >= 0) {
        const float a = leftChance(_nodes[n], p, nrm);
        if (u < a) {
            u = u / a;
            n = size_t(_nodes[n].left);
        } else {
            u = (u - a) / (1.0f - a);
            n = size_t(_nodes[n].left) + 1;
        }
        u = std::min(std::max(u, 0.0f), 0.99999994f);  // the rescaled u stays in [0, 1)
    }
    return _nodes[n].light;
}

float LightTree::probability(uint32_t light, const glm::vec3& p, const glm::vec3& nrm) const {
    if (light >= _leafOf.size() || _leafOf[light] < 0) return 0.0f;
    int32_t n = _leafOf[light];
    float prob = 1.0f;
    while (_nodes[size_t(n)].parent >= 0) {
        const Node& parent = _nodes[size_t(_nodes[size_t(n)].parent)];
        const float a = leftChance(parent, p, nrm);
        prob *= n == parent.left ? a : 1.0f - a;
        n = _nodes[size_t(n)].parent;
    }
    return prob;
}

}  // namespace principled::embree
