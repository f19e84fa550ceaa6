// SPDX-License-Identifier: Apache-2.0
// The facade: whole-material statistics, consistency, lobe selection, delta lobes, pruning,
// robustness and golden values.
#include "bsdf/bsdf.h"

#include "testUtil.h"

namespace principled::bsdf {
namespace {

MaterialParams white() { return cliDefaults(); }

Options disney() { return Options{}; }
Options ue4() {
    Options o;
    o.model = Model::UE4;
    return o;
}

// reference/bsdf.md §4.3: full wdas Disney BRDF, white baseColor, separable G.
TEST(Bsdf, DisneyAlbedoTable) {
    struct Row { float roughness, metallic, specular, sheen, clearcoat; float ref[4]; };
    const Row rows[] = {
        {0.2f, 0, 0.5f, 0, 0, {1.028f, 1.051f, 1.222f, 1.305f}},
        {0.5f, 0, 0.5f, 0, 0, {1.043f, 1.064f, 1.148f, 1.189f}},
        {1.0f, 0, 0.5f, 0, 0, {1.048f, 1.076f, 1.274f, 1.503f}},
        {0.5f, 0, 1.0f, 0, 0, {1.079f, 1.097f, 1.178f, 1.218f}},
        {0.2f, 1, 0.5f, 0, 0, {0.998f, 0.995f, 0.975f, 0.884f}},
        {0.5f, 1, 0.5f, 0, 0, {0.916f, 0.855f, 0.832f, 0.875f}},
        {1.0f, 1, 0.5f, 0, 0, {0.307f, 0.409f, 0.511f, 0.584f}},
        {0.5f, 0, 0.5f, 1, 0, {1.043f, 1.079f, 1.196f, 1.266f}},
        {0.5f, 0, 0.5f, 0, 1, {1.052f, 1.079f, 1.192f, 1.220f}},
    };
    const float mus[4] = {1.0f, 0.5f, 0.2f, 0.05f};
    for (const auto& row : rows) {
        MaterialParams p = white();
        p.roughness = row.roughness;
        p.metallic = row.metallic;
        p.specular = row.specular;
        p.sheen = row.sheen;
        p.clearcoat = row.clearcoat;
        p.clearcoatGloss = 1.0f;
        Bsdf b(p, disney());
        for (int m = 0; m < 4; ++m) {
            AlbedoResult a = directionalAlbedo(b, mus[m], 250000);
            EXPECT_NEAR(a.albedo.x, row.ref[m], 0.01)
                << "roughness " << row.roughness << " metallic " << row.metallic << " specular "
                << row.specular << " sheen " << row.sheen << " clearcoat " << row.clearcoat
                << " mu " << mus[m];
        }
    }
}

TEST(Bsdf, Ue4AlbedoTableThroughFacade) {
    // Metallic white: F0 = 1, only the specular lobe (reference/bsdf.md §4.3, UE4 analytic k).
    const float rough[4] = {0.1f, 0.25f, 0.5f, 1.0f};
    const float ref[4][3] = {{1.000f, 0.754f, 0.183f}, {0.988f, 0.691f, 0.196f},
                             {0.860f, 0.585f, 0.360f}, {0.307f, 0.409f, 0.558f}};
    const float mus[3] = {1.0f, 0.5f, 0.1f};
    for (int r = 0; r < 4; ++r) {
        MaterialParams p = white();
        p.metallic = 1.0f;
        p.roughness = rough[r];
        Bsdf b(p, ue4());
        for (int m = 0; m < 3; ++m)
            EXPECT_NEAR(directionalAlbedo(b, mus[m], 250000).albedo.x, ref[r][m], 0.01);
    }
}

TEST(Bsdf, LambertianFurnaceIsOne) {
    MaterialParams p = white();
    p.specular = 0.0f;
    Options o = ue4();
    o.lobeMask = lobeBit(Lobe::Diffuse);
    Bsdf b(p, o);
    for (float mu : {1.0f, 0.5f, 0.1f}) EXPECT_NEAR(directionalAlbedo(b, mu, 10000).albedo.x, 1.0f, 1e-4f);
}

std::vector<MaterialParams> fastGrid() {
    std::vector<MaterialParams> g;
    auto add = [&](auto fn) {
        MaterialParams p = white();
        p.baseColor = {0.8f, 0.5f, 0.3f};
        fn(p);
        g.push_back(p);
    };
    add([](MaterialParams& p) { p.roughness = 0.5f; });
    add([](MaterialParams& p) { p.roughness = 0.2f; p.anisotropic = 0.8f; p.metallic = 1.0f; });
    add([](MaterialParams& p) { p.roughness = 1.0f; p.sheen = 1.0f; p.subsurface = 0.5f; });
    add([](MaterialParams& p) { p.roughness = 0.2f; p.clearcoat = 1.0f; p.clearcoatGloss = 0.5f; });
    add([](MaterialParams& p) { p.roughness = 0.05f; p.clearcoat = 1.0f; p.clearcoatGloss = 0.0f; });
    add([](MaterialParams& p) { p.roughness = 0.5f; p.specTrans = 0.7f; });
    add([](MaterialParams& p) { p.roughness = 0.2f; p.specTrans = 0.7f; p.anisotropic = 0.8f; p.thin = true; });
    return g;
}

TEST(Bsdf, Chi2FastGrid) {
    std::vector<MaterialParams> grid = fastGrid();
    const float thetas[] = {15.0f, 60.0f, 85.0f};
    int count = int(grid.size()) * 3 + 2;
    Chi2Config cfg;
    cfg.samples = 300000;
    cfg.cosBins = 60;
    cfg.phiBins = 60;
    cfg.testCount = count;
    for (const auto& p : grid)
        for (float theta : thetas) {
            auto r = chi2TestBsdf(Bsdf(p, disney()), theta, cfg);
            EXPECT_TRUE(r.passed) << "roughness " << p.roughness << " theta " << theta << ": " << r.message;
            EXPECT_LE(r.pdfIntegral, 1.002);
        }
    // From inside a solid glass object (view below the surface).
    MaterialParams glass = white();
    glass.specTrans = 1.0f;
    glass.roughness = 0.4f;
    auto r = chi2TestBsdf(Bsdf(glass, disney()), 150.0f, cfg);
    EXPECT_TRUE(r.passed) << "inside glass: " << r.message;
    MaterialParams plastic = white();
    auto u = chi2TestBsdf(Bsdf(plastic, ue4()), 70.0f, cfg);
    EXPECT_TRUE(u.passed) << "ue4: " << u.message;
}

// sample() returns exactly the eval() and pdf() values at its wi.
TEST(Bsdf, SampleEvalPdfConsistency) {
    Pcg32 rng(31);
    std::vector<MaterialParams> grid = fastGrid();
    for (Model m : {Model::Disney, Model::UE4})
        for (const auto& p : grid) {
            Options o;
            o.model = m;
            Bsdf b(p, o);
            for (int i = 0; i < 2000; ++i) {
                glm::vec3 wo = squareToUniformSphere({rng.uniform(), rng.uniform()});
                auto s = b.sample(wo, rng.uniform(), {rng.uniform(), rng.uniform()});
                if (!s || s->delta) continue;
                float pdf = 0.0f;
                glm::vec3 f = b.eval(wo, s->wi, &pdf);
                EXPECT_LE(test::relErr(s->pdf, b.pdf(wo, s->wi)), 1e-3f);
                EXPECT_LE(test::relErr(s->pdf, pdf), 1e-3f);
                for (int c = 0; c < 3; ++c) EXPECT_LE(test::relErr(s->f[c], f[c]), 1e-3f);
            }
        }
}

// The mixture weights depend on wo only: pdf() = sum_k P_k(wo) pdf_k(wo, wi) for every wi, and
// the frequencies with which sample() picks lobes match P_k(wo).
TEST(Bsdf, LobeSelectionIndependentOfWi) {
    MaterialParams p = white();
    p.sheen = 1.0f;
    p.clearcoat = 1.0f;
    p.specTrans = 0.3f;
    Bsdf b(p, disney());
    const LobeSet& s = b.lobeSet();
    Pcg32 rng(37);
    glm::vec3 wo = directionFromAngles(50, 10);
    auto prob = b.lobeProbabilities(wo);
    for (int i = 0; i < 500; ++i) {
        glm::vec3 wi = squareToUniformSphere({rng.uniform(), rng.uniform()});
        float expect = prob[0] * s.diffuse.pdf(wo, wi) + prob[1] * s.sheen.pdf(wo, wi) +
                       prob[2] * s.specular.pdf(wo, wi) + prob[3] * s.clearcoat.pdf(wo, wi) +
                       prob[4] * s.transmission.pdf(wo, wi);
        EXPECT_LE(test::relErr(b.pdf(wo, wi), expect), 1e-5f);
    }
    std::array<int, kLobeCount> counts{};
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        auto smp = b.sample(wo, rng.uniform(), {rng.uniform(), rng.uniform()});
        if (smp) counts[int(smp->lobe)]++;
    }
    for (int k = 0; k < kLobeCount; ++k)
        EXPECT_NEAR(double(counts[k]) / n, prob[k], 0.01) << k;  // lost VNDF samples < 1%
}

TEST(Bsdf, ReciprocityOpaque) {
    MaterialParams p = white();
    p.baseColor = {0.7f, 0.4f, 0.2f};
    p.sheen = 0.6f;
    p.clearcoat = 0.7f;
    p.subsurface = 0.3f;
    p.anisotropic = 0.5f;
    for (Model m : {Model::Disney, Model::UE4}) {
        Options o;
        o.model = m;
        Bsdf b(p, o);
        Pcg32 rng(41);
        for (int i = 0; i < 1000; ++i) {
            glm::vec3 a = test::randomUpper(rng), c = test::randomUpper(rng);
            if (a.z < 1e-2f || c.z < 1e-2f) continue;
            glm::vec3 fac = b.eval(a, c) / c.z, fca = b.eval(c, a) / a.z;
            for (int k = 0; k < 3; ++k) EXPECT_LE(test::relErr(fac[k], fca[k]), 1e-4f);
        }
    }
}

TEST(Bsdf, PdfIntegratesToOneWhenNothingIsLost) {
    MaterialParams p = white();
    p.metallic = 0.0f;
    Options o;
    o.lobeMask = lobeBit(Lobe::Diffuse) | lobeBit(Lobe::Sheen);
    p.sheen = 1.0f;
    Bsdf b(p, o);
    glm::vec3 wo = directionFromAngles(40, 0);
    EXPECT_NEAR(integratePdf([&](const glm::vec3& wi) { return b.pdf(wo, wi); }, 40, 40), 1.0, 2e-3);
}

TEST(Bsdf, DeltaMirrorBelowThreshold) {
    MaterialParams p = white();
    p.metallic = 1.0f;
    p.roughness = 0.0f;
    Bsdf b(p, disney());
    EXPECT_TRUE(b.isDeltaOnly());
    glm::vec3 wo = directionFromAngles(45, 0);
    auto s = b.sample(wo, 0.5f, {0.5f, 0.5f});
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->delta);
    EXPECT_EQ(s->lobe, Lobe::Specular);
    EXPECT_NEAR(s->f.x / s->pdf, 1.0f, 1e-6f);  // white metal: F = 1
    EXPECT_FLOAT_EQ(b.pdf(wo, s->wi), 0.0f);
    EXPECT_FLOAT_EQ(b.eval(wo, s->wi).x, 0.0f);
    // Plastic at roughness 0: diffuse stays, specular is delta; the albedo matches the
    // rough-limit of the table row (mu = 1: diffuse ~0.976 Fd + 0.04).
    MaterialParams plastic = white();
    plastic.roughness = 0.0f;
    Bsdf pb(plastic, disney());
    EXPECT_FALSE(pb.isDeltaOnly());
    MaterialParams nearly = plastic;
    nearly.roughness = 0.02f;  // alpha at the reference floor, GGX still continuous
    Options o;
    for (float mu : {1.0f, 0.5f, 0.2f}) {
        float a = directionalAlbedo(pb, mu, 250000).albedo.x;
        float c = directionalAlbedo(Bsdf(nearly, o), mu, 250000).albedo.x;
        EXPECT_NEAR(a, c, 0.01) << mu;
    }
}

