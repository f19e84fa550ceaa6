// Mesh-light sampling by solid angle (lightSampling.cpp, Arvo 1995) against area sampling: the
// two estimators of the same image must agree in mean within their noise, and solid-angle
// sampling must be the less noisy one next to the emitter (where 1/r^2 varies most).
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

// A diffuse floor (4 x 4, z = 0) under a 1 x 1 emissive quad at z = 0.25, seen from above by an
// orthographic camera; direct light only. Returns the red channel.
std::vector<float> render(int solidAngle, int seed) {
    embree::EmbreeRenderDelegate delegate;
    hd::RenderIndex index(&delegate);
    TestSceneDelegate scene(&index);
    index.insertBprim(hd::tokens::renderBuffer(), &scene, hd::Path("/color"));
    auto* color = static_cast<embree::EmbreeRenderBuffer*>(index.bprim(hd::tokens::renderBuffer(), hd::Path("/color")));
    const int w = 32, h = 32;
    color->allocate(w, h, hd::Format::Float32Vec4, true);
    auto pass = delegate.createRenderPass(&index);
    delegate.setRenderSetting(hd::Token("convergedSamplesPerPixel"), hd::Value(16));
    delegate.setRenderSetting(hd::Token("maxDepth"), hd::Value(0));
    delegate.setRenderSetting(hd::Token("seed"), hd::Value(seed));
    delegate.setRenderSetting(hd::Token("lightSolidAngle"), hd::Value(solidAngle));
    scene.addQuad(hd::Path("/floor"), 4.0f);
    scene.addMaterial(hd::Path("/white"), {{hd::Token("diffuseColor"), hd::Value(glm::vec3(0.8f))},
                                           {hd::Token("ior"), hd::Value(1.0f)},
                                           {hd::Token("roughness"), hd::Value(1.0f)}});
    scene.bind(hd::Path("/floor"), hd::Path("/white"));
    scene.addQuad(hd::Path("/lamp"), 1.0f, translate(0, 0, 0.25));
    scene.addMaterial(hd::Path("/glow"), {{hd::Token("diffuseColor"), hd::Value(glm::vec3(0.0f))},
                                          {hd::Token("emissiveColor"), hd::Value(glm::vec3(4.0f))}});
    scene.bind(hd::Path("/lamp"), hd::Path("/glow"));
    scene.addCamera(hd::Path("/cam"), translate(0, 0, 5),
                    {{hd::Token("projection"), hd::Value(hd::Token("orthographic"))},
                     {hd::Token("horizontalAperture"), hd::Value(3.0f)},
                     {hd::Token("verticalAperture"), hd::Value(3.0f)}});
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

Stats stats(int solidAngle) {
    return test::seedStatistics([&](int seed) { return render(solidAngle, seed); }, 100);
}

}  // namespace

TEST(MeshLightSampling, SolidAngleAndAreaSamplingAgreeInMean) {
    Stats area = stats(0), solid = stats(1);
    ASSERT_GT(area.mean, 0.1);
    double tol = 4.0 * std::sqrt(area.se * area.se + solid.se * solid.se) + 1e-4 * area.mean;
    EXPECT_NEAR(solid.mean, area.mean, tol) << "area " << area.mean << " +- " << area.se << ", solid angle "
                                            << solid.mean << " +- " << solid.se;
    // The point of solid-angle sampling: lower per-pixel variance this close to the emitter.
    EXPECT_LT(solid.pixelVar, area.pixelVar) << "solid angle " << solid.pixelVar << ", area " << area.pixelVar;
}
