// LightTree (delegate/lightTree.h): its leaves weigh lights exactly as the linear pick does, a
// descent picks each light with the probability the tree reports, and the probabilities form a
// distribution at every point.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "delegate/lightSampling.h"
#include "delegate/lightTree.h"

using namespace principled::embree;

TEST(LightTree, TwoLightsAreChosenInProportionToTheirWeights) {
    // Weights power * R^2 / d^2, d from p to the box around a light's sphere (radius 0.1): at the
    // origin, light 5 (power 1, d = 1.9) against light 2 (power 3, d = 5.9).
    const LightTree tree({{glm::vec3(2, 0, 0), 0.01f, 1.0f, 5}, {glm::vec3(-6, 0, 0), 0.01f, 3.0f, 2}}, 100.0f);
    const glm::vec3 p(0.0f);
    const float w5 = 1.0f / (1.9f * 1.9f), w2 = 3.0f / (5.9f * 5.9f);
    EXPECT_NEAR(tree.probability(5, p), w5 / (w5 + w2), 1e-6f);
    EXPECT_NEAR(tree.probability(2, p), w2 / (w5 + w2), 1e-6f);
    EXPECT_EQ(tree.probability(0, p), 0.0f);  // not in the tree
    EXPECT_FALSE(tree.contains(3));
    int fives = 0;
    for (int k = 0; k < 10000; ++k) fives += tree.pick(p, (k + 0.5f) / 10000.0f) == 5u;
    EXPECT_NEAR(fives / 10000.0, w5 / (w5 + w2), 1e-4);
    // Inside a light's box the distance is its radius.
    const glm::vec3 q(2.05f, 0.0f, 0.0f);
    const float v5 = 1.0f / 0.01f, v2 = 3.0f / (7.95f * 7.95f);
    EXPECT_NEAR(tree.probability(5, q), v5 / (v5 + v2), 1e-6f);
}

TEST(LightTree, ProbabilitiesFormADistributionAndMatchTheDescent) {
    std::vector<LightTree::Item> items;
    for (uint32_t i = 0; i < 97; ++i) {  // a grid with a cluster of coincident lamps at the origin
        const float x = i < 10 ? 0.0f : float(i % 9) * 3.0f - 12.0f, z = i < 10 ? 0.0f : float(i / 9) * 2.0f - 10.0f;
        items.push_back({glm::vec3(x, 1.0f, z), 0.04f, 1.0f + float(i % 5), i});
    }
    const LightTree tree(items, 400.0f);
    EXPECT_EQ(tree.nodeCount(), 2 * items.size() - 1);
    for (const glm::vec3 p : {glm::vec3(0.0f), glm::vec3(9.0f, 0.0f, -7.0f), glm::vec3(100.0f, 50.0f, 0.0f)}) {
        double sum = 0.0;
        for (uint32_t i = 0; i < 97; ++i) sum += tree.probability(i, p);
        EXPECT_NEAR(sum, 1.0, 1e-5);
        const int n = 1 << 20;
        std::vector<int> hits(97, 0);
        for (int k = 0; k < n; ++k) ++hits[tree.pick(p, (k + 0.5f) / n)];
        for (uint32_t i = 0; i < 97; ++i) EXPECT_NEAR(double(hits[i]) / n, tree.probability(i, p), 2e-5) << i;
    }
}

TEST(LightTree, RaysFindEverySphereTheyCrossAmongTheCandidates) {
    // 500 spheres at random; random segments (some from inside a sphere, some axis-aligned, some
    // ending short of a sphere): the candidates must include every sphere the segment meets.
    uint32_t state = 99u;
    auto next = [&state]() {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) / float(1u << 24);
    };
    std::vector<LightTree::Item> items;
    for (uint32_t i = 0; i < 500; ++i) {
        const float r = 0.05f + 0.5f * next();
        items.push_back({glm::vec3(20 * next() - 10, 20 * next() - 10, 20 * next() - 10), r * r, 1.0f, i});
    }
    const LightTree tree(items, 100.0f);
    int crossings = 0;
    for (int k = 0; k < 4000; ++k) {
        glm::vec3 o(24 * next() - 12, 24 * next() - 12, 24 * next() - 12);
        if (k % 7 == 0) o = items[k % 500].center;  // from inside a sphere
        glm::vec3 d(next() - 0.5f, next() - 0.5f, next() - 0.5f);
        if (k % 5 == 0) d = glm::vec3(0.0f, k % 2 ? 1.0f : -1.0f, 0.0f);  // zero components
        d = glm::normalize(d);
        const float tmax = k % 3 == 0 ? 5.0f * next() : INFINITY;
        std::vector<char> candidate(500, 0);
        tree.forEachAlong(o, d, tmax, [&](uint32_t light) { candidate[light] = 1; });
        for (const LightTree::Item& it : items) {
            // Does the segment meet the sphere? Closest approach within [0, tmax].
            const float t = std::min(std::max(glm::dot(it.center - o, d), 0.0f), tmax);
            const glm::vec3 q = o + t * d - it.center;
            if (glm::dot(q, q) < it.radius2) {
                ++crossings;
                EXPECT_TRUE(candidate[it.light]) << "ray " << k << " misses sphere " << it.light;
            }
        }
    }
    EXPECT_GT(crossings, 1000);
}