TEST(Bsdf, SmoothGlassIsDeltaAndConserves) {
    MaterialParams p = white();
    p.specTrans = 1.0f;
    p.roughness = 0.0f;
    Bsdf b(p, disney());
    EXPECT_TRUE(b.isDeltaOnly());
    for (float mu : {1.0f, 0.5f, 0.1f, -0.5f}) EXPECT_NEAR(directionalAlbedo(b, mu, 10000).albedo.x, 1.0f, 1e-4f);
}

TEST(Bsdf, LobePruning) {
    MaterialParams p = white();
    Bsdf plain(p, disney());
    EXPECT_EQ(plain.lobes(), lobeBit(Lobe::Diffuse) | lobeBit(Lobe::Specular));
    p.metallic = 1.0f;
    EXPECT_EQ(Bsdf(p, disney()).lobes(), lobeBit(Lobe::Specular));
    p = white();
    p.clearcoat = 1e-6f;  // below the cutoff
    p.sheen = 1.0f;
    EXPECT_EQ(Bsdf(p, disney()).lobes() & lobeBit(Lobe::Clearcoat), 0u);
    EXPECT_NE(Bsdf(p, disney()).lobes() & lobeBit(Lobe::Sheen), 0u);
    Options keep;
    keep.pruneLobes = false;
    EXPECT_NE(Bsdf(p, keep).lobes() & lobeBit(Lobe::Clearcoat), 0u);
    p.specTrans = 0.5f;
    EXPECT_NE(Bsdf(p, disney()).lobes() & lobeBit(Lobe::Transmission), 0u);
    // UE4 never has sheen, clearcoat or transmission.
    EXPECT_EQ(Bsdf(p, ue4()).lobes(), lobeBit(Lobe::Diffuse) | lobeBit(Lobe::Specular));
}

