// SPDX-License-Identifier: Apache-2.0
// LightPick: which light next-event estimation samples at a shading point, when it samples one
// (SceneSnapshot::neeAllLights off). Each light's global pick probability (by power delivered to
// the scene, 10 % uniform; renderDelegate.cpp) is scaled by how much of it reaches the point:
// R^2 / max(d^2, r^2) for a light of bounding radius r whose centre is d away (R: the scene's
// bounding radius, against which the global probabilities of distant and dome lights were
// taken), 1 for distant and dome lights. So a lamp next to the point is picked before an equally
// strong one across the scene, in proportion to the irradiance each can deliver (inverse square
// law; Shirley, Wang & Zimmerman 1996, "Monte Carlo Techniques for Direct Lighting
// Calculations", section 4.1, weights by estimated contribution). A share kGlobalShare of the
// picks stays with the global probabilities, so a weak lamp next to the point (blocked, or
// facing away) cannot take every pick; every probability is then at least kGlobalShare times
// the global one, and the estimate is unbiased wherever that is. Up to kMaxLights lights are
// weighed one by one at each point; more local lights go into a LightTree (delegate/lightTree.h),
// whose clusters are weighed the same way, so a pick costs O(log n) (distant and dome lights
// stay in a flat list beside the tree's root).
//
// A light that cannot reach the point weighs 0 (before the global share): one whose bounding
// sphere lies wholly behind the receiving surface (n, the side light may arrive from, when the
// material does not transmit: the caller passes n = 0 otherwise), a distant light below its
// horizon, a one-sided rect or disk seen from behind, and a shaped light whose cone (widened by
// the angle its bounding sphere subtends at the point) misses it — ShapingAPI's cone angle, 90
// degrees for focus with a black tint, the vertical range of an IES profile. The tree applies
// the receiver test to its clusters' boxes.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "delegate/lightTree.h"
#include "delegate/sceneData.h"

namespace principled::embree {

class LightPick {
public:
    static constexpr size_t kMaxLights = 64;
    static constexpr float kGlobalShare = 0.1f;

    /// enabled: the render setting (spatialLightPick); inactive without lights to choose among.
    LightPick(const SceneSnapshot& scene, bool enabled);

    /// Weighs the lights at p: picks then depend on the point (else on power alone).
    bool spatial() const { return _spatial; }

    /// The lights' weights at p (receiver normal n, or 0) into w (kMaxLights entries; written
    /// only when the lights are weighed one by one), and their sum: once per shading point
    /// (spatial() only).
    float weigh(const glm::vec3& p, const glm::vec3& n, float* w) const;
    /// The light for u in [0, 1), with probability probability(i, p, n, total) (w and total from
    /// weigh() at p, n; total > 0).
    uint32_t pick(const glm::vec3& p, const glm::vec3& n, const float* w, float total, float u) const;
    /// The light for u in [0, 1) by the global probabilities alone (the snapshot's CDF).
    uint32_t globalPick(float u) const;
    /// The probability that pick() at p, n returns light i (total from weigh() at p, n); the
    /// global pick probability when not spatial() or when total is 0 (a point that used the
    /// global pick).
    float probability(uint32_t i, const glm::vec3& p, const glm::vec3& n, float total) const;

private:
    /// What limits where a light sends its emission (see the file comment).
    struct Reach {
        uint8_t tests = 0;       ///< kBehindPlane | kCone | kHorizon
        glm::vec3 normal{0.0f};  ///< one-sided emitter: the side it emits to; distant: toward the light
        glm::vec3 axis{0.0f};    ///< cone axis
        float cosCone = -1.0f, sinCone = 0.0f;  ///< cone half angle; distant: -sin(angular radius)
    };
    static constexpr uint8_t kBehindPlane = 1, kCone = 2, kHorizon = 4;
    static Reach reachOf(const LightRecord& l);
    /// The tree's emission cone for a light with these reach tests (everywhere: none).
    static LightTree::Cone emissionCone(const Reach& r);
    /// Can light i (bounding sphere centre c, radius^2 r2) reach p with receiver normal n?
    bool reaches(uint32_t i, const glm::vec3& c, float r2, const glm::vec3& p, const glm::vec3& n) const;
    float weight(uint32_t i, const glm::vec3& p, const glm::vec3& n) const;

    const SceneSnapshot& _scene;
    bool _spatial = false;
    /// Per light: its bounding sphere (centre, radius^2) for local lights; radius^2 < 0 marks a
    /// distant or dome light (weight = its global probability).
    std::vector<glm::vec4> _bounds;
    std::vector<Reach> _reach;  ///< per light
    float _sceneRadius2 = 1.0f;
    /// More than kMaxLights lights: the local ones in a tree, the others (distant, dome, or
    /// without finite bounds) listed, weighed one by one.
    bool _many = false;
    LightTree _tree;
    std::vector<uint32_t> _flat;
};

}  // namespace principled::embree