TEST(LightTree, ShearedRectAndDiskLightsHaveNoFiniteBound) {
    // The trees hold lights by lightBoundingRadius(); a rect under a shearing transform (axes
    // not perpendicular) reaches beyond sqrt(|U|^2 + |V|^2), so it must stay out of them.
    LightRecord rect;
    rect.kind = LightRecord::Kind::Rect;
    rect.axisU = glm::vec3(1, 0, 0);
    rect.axisV = glm::vec3(0, 2, 0);
    rect.normal = glm::vec3(0, 0, -1);
    EXPECT_NEAR(lightBoundingRadius(rect), std::sqrt(5.0f), 1e-6f);
    rect.axisV = glm::vec3(1, 1, 0);  // 45 degrees to U
    EXPECT_TRUE(std::isinf(lightBoundingRadius(rect)));
    LightRecord disk = rect;
    disk.kind = LightRecord::Kind::Disk;
    EXPECT_TRUE(std::isinf(lightBoundingRadius(disk)));
    disk.axisV = glm::vec3(0, 1, 0);
    disk.normal = glm::normalize(glm::vec3(0, 1, -1));  // normal not perpendicular to V
    EXPECT_TRUE(std::isinf(lightBoundingRadius(disk)));
}

namespace {
float angleBetween(const glm::vec3& a, const glm::vec3& b) {
    return std::acos(std::clamp(glm::dot(glm::normalize(a), glm::normalize(b)), -1.0f, 1.0f));
}
}  // namespace

TEST(LightTree, MergedConesHoldBothCones) {
    uint32_t state = 7u;
    auto next = [&state]() {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) / float(1u << 24);
    };
    auto randomDir = [&]() {
        const float z = 2.0f * next() - 1.0f, phi = 6.2831853f * next(), r = std::sqrt(std::max(0.0f, 1.0f - z * z));
        return glm::vec3(r * std::cos(phi), r * std::sin(phi), z);
    };
    for (int trial = 0; trial < 2000; ++trial) {
        LightTree::Cone a{randomDir(), std::cos(1.5f * next()), std::cos(1.5f * next())};
        LightTree::Cone b{randomDir(), std::cos(1.5f * next()), std::cos(1.5f * next())};
        const LightTree::Cone m = LightTree::merge(a, b);
        EXPECT_LE(m.cosThetaE, std::min(a.cosThetaE, b.cosThetaE));
        if (m.all()) continue;
        const float thetaM = std::acos(m.cosThetaO);
        for (const LightTree::Cone& c : {a, b}) {
            // The input cone's axis and its rim (in a few directions) lie inside the merged one.
            const float thetaC = std::acos(c.cosThetaO);
            const glm::vec3 t = glm::normalize(glm::cross(c.axis, std::abs(c.axis.x) < 0.9f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0)));
            const glm::vec3 u = glm::cross(c.axis, t);
            for (int k = 0; k < 8; ++k) {
                const float phi = 0.785398f * float(k);
                const glm::vec3 rim = std::cos(thetaC) * c.axis + std::sin(thetaC) * (std::cos(phi) * t + std::sin(phi) * u);
                EXPECT_LE(angleBetween(m.axis, rim), thetaM + 1e-3f) << trial;
            }
        }
    }
}

