// End-to-end renders through the render index with an in-memory scene delegate: analytic
// radiance, determinism across thread counts, and restarts on edits.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "delegate/hd/camera.h"
#include "delegate/renderBuffer.h"
#include "delegate/renderDelegate.h"
#include "delegate/renderParam.h"
#include "delegate/renderPass.h"
#include "delegate/shadingNormal.h"
#include "tests/support/testSceneDelegate.h"

using namespace principled;
using principled::test::TestSceneDelegate;
using principled::test::translate;

namespace {

constexpr float kPi = 3.14159265358979323846f;

struct Fixture {
    embree::EmbreeRenderDelegate delegate;
    hd::RenderIndex index{&delegate};
    TestSceneDelegate scene{&index};
    embree::EmbreeRenderBuffer* color = nullptr;
    std::unique_ptr<hd::RenderPass> pass;
    int w, h;

    Fixture(int width, int height) : w(width), h(height) {
        index.insertBprim(hd::tokens::renderBuffer(), &scene, hd::Path("/color"));
        color = static_cast<embree::EmbreeRenderBuffer*>(
            index.bprim(hd::tokens::renderBuffer(), hd::Path("/color")));
        color->allocate(w, h, hd::Format::Float32Vec4, true);
        pass = delegate.createRenderPass(&index);
    }
    void render() {
        index.sync();
        hd::RenderPassState s{hd::Path("/cam"), w, h, {{hd::tokens::color(), color}}};
        do pass->execute(s);
        while (!pass->isConverged());
    }
    std::vector<float> pixels() const {
        const float* p = static_cast<const float*>(color->map());
        return std::vector<float>(p, p + size_t(w) * h * 4);
    }
    /// A delta distant light of irradiance E placed by `light` (default: shining along -Z) and an
    /// orthographic 1 x 1 camera 5 above the origin looking down; renders and returns the mean red.
    double renderSunlitFromAbove(float E, const glm::dmat4& light = glm::dmat4(1.0)) {
        scene.addLight(hd::Path("/sun"), hd::tokens::distantLight(), light,
                       {{hd::Token("intensity"), hd::Value(E)}, {hd::Token("angle"), hd::Value(0.0f)}});
        scene.addCamera(hd::Path("/cam"), test::translate(0, 0, 5),
                        {{hd::Token("projection"), hd::Value(hd::Token("orthographic"))},
                         {hd::Token("horizontalAperture"), hd::Value(1.0f)},
                         {hd::Token("verticalAperture"), hd::Value(1.0f)}});
        render();
        auto px = pixels();
        double mean = 0.0;
        for (int i = 0; i < w * h; ++i) mean += px[4 * i];
        return mean / (w * h);
    }
};

}  // namespace

// A Lambertian plane of albedo a lit head-on by a distant light of irradiance E has radiance
// a E / pi (the diffuse BRDF is a/pi; Burley's retro-reflection factor is 1 at normal incidence).
class LambertPlane : public ::testing::TestWithParam<const char*> {};

TEST_P(LambertPlane, RadianceIsAlbedoTimesIrradianceOverPi) {
    Fixture f(16, 16);
    f.delegate.setRenderSetting(hd::Token("convergedSamplesPerPixel"), hd::Value(4));
    f.delegate.setRenderSetting(hd::Token("shadingModel"), hd::Value(hd::Token(GetParam())));
    const float albedo = 0.5f, E = 3.0f;
    f.scene.addQuad(hd::Path("/plane"), 4.0f);
    f.scene.addMaterial(hd::Path("/mat"), {{hd::Token("diffuseColor"), hd::Value(glm::vec3(albedo))},
                                           {hd::Token("ior"), hd::Value(1.0f)},  // specular 0
                                           {hd::Token("roughness"), hd::Value(1.0f)}});
    f.scene.bind(hd::Path("/plane"), hd::Path("/mat"));
    // Distant light along -Z (its default direction), angle 0: a delta light of irradiance E.
    const double mean = f.renderSunlitFromAbove(E);
    auto px = f.pixels();
    double expected = albedo * E / kPi;
    EXPECT_NEAR(mean, expected, 0.01 * expected) << "model " << GetParam();
    EXPECT_FLOAT_EQ(px[3], 1.0f);  // alpha: geometry was hit
}

