// The spatial light pick (delegate/lightPick.h): its probabilities are a distribution at every
// point, pick() draws from exactly that distribution, and nearer lamps of equal power are
// preferred in proportion to 1 / d^2.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "delegate/lightPick.h"

using namespace principled::embree;

namespace {

// Global pick probabilities in proportion to `power` (one per light), with the snapshot's CDF,
// scene radius R and a pick per vertex (as the render delegate's light distribution).
void setGlobalPick(SceneSnapshot& s, const std::vector<float>& power, float R) {
    float total = 0.0f;
    for (float x : power) total += x;
    s.lightCdf.assign(1, 0.0f);
    for (size_t i = 0; i < s.lights.size(); ++i) {
        s.lights[i].pickProbability = power[i] / total;
        s.lightCdf.push_back(s.lightCdf.back() + s.lights[i].pickProbability);
    }
    s.lightCdf.back() = 1.0f;
    s.lightSceneRadius = R;
    s.neeAllLights = false;
}

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
    setGlobalPick(s, {1, 2, 3, 4, 1, 2, 3, 4, 5}, 10.0f);
    return s;
}

}  // namespace

TEST(LightPick, ProbabilitiesSumToOneAndPickFollowsThem) {
    const SceneSnapshot scene = lampsOnALine();
    const LightPick pick(scene, true);
    ASSERT_TRUE(pick.spatial());
    float w[LightPick::kMaxLights];
    for (const glm::vec3 p : {glm::vec3(0.5f, 1.0f, 0.0f), glm::vec3(7.0f, 0.2f, 3.0f), glm::vec3(14.0f, 0.0f, 0.05f)})
    for (const glm::vec3 nrm : {glm::vec3(0.0f), glm::vec3(1.0f, 0.0f, 0.0f)}) {  // with a receiver, lamps behind it weigh 0
        const float total = pick.weigh(p, nrm, w);
        double sum = 0.0;
        for (uint32_t i = 0; i < scene.lights.size(); ++i) sum += pick.probability(i, p, nrm, total);
        EXPECT_NEAR(sum, 1.0, 1e-5);
        // pick() over a fine grid of u: each light's share of the grid is its probability.
        const int n = 1 << 18;
        std::vector<int> hits(scene.lights.size(), 0);
        for (int k = 0; k < n; ++k) ++hits[pick.pick(p, nrm, w, total, (k + 0.5f) / n)];
        for (uint32_t i = 0; i < scene.lights.size(); ++i)
            EXPECT_NEAR(double(hits[i]) / n, pick.probability(i, p, nrm, total), 1e-4) << "light " << i;
    }
}

TEST(LightPick, NearerLampsOfEqualPowerArePreferredByInverseSquare) {
    const SceneSnapshot scene = lampsOnALine();
    const LightPick pick(scene, true);
    float w[LightPick::kMaxLights];
    const glm::vec3 p(1.0f, 1.0f, 0.0f);  // distances^2 to lamps 0 and 4 (power 1 each): 2 and 50
    const float total = pick.weigh(p, glm::vec3(0.0f), w);
    const float share = 1.0f - LightPick::kGlobalShare, global = scene.lights[0].pickProbability;
    const float spatial0 = (pick.probability(0, p, glm::vec3(0.0f), total) - LightPick::kGlobalShare * global) / share;
    const float spatial4 = (pick.probability(4, p, glm::vec3(0.0f), total) - LightPick::kGlobalShare * global) / share;
    EXPECT_NEAR(spatial0 / spatial4, 25.0f, 1e-3f);
    // The distant light keeps its global weight; without the setting every pick is global.
    const LightPick off(scene, false);
    EXPECT_FALSE(off.spatial());
    EXPECT_EQ(off.probability(8, p, glm::vec3(0.0f), 0.0f), scene.lights[8].pickProbability);
}

TEST(LightPick, FewLightsKeepTheGlobalPick) {
    SceneSnapshot scene = lampsOnALine();
    scene.neeAllLights = true;  // every light sampled at every vertex: nothing to pick
    EXPECT_FALSE(LightPick(scene, true).spatial());
    scene = lampsOnALine();
    scene.lights.resize(1);
    EXPECT_FALSE(LightPick(scene, true).spatial());
}

