// The spatial light pick (delegate/lightPick.h): its probabilities are a distribution at every
// point, pick() draws from exactly that distribution, and nearer lamps of equal power are
// preferred in proportion to 1 / d^2.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "delegate/lightPick.h"

using namespace principled::embree;

namespace {

// Eight sphere lamps on a line (x = 0, 2, ..., 14), one distant light; global pick
// probabilities by a made-up power with the snapshot's CDF.
SceneSnapshot lampsOnALine() {
    SceneSnapshot s;
    for (int i = 0; i < 8; ++i) {
        LightRecord l;
        l.kind = LightRecord::Kind::Sphere;
        l.center = glm::vec3(2.0f * i, 0.0f, 0.0f);
        l.radius = 0.1f;
        s.lights.push_back(l);
    }
    LightRecord sun;
    sun.kind = LightRecord::Kind::Distant;
    s.lights.push_back(sun);
    const float power[9] = {1, 2, 3, 4, 1, 2, 3, 4, 5};
    float total = 0.0f;
    for (float p : power) total += p;
    s.lightCdf.assign(1, 0.0f);
    for (size_t i = 0; i < s.lights.size(); ++i) {
        s.lights[i].pickProbability = power[i] / total;
        s.lightCdf.push_back(s.lightCdf.back() + s.lights[i].pickProbability);
    }
    s.lightCdf.back() = 1.0f;
    s.lightSceneRadius = 10.0f;
    s.neeAllLights = false;
    return s;
}

}  // namespace

TEST(LightPick, ProbabilitiesSumToOneAndPickFollowsThem) {
    const SceneSnapshot scene = lampsOnALine();
    const LightPick pick(scene, true);
    ASSERT_TRUE(pick.spatial());
    float w[LightPick::kMaxLights];
    for (const glm::vec3 p : {glm::vec3(0.5f, 1.0f, 0.0f), glm::vec3(7.0f, 0.2f, 3.0f), glm::vec3(14.0f, 0.0f, 0.05f)}) {
        const float total = pick.weigh(p, w);
        double sum = 0.0;
        for (uint32_t i = 0; i < scene.lights.size(); ++i) sum += pick.probability(i, p, total);
        EXPECT_NEAR(sum, 1.0, 1e-5);
        // pick() over a fine grid of u: each light's share of the grid is its probability.
        const int n = 1 << 18;
        std::vector<int> hits(scene.lights.size(), 0);
        for (int k = 0; k < n; ++k) ++hits[pick.pick(w, total, (k + 0.5f) / n)];
        for (uint32_t i = 0; i < scene.lights.size(); ++i)
            EXPECT_NEAR(double(hits[i]) / n, pick.probability(i, p, total), 1e-4) << "light " << i;
    }
}

TEST(LightPick, NearerLampsOfEqualPowerArePreferredByInverseSquare) {
    const SceneSnapshot scene = lampsOnALine();
    const LightPick pick(scene, true);
    float w[LightPick::kMaxLights];
    const glm::vec3 p(1.0f, 1.0f, 0.0f);  // distances^2 to lamps 0 and 4 (power 1 each): 2 and 50
    const float total = pick.weigh(p, w);
    const float share = 1.0f - LightPick::kGlobalShare, global = scene.lights[0].pickProbability;
    const float spatial0 = (pick.probability(0, p, total) - LightPick::kGlobalShare * global) / share;
    const float spatial4 = (pick.probability(4, p, total) - LightPick::kGlobalShare * global) / share;
    EXPECT_NEAR(spatial0 / spatial4, 25.0f, 1e-3f);
    // The distant light keeps its global weight; without the setting every pick is global.
    const LightPick off(scene, false);
    EXPECT_FALSE(off.spatial());
    EXPECT_EQ(off.probability(8, p, 0.0f), scene.lights[8].pickProbability);
}

TEST(LightPick, FewLightsOrTooManyKeepTheGlobalPick) {
    SceneSnapshot scene = lampsOnALine();
    scene.neeAllLights = true;  // every light sampled at every vertex: nothing to pick
    EXPECT_FALSE(LightPick(scene, true).spatial());
    scene = lampsOnALine();
    scene.lights.resize(LightPick::kMaxLights + 1, scene.lights[0]);
    EXPECT_FALSE(LightPick(scene, true).spatial());
}