INSTANTIATE_TEST_SUITE_P(Models, LambertPlane, ::testing::Values("disney", "ue4"));

namespace {
std::vector<float> noisyScene(int threads, int seed) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    Fixture f(24, 16);
    f.delegate.setRenderSetting(hd::Token("convergedSamplesPerPixel"), hd::Value(3));
    f.delegate.setRenderSetting(hd::Token("seed"), hd::Value(seed));
    f.scene.addSphere(hd::Path("/ball"), 1.0f);
    f.scene.addQuad(hd::Path("/floor"), 10.0f, translate(0, 0, -1));
    f.scene.addLight(hd::Path("/sky"), hd::tokens::domeLight(), glm::dmat4(1.0), {});
    f.scene.addCamera(hd::Path("/cam"), translate(0, 0, 8), {});
    f.render();
    return f.pixels();
}
}  // namespace

TEST(Render, SameSeedGivesTheSameImageOnAnyThreadCount) {
    auto one = noisyScene(1, 7), two = noisyScene(2, 7);
    ASSERT_EQ(one.size(), two.size());
    EXPECT_TRUE(one == two);  // bit-identical
    auto other = noisyScene(2, 8);
    EXPECT_FALSE(one == other);
    double sum = 0.0;
    for (float v : one) {
        ASSERT_TRUE(std::isfinite(v));
        sum += v;
    }
    EXPECT_GT(sum, 0.0);
}

TEST(Render, MaterialEditRestartsWithoutRebuildingGeometry) {
    Fixture f(8, 8);
    f.delegate.setRenderSetting(hd::Token("convergedSamplesPerPixel"), hd::Value(2));
    f.scene.addSphere(hd::Path("/ball"), 1.0f);
    f.scene.addMaterial(hd::Path("/mat"), {{hd::Token("diffuseColor"), hd::Value(glm::vec3(0.2f))}});
    f.scene.bind(hd::Path("/ball"), hd::Path("/mat"));
    f.scene.addLight(hd::Path("/sky"), hd::tokens::domeLight(), glm::dmat4(1.0), {});
    f.scene.addCamera(hd::Path("/cam"), translate(0, 0, 6), {});
    f.render();
    auto before = f.pixels();
    double builds = f.delegate.renderStats()["blasBuilds"];
    f.scene.prim(hd::Path("/mat")).network.nodes[0].parameters[hd::Token("diffuseColor")] =
        hd::Value(glm::vec3(0.8f));
    f.index.changeTracker().markSprimDirty(hd::Path("/mat"), hd::SprimDirty::MaterialParams);
    f.render();
    auto after = f.pixels();
    EXPECT_EQ(f.delegate.renderStats()["blasBuilds"], builds);
    size_t center = (4 * 8 + 4) * 4;
    EXPECT_GT(after[center], 2.0f * before[center]);  // brighter, and restarted (not averaged)
}

TEST(Render, BadMeshIsSkippedWithAWarning) {
    Fixture f(8, 8);
    f.delegate.setRenderSetting(hd::Token("convergedSamplesPerPixel"), hd::Value(1));
    f.scene.addQuad(hd::Path("/bad"), 1.0f);
    f.scene.prim(hd::Path("/bad")).topology.faceVertexIndices = {0, 1, 2, 7};
    f.scene.prim(hd::Path("/bad")).values[hd::tokens::points()] =
        std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {1, 1, NAN}, {0, 1, 0}};
    f.scene.addCamera(hd::Path("/cam"), translate(0, 0, 6), {});
    f.render();
    auto warnings = f.delegate.takeWarnings();
    ASSERT_FALSE(warnings.empty());
    EXPECT_NE(warnings[0].find("/bad"), std::string::npos);
    for (float v : f.pixels()) EXPECT_TRUE(std::isfinite(v));
}