TEST(LightPick, ManyLightsArePickedThroughTheTreeWithTheProbabilitiesItReports) {
    // 300 sphere lamps scattered over a 40 x 40 x 4 box with powers over two decades, two distant
    // lights: more than kMaxLights, so the local lamps go into a LightTree.
    SceneSnapshot s;
    uint32_t state = 12345u;
    auto next = [&state]() {
        state = state * 1664525u + 1013904223u;
        return float(state >> 8) / float(1u << 24);
    };
    std::vector<float> power;
    for (int i = 0; i < 300; ++i) {
        LightRecord l;
        l.kind = LightRecord::Kind::Sphere;
        l.center = glm::vec3(40.0f * next() - 20.0f, 4.0f * next(), 40.0f * next() - 20.0f);
        l.radius = 0.05f + 0.2f * next();
        s.lights.push_back(l);
        power.push_back(std::pow(10.0f, 2.0f * next()));
    }
    for (int i = 0; i < 2; ++i) {
        LightRecord sun;
        sun.kind = i == 0 ? LightRecord::Kind::Distant : LightRecord::Kind::Dome;
        s.lights.push_back(sun);
        power.push_back(500.0f);
    }
    setGlobalPick(s, power, 30.0f);
    const LightPick pick(s, true);
    ASSERT_TRUE(pick.spatial());
    float w[LightPick::kMaxLights];
    for (uint32_t near : {7u, 150u, 299u}) {
        // Just beside lamp `near`, on the floor below it.
        const glm::vec3 p = s.lights[near].center + glm::vec3(0.3f, -0.5f, 0.0f);
        const glm::vec3 up(0.0f, 1.0f, 0.0f);  // a floor: lamps below it weigh 0
        const float t = pick.weigh(p, up, w);
        double sum = 0.0;
        for (uint32_t i = 0; i < s.lights.size(); ++i) sum += pick.probability(i, p, up, t);
        EXPECT_NEAR(sum, 1.0, 1e-4);
        const int n = 1 << 20;
        std::vector<int> hits(s.lights.size(), 0);
        for (int k = 0; k < n; ++k) ++hits[pick.pick(p, up, w, t, (k + 0.5f) / n)];
        double worst = 0.0;
        for (uint32_t i = 0; i < s.lights.size(); ++i)
            worst = std::max(worst, std::abs(double(hits[i]) / n - pick.probability(i, p, up, t)));
        EXPECT_LT(worst, 2e-5) << "at lamp " << near;
        // The lamp next to the point is picked far more often than its power alone would have it.
        EXPECT_GT(pick.probability(near, p, up, t), 10.0f * s.lights[near].pickProbability) << "lamp " << near;
        // The distant lights keep the share of their power among the weights.
        EXPECT_GT(pick.probability(300, p, up, t), LightPick::kGlobalShare * s.lights[300].pickProbability);
    }
}

TEST(LightPick, LightsThatCannotReachThePointWeighNothing) {
    // Around p = origin with a receiver facing +Y, nine lights that each fail one reach test and
    // one that passes; their spatial weight must be 0, leaving only the global share.
    SceneSnapshot s;
    auto add = [&](LightRecord l) { s.lights.push_back(l); };
    LightRecord sphere;
    sphere.kind = LightRecord::Kind::Sphere;
    sphere.radius = 0.1f;
    sphere.center = glm::vec3(0, -2, 0);  // 0: below the receiver's plane
    add(sphere);
    LightRecord rect;
    rect.kind = LightRecord::Kind::Rect;
    rect.axisU = glm::vec3(0.5f, 0, 0);
    rect.axisV = glm::vec3(0, 0, 0.5f);
    rect.center = glm::vec3(0, 2, 0);
    rect.normal = glm::vec3(0, 1, 0);  // 1: emits upward, p lies behind it
    add(rect);
    LightRecord spot = sphere;
    spot.center = glm::vec3(3, 2, 0);
    spot.shaping.enabled = true;
    spot.shaping.axis = glm::vec3(0, -1, 0);
    spot.shaping.coneAngle = 0.3f;  // 2: aimed straight down at (3, 0, 0); p is 56 degrees off
    add(spot);
    LightRecord focused = spot;
    focused.shaping.coneAngle = 3.14159265f;
    focused.shaping.focus = 4.0f;     // 3: black-tinted focus emits nothing beyond 90 degrees;
    focused.shaping.axis = glm::vec3(0, 1, 0);  // aimed up, p below it
    add(focused);
    LightRecord sun;
    sun.kind = LightRecord::Kind::Distant;
    sun.direction = glm::vec3(0, 1, 0);  // 4: travels up: below the receiver's horizon
    sun.cosHalfAngle = std::cos(0.01f);
    add(sun);
    LightRecord lit = sphere;
    lit.center = glm::vec3(1, 2, 0);  // 5: reaches p
    add(lit);
    LightRecord wideSpot = spot;
    wideSpot.shaping.coneAngle = 1.1f;  // 6: 63 degrees, p at 56 degrees: reaches
    add(wideSpot);
    LightRecord dome;
    dome.kind = LightRecord::Kind::Dome;  // 7: always
    add(dome);
    setGlobalPick(s, std::vector<float>(s.lights.size(), 1.0f), 10.0f);
    const LightPick pick(s, true);
    ASSERT_TRUE(pick.spatial());
    float w[LightPick::kMaxLights];
    const glm::vec3 p(0.0f), up(0, 1, 0);
    const float t = pick.weigh(p, up, w);
    const float floor = LightPick::kGlobalShare / float(s.lights.size());
    for (uint32_t i = 0; i < 5; ++i) EXPECT_FLOAT_EQ(pick.probability(i, p, up, t), floor) << "light " << i;
    for (uint32_t i = 5; i < 8; ++i) EXPECT_GT(pick.probability(i, p, up, t), 2.0f * floor) << "light " << i;
    // Without a receiver (a transmitting surface) the lamp below and the sun count again.
    const float t0 = pick.weigh(p, glm::vec3(0.0f), w);
    EXPECT_GT(pick.probability(0, p, glm::vec3(0.0f), t0), 2.0f * floor);
    EXPECT_GT(pick.probability(4, p, glm::vec3(0.0f), t0), 2.0f * floor);
}
