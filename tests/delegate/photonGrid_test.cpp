// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <random>

#include "delegate/photonGrid.h"

using namespace principled::embree;

TEST(PhotonGrid, QueriesFindExactlyThePhotonsWithinTheRadiusOnce) {
    // Against brute force, with few buckets per photon so that cells share buckets (a photon
    // visited twice would be counted twice), and points far from the origin.
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    struct Case {
        glm::vec3 offset;
        int count;
        float spread;
    };
    // 20 photons: 64 buckets, which the 8 cells of a query share often.
    for (const Case& c : {Case{glm::vec3(0.0f), 3000, 2.0f}, Case{glm::vec3(1e5f, -3e4f, 2e5f), 3000, 2.0f},
                          Case{glm::vec3(0.5f), 20, 0.3f}}) {
        const glm::vec3 offset = c.offset;
        const int count = c.count;
        std::vector<Photon> photons(static_cast<size_t>(count));
        for (size_t i = 0; i < photons.size(); ++i) {
            photons[i].position = offset + glm::vec3(u(rng), u(rng), u(rng)) * c.spread;
            photons[i].power = glm::vec3(float(i));
        }
        const float r = 0.15f;
        PhotonGrid grid(photons, r);
        ASSERT_EQ(grid.size(), photons.size());
        for (int q = 0; q < 2000; ++q) {
            const glm::vec3 p = offset + glm::vec3(u(rng), u(rng), u(rng)) * c.spread;
            std::vector<int> expected, found;
            for (const Photon& ph : photons)
                if (glm::dot(ph.position - p, ph.position - p) <= r * r) expected.push_back(int(ph.power.x));
            grid.query(p, [&](const Photon& ph) { found.push_back(int(ph.power.x)); });
            std::sort(found.begin(), found.end());
            EXPECT_EQ(found, expected) << "query " << q;
        }
    }
}

TEST(PhotonGrid, NonFinitePhotonsAndRadiiAreDropped) {
    std::vector<Photon> photons(2);
    photons[1].position = glm::vec3(std::nanf(""), 0.0f, 0.0f);
    EXPECT_EQ(PhotonGrid(photons, 0.1f).size(), 1u);
    EXPECT_TRUE(PhotonGrid(photons, 0.0f).empty());
    EXPECT_TRUE(PhotonGrid(photons, std::numeric_limits<float>::infinity()).empty());
    int visits = 0;
    PhotonGrid(photons, 0.0f).query(glm::vec3(0.0f), [&](const Photon&) { ++visits; });
    EXPECT_EQ(visits, 0);
}