// Thin-lens depth of field (UsdGeomCamera fStop, focusDistance). An emissive half-plane x >= 0
// at depth Z seen by a camera focused at F: a lens of radius R = focalLength / (2 fStop) spreads
// each scene point over an image-plane disk of radius r = R |1/Z - 1/F| (window units at unit
// distance; Pharr et al. 2023, PBR 4th ed., §5.2.3, circle of confusion), so the edge's profile
// is the edge spread function of a uniform disk: the disk's area fraction left of the offset,
// ESF(s) = 1/2 + (s sqrt(r^2 - s^2) + r^2 asin(s / r)) / (pi r^2), box-filtered over a pixel.
namespace {

std::vector<double> edgeProfile(float fStop, float focus, float depth, int w, int h, int spp) {
    Fixture f(w, h);
    f.delegate.setRenderSetting(hd::Token("convergedSamplesPerPixel"), hd::Value(spp));
    f.scene.addQuad(hd::Path("/half"), 20.0f, translate(10.0, 0.0, -depth));  // x in [0, 20]
    f.scene.addMaterial(hd::Path("/glow"), {{hd::Token("diffuseColor"), hd::Value(glm::vec3(0.0f))},
                                            {hd::Token("emissiveColor"), hd::Value(glm::vec3(1.0f))},
                                            {hd::Token("ior"), hd::Value(1.0f)}});
    f.scene.bind(hd::Path("/half"), hd::Path("/glow"));
    // Window 1 x (h / w) at unit distance: focal length 0.5, apertures 0.5 and 0.5 h / w.
    f.scene.addCamera(hd::Path("/cam"), glm::dmat4(1.0),
                      {{hd::Token("focalLength"), hd::Value(0.5f)},
                       {hd::Token("horizontalAperture"), hd::Value(0.5f)},
                       {hd::Token("verticalAperture"), hd::Value(0.5f * float(h) / float(w))},
                       {hd::Token("clippingRange"), hd::Value(glm::vec2(0.01f, 100.0f))},
                       {hd::Token("fStop"), hd::Value(fStop)},
                       {hd::Token("focusDistance"), hd::Value(focus)}});
    f.render();
    auto px = f.pixels();
    std::vector<double> profile(w, 0.0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) profile[x] += px[4 * (size_t(y) * w + x)] / h;
    return profile;
}

// The uniform-disk edge spread function above, averaged over pixel x (window [-0.5, 0.5]).
double expectedEdge(int x, int w, double r) {
    double sum = 0.0;
    const int sub = 64;
    for (int i = 0; i < sub; ++i) {
        double s = -0.5 + (x + (i + 0.5) / sub) / w;  // window position of the sub-sample
        if (r <= 0.0) {
            sum += s >= 0.0 ? 1.0 : 0.0;
            continue;
        }
        double c = std::clamp(s, -r, r);
        sum += 0.5 + (c * std::sqrt(r * r - c * c) + r * r * std::asin(c / r)) / (kPi * r * r);
    }
    return sum / sub;
}

double rmsAgainst(const std::vector<double>& profile, int w, double r) {
    double e = 0.0;
    for (int x = 0; x < w; ++x) e += std::pow(profile[x] - expectedEdge(x, w, r), 2);
    return std::sqrt(e / w);
}

}  // namespace

TEST(Render, DepthOfFieldBlursByTheThinLensCircleOfConfusion) {
    const int w = 128, h = 8, spp = 256;
    // R = 0.5 / (2 fStop) = 0.15625 at fStop 1.6; Z = 2, F = 1: r = R |1/2 - 1| = 0.078 (10 px).
    const float fStop = 1.6f, focus = 1.0f, depth = 2.0f;
    const double r = 0.5 / (2.0 * fStop) * std::abs(1.0 / depth - 1.0 / focus);
    auto blurred = edgeProfile(fStop, focus, depth, w, h, spp);
    EXPECT_LT(rmsAgainst(blurred, w, r), 0.004);  // measured 0.001; a 20 % larger r gives 0.017
    EXPECT_GT(rmsAgainst(blurred, w, 0.0), 0.1);  // visibly not the sharp edge
    // The same lens focused on the plane, and a pinhole (fStop 0): a sharp edge.
    EXPECT_LT(rmsAgainst(edgeProfile(fStop, depth, depth, w, h, spp), w, 0.0), 0.01);
    EXPECT_LT(rmsAgainst(edgeProfile(0.0f, focus, depth, w, h, spp), w, 0.0), 0.01);
    // focusDistance 0 (the schema fallback) is a pinhole too, not a blur of everything.
    EXPECT_LT(rmsAgainst(edgeProfile(fStop, 0.0f, depth, w, h, spp), w, 0.0), 0.01);
}

