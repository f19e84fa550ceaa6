// SPDX-License-Identifier: Apache-2.0
#include "bsdf/diagnostics.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "bsdf/rng.h"

namespace principled::bsdf {

AlbedoResult directionalAlbedo(const Bsdf& bsdf, float mu, int samples, uint64_t seed) {
    mu = std::clamp(mu, -1.0f, 1.0f);
    glm::vec3 wo(std::sqrt(std::max(0.0f, 1.0f - mu * mu)), 0.0f, mu);
    Pcg32 rng(seed);
    glm::dvec3 sum(0.0), sum2(0.0);
    // Stratified in u (sqrt(n) x sqrt(n) jittered cells) and random in uLobe.
    int side = std::max(1, int(std::sqrt(double(samples))));
    int n = side * side;
    for (int k = 0; k < n; ++k) {
        glm::vec2 u((float(k % side) + rng.uniform()) / side, (float(k / side) + rng.uniform()) / side);
        u = glm::min(u, glm::vec2(0.99999994f));  // largest float below 1
        auto s = bsdf.sample(wo, rng.uniform(), u);
        if (!s || !(s->pdf > 0.0f)) continue;
        glm::dvec3 w = glm::dvec3(s->f) / double(s->pdf);
        sum += w;
        sum2 += w * w;
    }
    AlbedoResult r;
    glm::dvec3 mean = sum / double(n);
    glm::dvec3 var = glm::max(sum2 / double(n) - mean * mean, glm::dvec3(0.0));
    r.albedo = glm::vec3(mean);
    r.stdError = glm::vec3(glm::sqrt(var / double(n)));
    return r;
}

namespace {

float edgyUniform(Pcg32& rng) {
    float pick = rng.uniform();
    if (pick < 0.1f) return 0.0f;
    if (pick < 0.2f) return 1.0f;
    if (pick < 0.25f) return 1e-8f;
    if (pick < 0.3f) return 1.0f - 1e-7f;
    return rng.uniform();
}

glm::vec3 randomDirection(Pcg32& rng) {
    float pick = rng.uniform();
    float phi = kTwoPi * rng.uniform();
    auto withCos = [&](float c) {
        float s = std::sqrt(std::max(0.0f, 1.0f - c * c));
        return glm::vec3(s * std::cos(phi), s * std::sin(phi), c);
    };
    if (pick < 0.05f) return {0.0f, 0.0f, 1.0f};
    if (pick < 0.1f) return {0.0f, 0.0f, -1.0f};
    if (pick < 0.15f) return withCos(0.0f);
    if (pick < 0.2f) return withCos(1e-8f);
    if (pick < 0.25f) return withCos(-1e-8f);
    if (pick < 0.3f) return withCos(1e-4f);
    float z = 1.0f - 2.0f * rng.uniform();
    return withCos(z);
}

bool bad(const glm::vec3& v) {
    return !std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z) || v.x < 0.0f ||
           v.y < 0.0f || v.z < 0.0f;
}
bool bad(float v) { return !std::isfinite(v) || v < 0.0f; }

std::string describe(const MaterialParams& p, const glm::vec3& wo, const glm::vec3& wi,
                     const char* what) {
    std::ostringstream s;
    s << what << " at wo=(" << wo.x << "," << wo.y << "," << wo.z << ") wi=(" << wi.x << ","
      << wi.y << "," << wi.z << ") roughness=" << p.roughness << " metallic=" << p.metallic
      << " anisotropic=" << p.anisotropic << " specTrans=" << p.specTrans
      << " clearcoatGloss=" << p.clearcoatGloss << " thin=" << p.thin;
    return s.str();
}

}  // namespace

