// SPDX-License-Identifier: Apache-2.0
// Accuracy side of the speed/accuracy charts in docs/bsdf.md: prints markdown tables for the
// delta-mirror threshold, the pruning cutoff, VNDF vs classic sampling, and the G variants.
// Deterministic (fixed seeds); timings come from bsdf_bench.
#include <cmath>
#include <cstdio>
#include <vector>

#include "bsdf/bsdf.h"
#include "bsdf/chi2.h"
#include "bsdf/diagnostics.h"
#include "bsdf/rng.h"

using namespace principled::bsdf;

namespace {

glm::vec3 viewMu(float mu) { return {std::sqrt(1.0f - mu * mu), 0.0f, mu}; }

// Angle (degrees) around the mirror direction that holds `fraction` of the sampled specular
// energy: how much blur a mirror throws away.
float energyRadiusDeg(const Bsdf& b, float mu, float fraction) {
    glm::vec3 wo = viewMu(mu), mirror(-wo.x, -wo.y, wo.z);
    Pcg32 rng(5);
    std::vector<std::pair<float, float>> v;
    double total = 0.0;
    for (int i = 0; i < 200000; ++i) {
        auto s = b.sample(wo, rng.uniform(), {rng.uniform(), rng.uniform()});
        if (!s || !(s->pdf > 0.0f)) continue;
        float w = s->f.x / s->pdf;
        float ang = glm::degrees(std::acos(std::clamp(glm::dot(s->wi, mirror), -1.0f, 1.0f)));
        v.push_back({ang, w});
        total += w;
    }
    std::sort(v.begin(), v.end());
    double acc = 0.0;
    for (auto& [a, w] : v) {
        acc += w;
        if (acc >= fraction * total) return a;
    }
    return 180.0f;
}

// Per-sample variance of the albedo estimator (red channel) and fraction of lost samples.
void estimatorStats(const Bsdf& b, float mu, double* var, double* lost) {
    glm::vec3 wo = viewMu(mu);
    Pcg32 rng(9);
    const int n = 400000;
    double s1 = 0, s2 = 0;
    int miss = 0;
    for (int i = 0; i < n; ++i) {
        auto s = b.sample(wo, rng.uniform(), {rng.uniform(), rng.uniform()});
        double w = 0.0;
        if (s && s->pdf > 0.0f) w = s->f.x / s->pdf;
        else ++miss;
        s1 += w;
        s2 += w * w;
    }
    double m = s1 / n;
    *var = s2 / n - m * m;
    *lost = double(miss) / n;
}

}  // namespace