// A normal map tilting the shading normal 30 degrees toward a distant light 60 degrees from the
// plane's normal: Lambert gives a E / pi (n.wi) with n.wi = cos 30, and the diffuse lobe is
// shadowed by the plane (Chiang et al. 2019, bsdf/bumpShadowing.h): G = cos 60 / cos^2 30 = 2/3,
// factor -G^3 + G^2 + G = 22/27, as Cycles 3.4 renders it (bench/blender_parity.py normal_map).
// bumpShadowing = 0 leaves the unshadowed a E / pi (n.wi).
namespace {

// Mean radiance of a normal-mapped Lambert-like plane z = 0 (UE4 model, albedo 0.5, ior 1, rough
// 1, 8x8 orthographic view straight down, direct light only) under a delta distant light of
// irradiance 3 tilted `lightDeg` toward +X. st = (x, y), so the tangent is +X; `normals`, when
// given, are authored per vertex.
double normalMappedPlane(const glm::vec3& tangentNormal, float lightDeg, int bumpShadowing,
                         const glm::vec3* normals = nullptr) {
    Fixture f(8, 8);
    f.delegate.setRenderSetting(hd::Token("convergedSamplesPerPixel"), hd::Value(4));
    f.delegate.setRenderSetting(hd::Token("maxDepth"), hd::Value(0));
    f.delegate.setRenderSetting(hd::Token("shadingModel"), hd::Value(hd::Token("ue4")));
    f.delegate.setRenderSetting(hd::Token("bumpShadowing"), hd::Value(bumpShadowing));
    f.scene.addQuad(hd::Path("/plane"), 4.0f);
    auto& plane = f.scene.prim(hd::Path("/plane"));
    plane.values[hd::Token("st")] = std::vector<glm::vec2>{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    plane.interpolation[hd::Token("st")] = hd::Interpolation::Vertex;
    if (normals) {
        plane.values[hd::tokens::normals()] = std::vector<glm::vec3>(4, *normals);
        plane.interpolation[hd::tokens::normals()] = hd::Interpolation::Vertex;
    }
    f.scene.addMaterial(hd::Path("/mat"), {{hd::Token("diffuseColor"), hd::Value(glm::vec3(0.5f))},
                                           {hd::Token("ior"), hd::Value(1.0f)},
                                           {hd::Token("roughness"), hd::Value(1.0f)},
                                           {hd::Token("normal"), hd::Value(tangentNormal)}});
    f.scene.bind(hd::Path("/plane"), hd::Path("/mat"));
    // The light's +Z (toward the light; it shines along -Z) rotated toward +X: rows of the
    // row-vector matrix, so (0, 0, 1) M = (sin a, 0, cos a).
    const double a = double(lightDeg) * kPi / 180.0;
    glm::dmat4 rot(1.0);
    rot[0] = glm::dvec4(std::cos(a), 0.0, -std::sin(a), 0.0);
    rot[2] = glm::dvec4(std::sin(a), 0.0, std::cos(a), 0.0);
    return f.renderSunlitFromAbove(3.0f, rot);
}

}  // namespace

class TiltedNormalPlane : public ::testing::TestWithParam<int> {};

TEST_P(TiltedNormalPlane, DiffuseIsShadowedByTheSurface) {
    const int shadowing = GetParam();
    const float albedo = 0.5f, E = 3.0f, s30 = 0.5f, c30 = std::sqrt(3.0f) / 2.0f;
    const double mean = normalMappedPlane(glm::vec3(s30, 0.0f, c30), 60.0f, shadowing);
    const double unshadowed = albedo * E / kPi * c30;
    const double expected = shadowing ? unshadowed * 22.0 / 27.0 : unshadowed;
    EXPECT_NEAR(mean, expected, 0.01 * expected)
        << "bumpShadowing " << shadowing << ": expected " << expected << " (unshadowed "
        << unshadowed << ")";
}

INSTANTIATE_TEST_SUITE_P(BumpShadowing, TiltedNormalPlane, ::testing::Values(1, 0));

// A normal map is applied in the tangent frame of the surface's own interpolated normal, and the
// result is bent once (Cycles 3.4: svm_node_normal_map uses the smooth normal; the closure then
// applies ensure_valid_reflection). Mapping it around the already-bent interpolated normal made
// the result depend on the view twice. Plane z = 0 with authored normals tilted 60 degrees toward
// +Y, seen straight down (that normal is bent, to 44.7 degrees), a map tilting 20 degrees toward
// +X, a delta light 30 degrees toward +X: radiance a E / pi (N.wi) bumpShadowing, N the mapped
// normal bent once (the view's mirror direction then grazes the plane).
TEST(Render, NormalMapUsesTheUnbentInterpolatedNormal) {
    const float albedo = 0.5f, E = 3.0f, kDeg = kPi / 180.0f;
    const glm::vec3 n0(0.0f, std::sin(60 * kDeg), std::cos(60 * kDeg));
    const glm::vec3 tangentNormal(std::sin(20 * kDeg), 0.0f, std::cos(20 * kDeg));
    const double mean = normalMappedPlane(tangentNormal, 30.0f, 1, &n0);
    const glm::vec3 wi(0.5f, 0.0f, std::sqrt(3.0f) / 2.0f);
    // The expected shading normal: tangent frame (t = +X from st, b = n x t) around n, then bent.
    const glm::vec3 ng(0, 0, 1), wo(0, 0, 1);
    auto shade = [&](const glm::vec3& frameNormal) {
        const glm::vec3 t(1, 0, 0), b = glm::cross(frameNormal, t);
        glm::vec3 m = glm::normalize(tangentNormal.x * t + tangentNormal.y * b + tangentNormal.z * frameNormal);
        glm::vec3 n = embree::validReflectionNormal(ng, wo, m);
        // bumpShadowing in n's frame: the smooth normal n0 seen from n.
        const float g = glm::dot(n0, wi) / (glm::dot(n, wi) * glm::dot(n0, n));
        const float k = g >= 1.0f ? 1.0f : (-g * g * g + g * g + g);
        return albedo * E / kPi * glm::dot(n, wi) * k;
    };
    const double expected = shade(n0);
    const double viewTwice = shade(embree::validReflectionNormal(ng, wo, n0));
    ASSERT_GT(std::abs(viewTwice / expected - 1.0), 0.02);  // the two orders are distinguishable
    EXPECT_NEAR(mean, expected, 0.005 * expected)
        << "mapping around the bent normal would give " << viewTwice;
}

// Texture versions retired by TextureCache::invalidate() (lookups may still hold them while a
// pass runs) are freed at the next commit, when no pass runs.
TEST(Render, CommitFreesTexturesRetiredByInvalidate) {
    embree::EmbreeRenderDelegate delegate;
    auto* param = static_cast<embree::EmbreeRenderParam*>(delegate.renderParam());
    ASSERT_NE(param->textureCache(), nullptr);
    shading::TextureCache& cache = *param->textureCache();
    const std::string path = ::testing::TempDir() + "principled_commit_retired_" +
                             std::to_string(::getpid()) + ".exr";
    {
        auto out = OIIO::ImageOutput::create(path);
        ASSERT_TRUE(out);
        std::vector<float> px(4 * 4 * 3, 0.5f);
        ASSERT_TRUE(out->open(path, OIIO::ImageSpec(4, 4, 3, OIIO::TypeDesc::FLOAT)));
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
        ASSERT_TRUE(out->close());
    }
    ASSERT_NE(cache.open(path).texture, nullptr);
    cache.invalidate();
    EXPECT_EQ(cache.retiredBytes(), size_t(4) * 4 * 3 * 4);
    delegate.commitResources(nullptr);
    EXPECT_EQ(cache.retiredBytes(), 0u);
    std::remove(path.c_str());
}