TEST(LightTree, ConesTakeTheLightsThatFaceAwayOutOfThePickAndNoMore) {
    // 120 one-sided emitters (radius 0.2) on a grid at height 2: most face down, every fifth up,
    // every seventh a 20-degree spot aimed down. A light that can send light to p (some point of
    // its sphere within its emission cone of p) always keeps a positive probability; well below
    // the lamps the upward ones are hardly ever picked; the probabilities form a distribution.
    std::vector<LightTree::Item> items;
    for (uint32_t i = 0; i < 120; ++i) {
        LightTree::Item it{glm::vec3(float(i % 12) * 1.5f - 8.0f, 2.0f, float(i / 12) * 1.5f - 7.0f), 0.04f,
                           1.0f + float(i % 3), i, {}};
        it.cone.axis = i % 5 == 0 ? glm::vec3(0, 1, 0) : glm::vec3(0, -1, 0);
        it.cone.cosThetaO = 1.0f;
        it.cone.cosThetaE = i % 7 == 0 ? std::cos(0.349f) : 0.0f;
        items.push_back(it);
    }
    const LightTree tree(items, 400.0f);
    uint32_t state = 3u;
    auto next = [&state]() {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) / float(1u << 24);
    };
    double upward = 0.0;  // summed over the trials below y = 1
    std::vector<glm::vec3> below;
    for (int trial = 0; trial < 200; ++trial) {
        const glm::vec3 p(24.0f * next() - 12.0f, 6.0f * next() - 2.0f, 24.0f * next() - 12.0f);
        if (p.y < 1.0f) below.push_back(p);
        double sum = 0.0;
        for (const LightTree::Item& it : items) {
            const float prob = tree.probability(it.light, p);
            sum += prob;
            // Can some point q of the sphere send light to p?
            bool reaches = false;
            for (int k = 0; k < 64 && !reaches; ++k) {
                const float z = 2.0f * next() - 1.0f, phi = 6.2831853f * next(), r = std::sqrt(1.0f - z * z);
                const glm::vec3 q = it.center + 0.2f * glm::vec3(r * std::cos(phi), r * std::sin(phi), z);
                reaches = glm::dot(glm::normalize(p - q), it.cone.axis) > it.cone.cosThetaE + 1e-3f;
            }
            if (reaches) EXPECT_GT(prob, 0.0f) << "light " << it.light << " at trial " << trial;
            if (it.light % 5 == 0 && p.y < 1.0f) upward += prob;
        }
        if (sum > 0.0) EXPECT_NEAR(sum, 1.0, 1e-4);
    }
    // Below the lamps the upward ones, a fifth of the power, are picked far less often than by
    // distance alone (a cluster whose children both weigh 0 falls back to their powers, so they
    // keep a share: 5.7 % against 20 % when this was written).
    std::vector<LightTree::Item> plain = items;
    for (LightTree::Item& it : plain) it.cone = LightTree::Cone{};
    const LightTree distanceOnly(plain, 400.0f);
    double upwardByDistance = 0.0;
    for (const glm::vec3& p : below)
        for (const LightTree::Item& it : plain)
            if (it.light % 5 == 0) upwardByDistance += distanceOnly.probability(it.light, p);
    EXPECT_LT(upward, 0.4 * upwardByDistance);
}

TEST(LightTree, SpotConesWiderThanAHemisphereStayConservative) {
    // 80 spots with 120-degree cones, axes down or along +x: a point 100 degrees off a spot's
    // axis is inside its cone, so the spot must keep a positive probability there.
    std::vector<LightTree::Item> items;
    for (uint32_t i = 0; i < 80; ++i) {
        LightTree::Item it{glm::vec3(float(i % 10) * 2.0f - 9.0f, 4.0f, float(i / 10) * 2.0f - 7.0f), 0.01f, 1.0f, i, {}};
        it.cone.axis = i % 2 ? glm::vec3(1, 0, 0) : glm::vec3(0, -1, 0);
        it.cone.cosThetaO = 1.0f;
        it.cone.cosThetaE = std::cos(2.0944f);  // 120 degrees
        items.push_back(it);
    }
    const LightTree tree(items, 400.0f);
    for (const LightTree::Item& it : items) {
        // 100 degrees off the axis, 3 units away, in the plane of the axis and +z.
        const float a = 1.745f;
        const glm::vec3 side = glm::normalize(glm::cross(it.cone.axis, glm::vec3(0, 0, 1)));
        const glm::vec3 p = it.center + 3.0f * (std::cos(a) * it.cone.axis + std::sin(a) * side);
        EXPECT_GT(tree.probability(it.light, p), 0.0f) << it.light;
    }
}
