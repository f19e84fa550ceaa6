// SPDX-License-Identifier: Apache-2.0
// LightTree: a binary tree over local lights' bounding spheres, for picking one of many lights
// at a shading point in O(log n) (Conty Estevez & Kulla 2018, "Importance Sampling of Many
// Lights with Adaptive Tree Splitting", section 4: descend by the children's estimated
// importance, orientation cones included; no splitting). A node's weight at p is power * R^2 / d^2, with
// power the sum of the global pick probabilities below it and d^2 the squared distance from p to
// the box around its lights' bounding spheres, at least the smallest of their radii^2: a cluster
// around p outweighs one beside it, as the lamps next to p do in the linear pick. (Measured on
// 144 lamps over a floor, bench/lamps_scene.py --side 12 --pitch 4: by the distance to each
// cluster's bounding-sphere centre the variance was 10x higher; with a floor of diagonal^2 / 4n,
// the lamps' spacing, 2.7x.) The root is weighed by its bounding sphere, max(|p - c|^2, r^2), as
// one light standing for them all (rootWeight(), which LightPick sets against distant and dome
// lights as the linear pick does).
// pick() descends choosing a child in proportion to its weight; probability() walks back up
// from the light's leaf and multiplies the same choices, so the two agree at every point.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace principled::embree {

class LightTree {
public:
    /// The directions an emitter sends light along: within thetaE of some direction within
    /// thetaO of axis (Conty Estevez & Kulla 2018, section 4.1, the normal and emission
    /// bounds). The default bounds nothing (thetaO = pi).
    struct Cone {
        glm::vec3 axis{0.0f, 0.0f, 1.0f};
        float cosThetaO = -1.0f;
        float cosThetaE = 0.0f;
        bool all() const { return cosThetaO <= -1.0f; }
    };
    struct Item {
        glm::vec3 center;  ///< bounding sphere of the emitter
        float radius2;     ///< its radius^2 (> 0)
        float power;       ///< global pick probability (> 0)
        uint32_t light;    ///< index in the snapshot's lights
        Cone cone{};       ///< where it emits (default: everywhere)
    };
    /// The smallest cone holding both (Conty Estevez & Kulla 2018, Algorithm 1).
    static Cone merge(const Cone& a, const Cone& b);
    /// Orientation factor of a cluster with bounding sphere (c, r^2) and cone k at p: the cosine
    /// of the least angle between a direction it may emit along and p (0 when p lies outside every
    /// such direction). Conty Estevez & Kulla 2018, eq. 3 (theta' = max(0, theta - theta_o -
    /// theta_u)), with the cosines composed as in Pharr et al. 2023, section 12.6.3.
    static float orientation(const Cone& k, const glm::vec3& c, float r2, const glm::vec3& p);

    LightTree() = default;
    /// sceneRadius2: the R^2 of the weights. Items with non-finite bounds or power <= 0 must be
    /// left out by the caller.
    LightTree(std::vector<Item> items, float sceneRadius2);

    bool empty() const { return _nodes.empty(); }
    size_t nodeCount() const { return _nodes.size(); }
    bool contains(uint32_t light) const { return light < _leafOf.size() && _leafOf[light] >= 0; }
    /// The root's weight at p: the whole tree as one cluster. n: the receiver's normal (the side
    /// light may arrive from) or 0; a node whose box lies wholly behind that plane weighs 0.
    float rootWeight(const glm::vec3& p, const glm::vec3& n = glm::vec3(0.0f)) const;
    /// The light for u in [0, 1), with probability probability(light, p, n).
    uint32_t pick(const glm::vec3& p, float u, const glm::vec3& n = glm::vec3(0.0f)) const;
    /// The chance that pick(p, u, n) returns this light over u uniform; 0 for a light not in the
    /// tree.
    float probability(uint32_t light, const glm::vec3& p, const glm::vec3& n = glm::vec3(0.0f)) const;
    /// Calls f(light) for every light whose box the segment o + t d, 0 <= t <= tmax, meets: a
    /// superset of the emitters the ray reaches, for the caller to intersect exactly.
    template <class F>
    void forEachAlong(const glm::vec3& o, const glm::vec3& d, float tmax, F&& f) const {
        if (_nodes.empty()) return;
        int32_t stack[64];  // median splits: depth <= log2(lights) + 1
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& n = _nodes[size_t(stack[--top])];
            if (!segmentMeetsBox(n, o, d, tmax)) continue;
            if (n.left < 0) {
                f(n.light);
            } else {
                stack[top++] = n.left;
                stack[top++] = n.left + 1;
            }
        }
    }

private:
    struct Node {
        glm::vec3 center;  ///< bounding sphere (the root's weight)
        float radius2;
        glm::vec3 lo, hi;  ///< bounding box of the emitters' spheres (the other nodes' weight)
        float floor2;      ///< the least d^2 of the weight: the lights' smallest radius^2
        float power;
        Cone cone;         ///< where its lights emit
        int32_t left;    ///< first child (the second is left + 1); -1 for a leaf
        int32_t parent;  ///< -1 for the root
        uint32_t light;  ///< leaves: the light
    };
    void build(std::vector<Item>& items, size_t begin, size_t end, int32_t self);
    /// The root's weight: by the distance to its bounding sphere's centre.
    float sphereWeight(const Node& n, const glm::vec3& p, const glm::vec3& nrm) const;
    /// The weight of a node below the root, by the distance to its box (see the file comment).
    float weight(const Node& n, const glm::vec3& p, const glm::vec3& nrm) const;
    static bool behind(const Node& n, const glm::vec3& p, const glm::vec3& nrm);
    static bool segmentMeetsBox(const Node& n, const glm::vec3& o, const glm::vec3& d, float tmax);
    /// The chance the descent at interior node n goes to its first child.
    float leftChance(const Node& n, const glm::vec3& p, const glm::vec3& nrm) const;

    std::vector<Node> _nodes;
    std::vector<int32_t> _leafOf;  ///< per light index: its leaf, or -1
    float _sceneRadius2 = 1.0f;
};

}  // namespace principled::embree
