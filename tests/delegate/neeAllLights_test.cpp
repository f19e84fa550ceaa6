// Next-event estimation on every light (setting neeAllLights) against picking one light by
// power: the same image in expectation (each light's pdf no longer carries a pick probability;
// forgetting that scales the direct light by the pick probability and fails the mean test), and
// less noise when a sun and a sky light the same point.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "delegate/renderBuffer.h"
#include "delegate/renderDelegate.h"
#include "delegate/renderPass.h"
#include "tests/support/orthoRender.h"
#include "tests/support/seedStatistics.h"
#include "tests/support/testSceneDelegate.h"

using namespace principled;
using principled::test::TestSceneDelegate;
using principled::test::translate;

namespace {

// A sphere on a diffuse floor under a soft sun (a disc of 5 degrees, tilted) and a sky dome,
// seen from above; red channel.
std::vector<float> render(int allLights, int seed) {
    test::OrthoRender r(24, 24, {{"convergedSamplesPerPixel", hd::Value(16)}, {"maxDepth", hd::Value(2)},
                                {"seed", hd::Value(seed)}, {"neeAllLights", hd::Value(allLights)}});
    TestSceneDelegate& scene = r.scene;
    scene.addQuad(hd::Path("/floor"), 10.0f);
    scene.addMaterial(hd::Path("/white"), {{hd::Token("diffuseColor"), hd::Value(glm::vec3(0.7f))},
                                           {hd::Token("roughness"), hd::Value(0.6f)}});
    scene.bind(hd::Path("/floor"), hd::Path("/white"));
    scene.addSphere(hd::Path("/ball"), 1.0f, translate(0, 0, 1));
    scene.bind(hd::Path("/ball"), hd::Path("/white"));
    glm::dmat4 tilt(1.0);  // the sun travels along -Z rotated 30 degrees about X
    double a = 30.0 * 3.14159265358979 / 180.0;
    tilt[1] = glm::dvec4(0, std::cos(a), std::sin(a), 0);
    tilt[2] = glm::dvec4(0, -std::sin(a), std::cos(a), 0);
    scene.addLight(hd::Path("/sun"), hd::tokens::distantLight(), tilt,
                   {{hd::Token("intensity"), hd::Value(300.0f)}, {hd::Token("angle"), hd::Value(5.0f)}});
    scene.addLight(hd::Path("/sky"), hd::tokens::domeLight(), glm::dmat4(1.0),
                   {{hd::Token("intensity"), hd::Value(0.5f)}});
    return r.redFromAbove(8, 6.0f);
}

using Stats = test::SeedStats;

Stats stats(int allLights) {
    return test::seedStatistics([&](int seed) { return render(allLights, seed); }, 200);
}

}  // namespace

TEST(NeeAllLights, SameMeanAsPickingOneLightAndLessNoise) {
    Stats pick = stats(0), all = stats(4);
    ASSERT_GT(pick.mean, 0.1);
    double tol = 4.0 * std::sqrt(pick.se * pick.se + all.se * all.se) + 1e-4 * pick.mean;
    EXPECT_NEAR(all.mean, pick.mean, tol) << "pick one " << pick.mean << " +- " << pick.se << ", all " << all.mean
                                          << " +- " << all.se;
    EXPECT_LT(all.pixelVar, pick.pixelVar) << "all " << all.pixelVar << ", pick one " << pick.pixelVar;
}
