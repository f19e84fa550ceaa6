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
#include "tests/support/seedStatistics.h"
#include "tests/support/testSceneDelegate.h"

using namespace principled;
using principled::test::TestSceneDelegate;
using principled::test::translate;

namespace {

// A sphere on a diffuse floor under a soft sun (a disc of 5 degrees, tilted) and a sky dome,
// seen from above; red channel.
std::vector<float> render(int allLights, int seed) {
    embree::EmbreeRenderDelegate delegate;
    hd::RenderIndex index(&delegate);
    TestSceneDelegate scene(&index);
    index.insertBprim(hd::tokens::renderBuffer(), &scene, hd::Path("/color"));
    auto* color = static_cast<embree::EmbreeRenderBuffer*>(index.bprim(hd::tokens::renderBuffer(), hd::Path("/color")));
    const int w = 24, h = 24;
    color->allocate(w, h, hd::Format::Float32Vec4, true);
    auto pass = delegate.createRenderPass(&index);
    delegate.setRenderSetting(hd::Token("convergedSamplesPerPixel"), hd::Value(16));
    delegate.setRenderSetting(hd::Token("maxDepth"), hd::Value(2));
    delegate.setRenderSetting(hd::Token("seed"), hd::Value(seed));
    delegate.setRenderSetting(hd::Token("neeAllLights"), hd::Value(allLights));
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
    scene.addCamera(hd::Path("/cam"), translate(0, 0, 8),
                    {{hd::Token("projection"), hd::Value(hd::Token("orthographic"))},
                     {hd::Token("horizontalAperture"), hd::Value(6.0f)},
                     {hd::Token("verticalAperture"), hd::Value(6.0f)}});
    index.sync();
    hd::RenderPassState s{hd::Path("/cam"), w, h, {{hd::tokens::color(), color}}};
    do pass->execute(s);
    while (!pass->isConverged());
    const float* p = static_cast<const float*>(color->map());
    std::vector<float> red(size_t(w) * h);
    for (size_t i = 0; i < red.size(); ++i) red[i] = p[4 * i];
    return red;
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
