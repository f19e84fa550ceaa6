// Mesh-light sampling by solid angle (lightSampling.cpp, Arvo 1995) against area sampling: the
// two estimators of the same image must agree in mean within their noise, and solid-angle
// sampling must be the less noisy one next to the emitter (where 1/r^2 varies most).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "delegate/light.h"
#include "delegate/lightSampling.h"
#include "delegate/renderBuffer.h"
#include "delegate/renderDelegate.h"
#include "delegate/renderPass.h"
#include "delegate/sampler.h"
#include "tests/support/orthoRender.h"
#include "tests/support/seedStatistics.h"
#include "tests/support/testSceneDelegate.h"

using namespace principled;
using principled::test::TestSceneDelegate;
using principled::test::translate;

namespace {

// A diffuse floor (4 x 4, z = 0) under a 1 x 1 emissive quad at z = 0.25, seen from above by an
// orthographic camera; direct light only. Returns the red channel.
std::vector<float> render(int solidAngle, int seed) {
    test::OrthoRender r(32, 32, {{"convergedSamplesPerPixel", hd::Value(16)}, {"maxDepth", hd::Value(0)},
                                {"seed", hd::Value(seed)}, {"lightSolidAngle", hd::Value(solidAngle)}});
    TestSceneDelegate& scene = r.scene;
    scene.addQuad(hd::Path("/floor"), 4.0f);
    scene.addMaterial(hd::Path("/white"), {{hd::Token("diffuseColor"), hd::Value(glm::vec3(0.8f))},
                                           {hd::Token("ior"), hd::Value(1.0f)},
                                           {hd::Token("roughness"), hd::Value(1.0f)}});
    scene.bind(hd::Path("/floor"), hd::Path("/white"));
    scene.addQuad(hd::Path("/lamp"), 1.0f, translate(0, 0, 0.25));
    scene.addMaterial(hd::Path("/glow"), {{hd::Token("diffuseColor"), hd::Value(glm::vec3(0.0f))},
                                          {hd::Token("emissiveColor"), hd::Value(glm::vec3(4.0f))}});
    scene.bind(hd::Path("/lamp"), hd::Path("/glow"));
    return r.redFromAbove(5, 3.0f);
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

// A mesh light record built directly: a 2 x 1 quad (two triangles), moved by a transform. Every
// light sample lands on the quad at the distance sampleLight() reports, and its pdf is the one
// meshLightPdf() gives the same direction, near the light (solid angle) and far (area).
TEST(MeshLightSampling, SamplesLandOnTheLightWithTheIntersectionPdf) {
    embree::GeometryRecord g;
    g.points = {{-1, -0.5f, 0}, {1, -0.5f, 0}, {1, 0.5f, 0}, {-1, 0.5f, 0}};
    g.triangles = {{0, 1, 2}, {0, 2, 3}};
    g.objectToWorld = glm::mat4(glm::vec4(0, 1, 0, 0), glm::vec4(-1, 0, 0, 0), glm::vec4(0, 0, 1, 0),
                                glm::vec4(0.5f, 0.25f, 2.0f, 1));  // rotate 90 degrees about z, translate
    embree::LightRecord l;
    l.kind = embree::LightRecord::Kind::Mesh;
    l.radiance = glm::vec3(1.0f);
    l.mesh = &g;
    l.meshTriangles = std::make_shared<std::vector<uint32_t>>(std::vector<uint32_t>{0, 1});
    l.meshAreaCdf = std::make_shared<std::vector<float>>(std::vector<float>{0.0f, 0.5f, 1.0f});
    l.area = 2.0f;
    l.center = glm::vec3(0.5f, 0.25f, 2.0f);
    l.radius = std::sqrt(1.25f);
    embree::prepareMeshLight(&l);
    ASSERT_EQ(l.meshWorld->size(), 2u);
    EXPECT_NEAR((*l.meshWorld)[0].area + (*l.meshWorld)[1].area, 2.0f, 1e-5f);
    // World corners: x in [0.5 - 0.5, 0.5 + 0.5], y in [0.25 - 1, 0.25 + 1], z = 2.
    for (glm::vec3 p : {glm::vec3(0.3f, 0.1f, 1.5f), glm::vec3(2.0f, -1.0f, 0.5f), glm::vec3(0.5f, 0.2f, 2.5f),
                        glm::vec3(1.0f, 2.0f, -30.0f)}) {  // near below, near oblique, above, far
        for (uint32_t i = 0; i < 256; ++i) {
            embree::Sampler s(embree::SamplerKind::Sobol, 5, 0, i);
            embree::LightSample ls;
            ASSERT_TRUE(embree::sampleLight(l, p, glm::vec3(0, 0, 1), s.next2D(), &ls));
            glm::vec3 q = p + ls.distance * ls.wi;
            EXPECT_NEAR(q.z, 2.0f, 1e-4f);
            EXPECT_TRUE(q.x >= -1e-4f && q.x <= 1.0f + 1e-4f && q.y >= -0.75f - 1e-4f && q.y <= 1.25f + 1e-4f)
                << q.x << " " << q.y;
            float pdf = embree::meshLightPdf(l, p, ls.distance, ls.wi.z);
            EXPECT_NEAR(ls.pdf, pdf, 1e-4f * pdf);
        }
    }
}