int main() {
    const float mus[3] = {1.0f, 0.5f, 0.1f};
    std::printf("## Delta-mirror threshold\n\n");
    std::printf("White metal (F0 = 1) and the default dielectric (specular 0.5, white base). Albedo\n"
                "at mu = 1 / 0.5 / 0.1, and the cone (degrees around the mirror direction) that holds\n"
                "50%% / 90%% of the reflected specular energy of the metal at mu = 0.5.\n\n");
    std::printf("| roughness | metal albedo mu 1/.5/.1 | dielectric albedo mu 1/.5/.1 | 50%% cone | 90%% cone |\n");
    std::printf("|---|---|---|---|---|\n");
    for (float r : {0.0f, 0.001f, 0.01f, 0.02f, 0.03f, 0.05f, 0.1f}) {
        MaterialParams metal = cliDefaults();
        metal.metallic = 1.0f;
        metal.roughness = r;
        MaterialParams diel = cliDefaults();
        diel.roughness = r;
        Options o;
        o.deltaRoughness = r == 0.0f ? 1e-3f : 0.0f;  // r = 0: the mirror; else GGX at r
        Bsdf bm(metal, o), bd(diel, o);
        std::printf("| %s |", r == 0.0f ? "mirror" : (std::to_string(r).substr(0, 5)).c_str());
        for (float mu : mus) std::printf(" %.4f", directionalAlbedo(bm, mu, 250000).albedo.x);
        std::printf(" |");
        for (float mu : mus) std::printf(" %.4f", directionalAlbedo(bd, mu, 250000).albedo.x);
        std::printf(" | %.3f | %.3f |\n", energyRadiusDeg(bm, 0.5f, 0.5f), energyRadiusDeg(bm, 0.5f, 0.9f));
    }

    std::printf("\n## Lobe pruning cutoff\n\n");
    std::printf("Albedo change at mu = 0.5 / 0.1 when a lobe of weight w is pruned (white base,\n"
                "roughness 0.5): the error bound of a cutoff w.\n\n");
    std::printf("| lobe weight w | sheen: delta albedo | clearcoat: delta albedo | diffuse (metallic 1-w): delta albedo |\n|---|---|---|---|\n");
    for (float w : {1e-4f, 1e-3f, 1e-2f}) {
        std::printf("| %g |", w);
        for (int which = 0; which < 3; ++which) {
            MaterialParams p = cliDefaults();
            if (which == 0) p.sheen = w;
            if (which == 1) p.clearcoat = w * 4.0f;  // lobe weight 0.25 clearcoat
            if (which == 2) p.metallic = 1.0f - w;
            Options keep, prune;
            keep.pruneLobes = false;
            prune.pruneCutoff = 2.0f * w;
            std::printf(" ");
            for (float mu : {0.5f, 0.1f}) {
                float a = directionalAlbedo(Bsdf(p, keep), mu, 1000000, 3).albedo.x;
                float b = directionalAlbedo(Bsdf(p, prune), mu, 1000000, 3).albedo.x;
                std::printf("%.2e ", a - b);
            }
            std::printf("|");
        }
        std::printf("\n");
    }

    std::printf("\n## VNDF vs classic D sampling\n\n");
    std::printf("Per-sample variance of the albedo estimator f cos / pdf (white metal) and the\n"
                "fraction of samples lost below the horizon. Lower variance at equal cost = better.\n\n");
    std::printf("| roughness | mu | VNDF variance | VNDF lost | classic variance | classic lost |\n|---|---|---|---|---|---|\n");
    for (float r : {0.2f, 0.5f, 1.0f})
        for (float mu : {1.0f, 0.5f, 0.1f}) {
            MaterialParams p = cliDefaults();
            p.metallic = 1.0f;
            p.roughness = r;
            Options vn, cl;
            cl.vndfSampling = false;
            double v1, l1, v2, l2;
            estimatorStats(Bsdf(p, vn), mu, &v1, &l1);
            estimatorStats(Bsdf(p, cl), mu, &v2, &l2);
            std::printf("| %.1f | %.1f | %.4f | %.3f | %.4f | %.3f |\n", r, mu, v1, l1, v2, l2);
        }

    std::printf("\n## Specular G: reference (2017 code) vs 2012 course notes\n\n");
    std::printf("Albedo of white metal (F = 1) at mu = 1 / 0.5 / 0.1.\n\n");
    std::printf("| roughness | separable Smith, alpha of D | remapped alpha (0.5 + 0.5 r)^2 | UE4 Schlick-Smith |\n|---|---|---|---|\n");
    for (float r : {0.1f, 0.25f, 0.5f, 0.75f, 1.0f}) {
        MaterialParams p = cliDefaults();
        p.metallic = 1.0f;
        p.roughness = r;
        Options a, b, c;
        b.legacySpecularG = true;
        c.model = Model::UE4;
        std::printf("| %.2f |", r);
        for (const Options* o : {&a, &b, &c}) {
            Bsdf bs(p, *o);
            for (float mu : mus) std::printf(" %.3f", directionalAlbedo(bs, mu, 250000).albedo.x);
            std::printf(" |");
        }
        std::printf("\n");
    }
    return 0;
}