// Shading normals that put the view below the surface: opaque materials still reflect.
TEST(Bsdf, ViewBelowShadingHemisphereIsBentBack) {
    MaterialParams p = white();
    Bsdf b(p, disney());
    glm::vec3 wo = glm::normalize(glm::vec3(1.0f, 0.0f, -0.05f));
    float pdf = 0.0f;
    glm::vec3 f = b.eval(wo, glm::normalize(glm::vec3(-0.5f, 0.0f, 0.8f)), &pdf);
    EXPECT_GT(f.x, 0.0f);
    EXPECT_GT(pdf, 0.0f);
    EXPECT_GT(directionalAlbedo(b, -0.05f, 20000).albedo.x, 0.3f);
}

TEST(Bsdf, ExplicitDegenerateCases) {
    std::vector<MaterialParams> mats;
    for (float r : {0.0f, 1.0f})
        for (float an : {0.0f, 1.0f}) {
            MaterialParams p = white();
            p.roughness = r;
            p.anisotropic = an;
            p.clearcoat = 1.0f;
            p.clearcoatGloss = 1.0f;
            p.sheen = 1.0f;
            p.baseColor = glm::vec3(0.0f);
            mats.push_back(p);
            p.specTrans = 1.0f;
            mats.push_back(p);
            p.thin = true;
            mats.push_back(p);
        }
    std::vector<glm::vec3> dirs = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {1, 0, 1e-8f}, {1, 0, -1e-8f},
                                   glm::normalize(glm::vec3(1, 1, 1)), glm::normalize(glm::vec3(1, 0, -1))};
    auto ok = [](glm::vec3 v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z) && v.x >= 0 && v.y >= 0 && v.z >= 0;
    };
    for (Model m : {Model::Disney, Model::UE4})
        for (const auto& p : mats) {
            Options o;
            o.model = m;
            Bsdf b(p, o);
            for (glm::vec3 wo : dirs) {
                wo = glm::normalize(wo);
                for (glm::vec3 wi : dirs) {
                    wi = glm::normalize(wi);
                    for (glm::vec3 w : {wi, -wo}) {
                        float pdf = -1.0f;
                        EXPECT_TRUE(ok(b.eval(wo, w, &pdf)));
                        EXPECT_TRUE(std::isfinite(pdf) && pdf >= 0.0f);
                    }
                }
                for (float ul : {0.0f, 0.5f, 0.99999994f})
                    for (glm::vec2 u : {glm::vec2(0.0f), glm::vec2(0.99999994f), glm::vec2(0.5f, 0.0f)}) {
                        auto s = b.sample(wo, ul, u);
                        if (!s) continue;
                        EXPECT_TRUE(ok(s->f));
                        EXPECT_TRUE(std::isfinite(s->pdf) && s->pdf > 0.0f);
                        EXPECT_TRUE(ok(s->f / s->pdf));
                    }
            }
        }
}

