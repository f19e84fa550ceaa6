// LightTree (delegate/lightTree.h): its leaves weigh lights exactly as the linear pick does, a
// descent picks each light with the probability the tree reports, and the probabilities form a
// distribution at every point.
#include <gtest/gtest.h>

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
