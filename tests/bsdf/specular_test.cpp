// SPDX-License-Identifier: Apache-2.0
#include "bsdf/specular.h"

#include "bsdf/bsdf.h"
#include "testUtil.h"

namespace principled::bsdf {
namespace {

Specular ggx(float roughness, float anisotropic = 0.0f, glm::vec3 f0 = glm::vec3(1.0f)) {
    Specular s;
    glm::vec2 a = disneyAlpha(roughness, anisotropic);
    s.dist = {a.x, a.y};
    s.f0 = f0;
    return s;
}

Specular ue4(float roughness) {
    Specular s = ggx(roughness);
    s.gModel = SpecularG::SchlickSmith;
    s.gParam = sqr(roughness + 1.0f) / 8.0f;
    s.fModel = SpecularFresnel::SchlickSG;
    return s;
}

TEST(Specular, AnalyticNormalIncidence) {
    // wo = wi = n: D = 1/(pi a^2), G = 1, F = F0 -> f cos = F0 / (4 pi a^2).
    Specular s = ggx(0.5f, 0.0f, glm::vec3(0.04f));
    glm::vec3 n(0, 0, 1);
    EXPECT_NEAR(s.eval(n, n).x, 0.04f / (4.0f * kPi * 0.0625f), 1e-6f);
    // Schlick-Smith at normal incidence: G1 = 1 / ((1 - k) + k) = 1.
    EXPECT_NEAR(ue4(0.5f).eval(n, n).x, 1.0f / (4.0f * kPi * 0.0625f), 1e-5f);
    EXPECT_FLOAT_EQ(s.eval(n, -n).x, 0.0f);
}

TEST(Specular, Reciprocity) {
    Pcg32 rng(17);
    std::vector<Specular> lobes = {ggx(0.4f, 0.7f, glm::vec3(0.9f, 0.5f, 0.1f)), ue4(0.3f)};
    Specular legacy = ggx(0.4f);
    legacy.gModel = SpecularG::SmithRemapped;
    legacy.gParam = sqr(0.5f + 0.5f * 0.4f);
    lobes.push_back(legacy);
    for (const auto& s : lobes)
        for (int i = 0; i < 500; ++i) {
            glm::vec3 a = test::randomUpper(rng), b = test::randomUpper(rng);
            if (a.z < 1e-2f || b.z < 1e-2f) continue;
            float fab = s.eval(a, b).x / b.z, fba = s.eval(b, a).x / a.z;
            EXPECT_LE(test::relErr(fab, fba), 1e-4f);
        }
}

// reference/bsdf.md §4.3: GGX single scattering with F = 1, separable G.
TEST(Specular, AlbedoTableGgx) {
    const float rough[5] = {0.1f, 0.25f, 0.5f, 0.75f, 1.0f};
    const float mus[3] = {1.0f, 0.5f, 0.1f};
    const float ref[5][3] = {{1.000f, 1.000f, 0.994f}, {0.996f, 0.988f, 0.892f},
                             {0.916f, 0.855f, 0.855f}, {0.627f, 0.647f, 0.746f},
                             {0.307f, 0.409f, 0.558f}};
    for (int r = 0; r < 5; ++r)
        for (int m = 0; m < 3; ++m)
            EXPECT_NEAR(test::lobeAlbedoSampled(ggx(rough[r]), test::muDirection(mus[m]), 200000),
                        ref[r][m], 0.01)
                << "roughness " << rough[r] << " mu " << mus[m];
}

// reference/bsdf.md §4.3: UE4 specular albedo, Schlick-G with analytic k, F = 1.
TEST(Specular, AlbedoTableUe4) {
    const float rough[4] = {0.1f, 0.25f, 0.5f, 1.0f};
    const float mus[3] = {1.0f, 0.5f, 0.1f};
    const float ref[4][3] = {{1.000f, 0.754f, 0.183f}, {0.988f, 0.691f, 0.196f},
                             {0.860f, 0.585f, 0.360f}, {0.307f, 0.409f, 0.558f}};
    for (int r = 0; r < 4; ++r)
        for (int m = 0; m < 3; ++m)
            EXPECT_NEAR(test::lobeAlbedoSampled(ue4(rough[r]), test::muDirection(mus[m]), 200000),
                        ref[r][m], 0.01)
                << "roughness " << rough[r] << " mu " << mus[m];
}

TEST(Specular, SampledAndUniformAlbedoAgree) {
    Specular s = ggx(0.6f, 0.5f, glm::vec3(0.5f));
    glm::vec3 wo = test::muDirection(0.6f, 0.3f);
    EXPECT_NEAR(test::lobeAlbedoSampled(s, wo), test::lobeAlbedoUniform(s, wo, 1000000), 0.01);
}

TEST(Specular, Chi2VisibleAndClassic) {
    const int n = 6;
    for (bool visible : {true, false}) {
        Specular a = ggx(0.5f), b = ggx(0.3f, 0.8f), c = ggx(1.0f);
        for (Specular* s : {&a, &b, &c}) {
            s->visible = visible;
            for (float theta : {30.0f, 80.0f}) {
                auto r = test::lobeChi2(*s, theta, n * 2);
                EXPECT_TRUE(r.passed) << "visible " << visible << " theta " << theta << " " << r.message;
                EXPECT_LE(r.pdfIntegral, 1.002);
            }
        }
    }
}

TEST(Specular, DeltaMirror) {
    Specular s = ggx(0.0f, 0.0f, glm::vec3(0.04f));
    s.delta = true;
    glm::vec3 wo = directionFromAngles(40, 10);
    auto smp = s.sample(wo, {0.3f, 0.7f}, 0.5f);
    ASSERT_TRUE(smp);
    EXPECT_TRUE(smp->delta);
    EXPECT_NEAR(smp->wi.x, -wo.x, 1e-6f);
    EXPECT_NEAR(smp->wi.z, wo.z, 1e-6f);
    EXPECT_NEAR(smp->f.x / smp->pdf, schlickFresnel(0.04f, wo.z), 1e-6f);
    EXPECT_FLOAT_EQ(s.eval(wo, smp->wi).x, 0.0f);
    EXPECT_FLOAT_EQ(s.pdf(wo, smp->wi), 0.0f);
}

// Options::dielectricFresnel (Cycles 3.4's Principled v1 Fresnel): a dielectric of specular
// 0.5 follows the exact Fresnel of eta 1.5; a metal blends its base colour to white along the
// same curve, normalised to 0 at normal incidence; Schlick stays the default.
TEST(Specular, DielectricBlendFresnelThroughTheDisneyModel) {
    MaterialParams p = cliDefaults();
    p.metallic = 0.0f;
    p.specular = 0.5f;
    p.specularTint = 0.0f;
    Options o;
    o.dielectricFresnel = true;
    const Specular d = Bsdf(p, o).lobeSet().specular;
    EXPECT_EQ(d.fModel, SpecularFresnel::DielectricBlend);
    EXPECT_NEAR(d.eta, 1.5f, 1e-5f);
    for (float c : {1.0f, 0.8f, 0.5f, 0.2f, 0.05f})
        EXPECT_NEAR(d.fresnel(c).x, fresnelDielectric(c, 1.5f), 1e-5f) << "cos " << c;
    // At cos 0.5 the exact curve is above Schlick's (0.0892 against 0.0700).
    EXPECT_GT(d.fresnel(0.5f).x, schlickFresnel(0.04f, 0.5f) + 0.015f);

    p.metallic = 1.0f;
    p.baseColor = glm::vec3(1.0f, 0.77f, 0.34f);
    const Specular m = Bsdf(p, o).lobeSet().specular;
    const float w = (fresnelDielectric(0.5f, 1.5f) - 0.04f) / 0.96f;
    EXPECT_NEAR(m.fresnel(1.0f).z, 0.34f, 1e-5f);
    EXPECT_NEAR(m.fresnel(0.5f).z, 0.34f + 0.66f * w, 1e-5f);
    EXPECT_NEAR(m.fresnel(0.0f).z, 1.0f, 1e-5f);

    const Specular schlick = Bsdf(p, Options{}).lobeSet().specular;
    EXPECT_EQ(schlick.fModel, SpecularFresnel::Schlick);
    EXPECT_NEAR(schlick.fresnel(0.5f).z, schlickFresnel(glm::vec3(0.34f), 0.5f).z, 1e-6f);

    // Specular 0 (eta 1): no lobe colour from the blend, and nothing undefined.
    p.metallic = 0.0f;
    p.specular = 0.0f;
    const Specular zero = Bsdf(p, o).lobeSet().specular;
    for (float c : {1.0f, 0.5f, 0.0f}) EXPECT_EQ(zero.fresnel(c), glm::vec3(0.0f)) << "cos " << c;
}

}  // namespace
}  // namespace principled::bsdf