namespace {

StressResult stressImpl(uint64_t evaluations, uint64_t seed, int model) {
    StressResult r;
    Pcg32 rng(seed);
    Options o;
    o.model = model == 1 ? Model::UE4 : Model::Disney;
    MaterialParams p;
    Bsdf bsdf(p, o);
    for (uint64_t n = 0; n < evaluations; ++n) {
        if (n % 16 == 0) {  // new material every 16 evaluations
            p.baseColor = {edgyUniform(rng), edgyUniform(rng), edgyUniform(rng)};
            p.subsurface = edgyUniform(rng);
            p.metallic = edgyUniform(rng);
            p.specular = edgyUniform(rng);
            p.specularTint = edgyUniform(rng);
            p.roughness = edgyUniform(rng);
            p.anisotropic = edgyUniform(rng);
            p.sheen = edgyUniform(rng);
            p.sheenTint = edgyUniform(rng);
            p.clearcoat = edgyUniform(rng);
            p.clearcoatGloss = edgyUniform(rng);
            p.specTrans = edgyUniform(rng);
            p.ior = 1.0f + 2.0f * edgyUniform(rng);
            p.thin = rng.uniform() < 0.3f;
            o.vndfSampling = rng.uniform() < 0.7f;
            o.legacySpecularG = rng.uniform() < 0.2f;
            if (model < 0) o.model = rng.uniform() < 0.5f ? Model::Disney : Model::UE4;
            bsdf = Bsdf(p, o);
        }
        glm::vec3 wo = randomDirection(rng);
        glm::vec3 wi = rng.uniform() < 0.05f ? -wo : randomDirection(rng);
        ++r.evaluations;
        float pdf = 0.0f;
        LobeValues lv;
        glm::vec3 f = bsdf.eval(wo, wi, &pdf, &lv);
        const char* what = nullptr;
        if (bad(f) || bad(pdf)) what = "eval";
        for (const auto& v : lv)
            if (bad(v)) what = "eval per lobe";
        if (!what && bad(bsdf.pdf(wo, wi))) what = "pdf";
        glm::vec2 u(edgyUniform(rng), edgyUniform(rng));
        u = glm::min(u, glm::vec2(0.99999994f));
        float uLobe = std::min(edgyUniform(rng), 0.99999994f);
        if (auto s = bsdf.sample(wo, uLobe, u)) {
            if (bad(s->f) || bad(s->pdf) || !std::isfinite(s->wi.x + s->wi.y + s->wi.z) ||
                !(s->pdf > 0.0f) || bad(s->f / s->pdf))
                what = "sample";
        }
        if (what) {
            if (r.bad == 0) r.firstBad = describe(p, wo, wi, what);
            ++r.bad;
        }
    }
    return r;
}

}  // namespace

StressResult stressTest(uint64_t evaluations, uint64_t seed, Model model) {
    return stressImpl(evaluations, seed, model == Model::UE4 ? 1 : 0);
}
StressResult stressTest(uint64_t evaluations, uint64_t seed) { return stressImpl(evaluations, seed, -1); }

MaterialParams cliDefaults() {
    MaterialParams p;
    p.baseColor = glm::vec3(1.0f);
    p.subsurface = 0.0f;
    p.metallic = 0.0f;
    p.specular = 0.5f;
    p.specularTint = 0.0f;
    p.roughness = 0.5f;
    p.anisotropic = 0.0f;
    p.sheen = 0.0f;
    p.sheenTint = 0.0f;
    p.clearcoat = 0.0f;
    p.clearcoatGloss = 0.0f;
    p.specTrans = 0.0f;
    p.ior = 1.5f;
    p.thin = false;
    return p;
}

namespace {

bool parseFloat(const std::string& s, float* out) {
    if (s.empty()) return false;
    errno = 0;
    char* end = nullptr;
    float v = std::strtof(s.c_str(), &end);
    if (errno != 0 || end != s.c_str() + s.size() || !std::isfinite(v)) return false;
    *out = v;
    return true;
}

}  // namespace

std::string setParameter(MaterialParams& p, const std::string& name, const std::string& value) {
    if (name == "baseColor") {
        std::vector<float> c;
        std::string part;
        std::istringstream in(value);
        while (std::getline(in, part, ':')) {
            float v;
            if (!parseFloat(part, &v)) return "baseColor: '" + value + "' is not a number";
            if (v < 0.0f || v > 1.0f) return "baseColor: " + part + " is outside [0, 1]";
            c.push_back(v);
        }
        if (c.size() == 1) p.baseColor = glm::vec3(c[0]);
        else if (c.size() == 3) p.baseColor = {c[0], c[1], c[2]};
        else return "baseColor takes one value or three joined by ':'";
        return {};
    }
    float v;
    if (name == "thin") {
        if (value == "true" || value == "1") p.thin = true;
        else if (value == "false" || value == "0") p.thin = false;
        else return "thin: '" + value + "' is not 0/1/true/false";
        return {};
    }
    if (!parseFloat(value, &v)) return name + ": '" + value + "' is not a number";
    if (name == "ior") {
        if (v < 1.0f || v > 4.0f) return "ior: " + value + " is outside [1, 4]";
        p.ior = v;
        return {};
    }
    float* slot = nullptr;
    if (name == "subsurface") slot = &p.subsurface;
    else if (name == "metallic") slot = &p.metallic;
    else if (name == "specular") slot = &p.specular;
    else if (name == "specularTint") slot = &p.specularTint;
    else if (name == "roughness") slot = &p.roughness;
    else if (name == "anisotropic") slot = &p.anisotropic;
    else if (name == "sheen") slot = &p.sheen;
    else if (name == "sheenTint") slot = &p.sheenTint;
    else if (name == "clearcoat") slot = &p.clearcoat;
    else if (name == "clearcoatGloss") slot = &p.clearcoatGloss;
    else if (name == "specTrans") slot = &p.specTrans;
    if (!slot) return "unknown parameter '" + name + "'";
    if (v < 0.0f || v > 1.0f) return name + ": " + value + " is outside [0, 1]";
    *slot = v;
    return {};
}

}  // namespace principled::bsdf
