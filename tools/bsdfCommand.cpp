// SPDX-License-Identifier: Apache-2.0
// `principled bsdf albedo|chi2|stress|plot`: inspect the shading models from the shell.
#include "tools/bsdfCommand.h"

#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bsdf/bsdf.h"
#include "bsdf/chi2.h"
#include "bsdf/diagnostics.h"
#include "delegate/imageio/nativeWriter.h"

namespace principled::tools {
namespace {

using namespace principled::bsdf;

/// Options shared by the material-based subcommands; numbers are read as text so that bad
/// input gives our one-line message and exit status 1 instead of a parser exception.
struct MaterialArgs {
    std::string model = "disney";
    std::vector<std::string> sets;
    bool legacyG = false;
    bool classicSampling = false;
    std::string deltaRoughness;
    std::string lobes;
};

void addMaterialOptions(CLI::App* cmd, MaterialArgs* a) {
    cmd->add_option("--model", a->model, "disney or ue4")->default_val("disney");
    cmd->add_option("--set", a->sets, "name=value[,name=value...] (colours: v or r:g:b)");
    cmd->add_flag("--legacy-g", a->legacyG, "Burley 2012 course-notes specular G remap");
    cmd->add_flag("--classic-sampling", a->classicSampling, "sample D instead of visible normals");
    cmd->add_option("--delta-roughness", a->deltaRoughness, "roughness below which specular is a mirror");
    cmd->add_option("--lobes", a->lobes, "restrict to lobes: diffuse,sheen,specular,clearcoat,transmission");
}

bool fail(int* exitCode, const std::string& msg) {
    std::cerr << "principled bsdf: " << msg << "\n";
    *exitCode = 1;
    return false;
}

bool parseNumber(const std::string& text, const char* what, double lo, double hi, double* out,
                 int* exitCode) {
    errno = 0;
    char* end = nullptr;
    double v = std::strtod(text.c_str(), &end);
    if (text.empty() || errno != 0 || end != text.c_str() + text.size() || !std::isfinite(v))
        return fail(exitCode, std::string(what) + ": '" + text + "' is not a number");
    if (v < lo || v > hi) {
        std::ostringstream s;
        s << what << ": " << text << " is outside [" << lo << ", " << hi << "]";
        return fail(exitCode, s.str());
    }
    *out = v;
    return true;
}

bool buildMaterial(const MaterialArgs& a, MaterialParams* p, Options* o, int* exitCode) {
    if (a.model == "disney") o->model = Model::Disney;
    else if (a.model == "ue4") o->model = Model::UE4;
    else return fail(exitCode, "--model: '" + a.model + "' is not disney or ue4");
    o->legacySpecularG = a.legacyG;
    o->vndfSampling = !a.classicSampling;
    if (!a.deltaRoughness.empty()) {
        double v;
        if (!parseNumber(a.deltaRoughness, "--delta-roughness", 0.0, 1.0, &v, exitCode)) return false;
        o->deltaRoughness = float(v);
    }
    if (!a.lobes.empty()) {
        o->lobeMask = 0;
        std::istringstream in(a.lobes);
        std::string name;
        const char* names[kLobeCount] = {"diffuse", "sheen", "specular", "clearcoat", "transmission"};
        while (std::getline(in, name, ',')) {
            int k = 0;
            while (k < kLobeCount && name != names[k]) ++k;
            if (k == kLobeCount) return fail(exitCode, "--lobes: unknown lobe '" + name + "'");
            o->lobeMask |= 1u << k;
        }
    }
    *p = cliDefaults();
    for (const std::string& group : a.sets) {
        std::istringstream in(group);
        std::string item;
        while (std::getline(in, item, ',')) {
            size_t eq = item.find('=');
            if (eq == std::string::npos) return fail(exitCode, "--set: '" + item + "' is not name=value");
            std::string err = setParameter(*p, item.substr(0, eq), item.substr(eq + 1));
            if (!err.empty()) return fail(exitCode, err);
        }
    }
    return true;
}

struct Canvas {
    int w, h;
    std::vector<unsigned char> px;
    Canvas(int w_, int h_) : w(w_), h(h_), px(size_t(w_) * h_ * 3, 255) {}
    void dot(int x, int y, std::array<unsigned char, 3> c) {
        if (x < 0 || y < 0 || x >= w || y >= h) return;
        for (int k = 0; k < 3; ++k) px[(size_t(y) * w + x) * 3 + k] = c[k];
    }
    void line(float x0, float y0, float x1, float y1, std::array<unsigned char, 3> c) {
        int n = int(std::max(std::abs(x1 - x0), std::abs(y1 - y0))) + 1;
        for (int i = 0; i <= n; ++i) {
            float t = float(i) / n;
            int x = int(std::lround(x0 + (x1 - x0) * t)), y = int(std::lround(y0 + (y1 - y0) * t));
            dot(x, y, c);
            dot(x + 1, y, c);
        }
    }
};

void runPlot(const MaterialParams& p, const Options& o, float thetaDeg, const std::string& path,
             int* exitCode) {
    Bsdf b(p, o);
    glm::vec3 wo = directionFromAngles(thetaDeg, 0.0f);
    // Two slices: the plane of incidence (x-z) and the perpendicular plane (y-z), over the full
    // circle so transmission shows below the surface. Radius = luminance of f |cos theta_i|.
    const int n = 720;
    std::vector<float> inPlane(n), perp(n);
    float maxV = 1e-6f;
    std::printf("# angle_deg f_cos_incidence_plane f_cos_perpendicular_plane\n");
    for (int i = 0; i < n; ++i) {
        float a = kTwoPi * float(i) / n;
        glm::vec3 w1(std::sin(a), 0.0f, std::cos(a)), w2(0.0f, std::sin(a), std::cos(a));
        inPlane[i] = luminance(b.eval(wo, w1));
        perp[i] = luminance(b.eval(wo, w2));
        maxV = std::max(maxV, std::max(inPlane[i], perp[i]));
        if (i % 10 == 0) std::printf("%.1f %.6g %.6g\n", glm::degrees(a), inPlane[i], perp[i]);
    }
    const int size = 512;
    Canvas c(size, size);
    float cx = size / 2.0f, cy = size / 2.0f, scale = 0.45f * size / maxV;
    c.line(0, cy, float(size - 1), cy, {160, 160, 160});  // the surface
    c.line(cx, cy, cx + 0.45f * size * wo.x, cy - 0.45f * size * wo.z, {0, 150, 0});  // wo
    for (int i = 0; i < n; ++i) {
        int j = (i + 1) % n;
        float a0 = kTwoPi * float(i) / n, a1 = kTwoPi * float(j) / n;
        c.line(cx + scale * inPlane[i] * std::sin(a0), cy - scale * inPlane[i] * std::cos(a0),
               cx + scale * inPlane[j] * std::sin(a1), cy - scale * inPlane[j] * std::cos(a1), {220, 30, 30});
        c.line(cx + scale * perp[i] * std::sin(a0), cy - scale * perp[i] * std::cos(a0),
               cx + scale * perp[j] * std::sin(a1), cy - scale * perp[j] * std::cos(a1), {30, 60, 220});
    }
    std::string err;
    if (!imageio::writePng8(path, size, size, 3, c.px.data(), &err)) {
        fail(exitCode, "cannot write '" + path + "': " + err);
        return;
    }
    std::printf("wrote %s (red: plane of incidence, blue: perpendicular plane, green: wo; max %.4g)\n",
                path.c_str(), maxV);
}

}  // namespace

void addBsdfCommands(CLI::App& app, int* exitCode) {
    auto* bsdf = app.add_subcommand("bsdf", "Inspect the shading models");
    bsdf->require_subcommand(1);

    // albedo
    {
        auto args = std::make_shared<MaterialArgs>();
        auto mu = std::make_shared<std::string>();
        auto samples = std::make_shared<std::string>("1000000");
        auto* cmd = bsdf->add_subcommand("albedo", "Directional albedo (integral of f cos) by importance sampling");
        addMaterialOptions(cmd, args.get());
        cmd->add_option("--cos", *mu, "cosine of the view angle, in [-1, 1]")->required();
        cmd->add_option("--samples", *samples, "number of samples");
        cmd->callback([=]() {
            MaterialParams p;
            Options o;
            double m, n;
            if (!buildMaterial(*args, &p, &o, exitCode)) return;
            if (!parseNumber(*mu, "--cos", -1.0, 1.0, &m, exitCode)) return;
            if (!parseNumber(*samples, "--samples", 1.0, 1e10, &n, exitCode)) return;
            Bsdf b(p, o);
            AlbedoResult r = directionalAlbedo(b, float(m), int(std::min(n, 2e9)));
            std::printf("model %s lobes 0x%x deltaOnly %d\n", args->model.c_str(), b.lobes(), int(b.isDeltaOnly()));
            std::printf("stderr %.6f %.6f %.6f\n", r.stdError.x, r.stdError.y, r.stdError.z);
            std::printf("albedo %.6f %.6f %.6f\n", r.albedo.x, r.albedo.y, r.albedo.z);
            *exitCode = 0;
        });
    }
    // chi2
    {
        auto args = std::make_shared<MaterialArgs>();
        auto theta = std::make_shared<std::string>();
        auto samples = std::make_shared<std::string>("1000000");
        auto sig = std::make_shared<std::string>("0.01");
        auto tests = std::make_shared<std::string>("1");
        auto* cmd = bsdf->add_subcommand("chi2", "Chi-square test of sample() against pdf()");
        addMaterialOptions(cmd, args.get());
        cmd->add_option("--theta", *theta, "view angle from the normal, degrees [0, 180]")->required();
        cmd->add_option("--samples", *samples, "number of samples");
        cmd->add_option("--significance", *sig, "significance level");
        cmd->add_option("--tests", *tests, "Sidak correction for this many tests");
        cmd->callback([=]() {
            MaterialParams p;
            Options o;
            double t, n, s, k;
            if (!buildMaterial(*args, &p, &o, exitCode)) return;
            if (!parseNumber(*theta, "--theta", 0.0, 180.0, &t, exitCode)) return;
            if (!parseNumber(*samples, "--samples", 1000.0, 1e9, &n, exitCode)) return;
            if (!parseNumber(*sig, "--significance", 1e-9, 0.5, &s, exitCode)) return;
            if (!parseNumber(*tests, "--tests", 1.0, 1e6, &k, exitCode)) return;
            Chi2Config cfg;
            cfg.samples = int(n);
            cfg.significance = s;
            cfg.testCount = int(k);
            Chi2Result r = chi2TestBsdf(Bsdf(p, o), float(t), cfg);
            std::printf("%s\n", r.message.c_str());
            std::printf("%s\n", r.passed ? "pass" : "FAIL");
            std::printf("p-value %.6g\n", r.pValue);
            *exitCode = r.passed ? 0 : 1;
        });
    }
    // stress
    {
        auto evals = std::make_shared<std::string>("1000000");
        auto seed = std::make_shared<std::string>("1");
        auto* cmd = bsdf->add_subcommand("stress", "NaN/Inf/negative sweep over random parameters and directions");
        cmd->add_option("--evals", *evals, "number of evaluations");
        cmd->add_option("--seed", *seed, "random seed");
        cmd->callback([=]() {
            double n, s;
            if (!parseNumber(*evals, "--evals", 1.0, 1e12, &n, exitCode)) return;
            if (!parseNumber(*seed, "--seed", 0.0, 1.8e19, &s, exitCode)) return;
            StressResult r = stressTest(uint64_t(n), uint64_t(s));
            if (r.bad) std::printf("first bad: %s\n", r.firstBad.c_str());
            std::printf("bad %llu of %llu\n", (unsigned long long)r.bad, (unsigned long long)r.evaluations);
            *exitCode = r.bad ? 1 : 0;
        });
    }
    // plot
    {
        auto args = std::make_shared<MaterialArgs>();
        auto theta = std::make_shared<std::string>();
        auto out = std::make_shared<std::string>();
        auto* cmd = bsdf->add_subcommand("plot", "Polar slices of f cos as a PNG (and a table on stdout)");
        addMaterialOptions(cmd, args.get());
        cmd->add_option("--theta", *theta, "view angle from the normal, degrees [0, 180]")->required();
        cmd->add_option("-o,--output", *out, "output PNG")->required();
        cmd->callback([=]() {
            MaterialParams p;
            Options o;
            double t;
            if (!buildMaterial(*args, &p, &o, exitCode)) return;
            if (!parseNumber(*theta, "--theta", 0.0, 180.0, &t, exitCode)) return;
            *exitCode = 0;
            runPlot(p, o, float(t), *out, exitCode);
        });
    }
}

}  // namespace principled::tools