TEST(Bsdf, StressSweep) {
    for (Model m : {Model::Disney, Model::UE4}) {
        StressResult r = stressTest(300000, 5, m);
        EXPECT_EQ(r.bad, 0u) << r.firstBad;
    }
}

}  // namespace
}  // namespace principled::bsdf

namespace principled::bsdf {
namespace {

TEST(Bsdf, SpecularWorkflowUsesSpecularColorAsF0) {
    MaterialParams p = cliDefaults();
    p.specularWorkflow = true;
    p.specularColor = {0.9f, 0.6f, 0.3f};
    p.metallic = 1.0f;  // ignored
    p.baseColor = glm::vec3(0.0f);
    for (Model m : {Model::Disney, Model::UE4}) {
        Options o;
        o.model = m;
        Bsdf b(p, o);
        EXPECT_EQ(b.lobes(), lobeBit(Lobe::Specular));
        // Normal incidence: f cos = F0 D / 4 with G = 1.
        glm::vec3 n(0, 0, 1);
        glm::vec3 f = b.eval(n, n);
        EXPECT_NEAR(f.y / f.x, 0.6f / 0.9f, 3e-4f);  // UE4 SG Schlick: 2^-12.5 at cos 1
        EXPECT_NEAR(f.z / f.x, 0.3f / 0.9f, 3e-4f);
    }
}

}  // namespace
}  // namespace principled::bsdf
