// SPDX-License-Identifier: Apache-2.0
#include "bsdf/chi2.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "bsdf/frame.h"
#include "bsdf/rng.h"

namespace principled::bsdf {
namespace {

constexpr double kPiD = 3.14159265358979323846;

glm::vec3 dirFromCosPhi(double c, double phi) {
    double s = std::sqrt(std::max(0.0, 1.0 - c * c));
    return glm::vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(c));
}

// Adaptive Simpson quadrature (Kuncir 1962; Lyness 1969 error estimate |S2 - S1| / 15), with a
// forced minimum depth so that a narrow peak between the first three nodes is not missed.
template <typename G>
double simpson(const G& g, double a, double b, double fa, double fm, double fb, double whole,
               double eps, int depth, int minDepth) {
    double m = 0.5 * (a + b), lm = 0.5 * (a + m), rm = 0.5 * (m + b);
    double flm = g(lm), frm = g(rm);
    double left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
    double right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
    double delta = left + right - whole;
    if (minDepth <= 0 && (depth <= 0 || std::abs(delta) <= 15.0 * eps))
        return left + right + delta / 15.0;
    return simpson(g, a, m, fa, flm, fm, left, 0.5 * eps, depth - 1, minDepth - 1) +
           simpson(g, m, b, fm, frm, fb, right, 0.5 * eps, depth - 1, minDepth - 1);
}

template <typename G>
double integrate1D(const G& g, double a, double b, double eps) {
    double fa = g(a), fb = g(b), fm = g(0.5 * (a + b));
    double whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
    // 2 forced levels, up to 10 more: a cell is resolved to 1/4096 of its width where needed.
    return simpson(g, a, b, fa, fm, fb, whole, eps, 12, 2);
}

double cellIntegral(const DirectionPdf& pdf, double c0, double c1, double p0, double p1,
                    double eps) {
    auto inner = [&](double phi) {
        auto g = [&](double c) { return double(pdf(dirFromCosPhi(c, phi))); };
        return integrate1D(g, c0, c1, eps / (p1 - p0));
    };
    return integrate1D(inner, p0, p1, eps);
}

std::vector<double> expectedTable(const DirectionPdf& pdf, int nc, int np, double eps) {
    std::vector<double> e(size_t(nc) * np);
    for (int i = 0; i < nc; ++i)
        for (int j = 0; j < np; ++j) {
            double c0 = -1.0 + 2.0 * i / nc, c1 = -1.0 + 2.0 * (i + 1) / nc;
            double p0 = -kPiD + 2.0 * kPiD * j / np, p1 = -kPiD + 2.0 * kPiD * (j + 1) / np;
            e[size_t(i) * np + j] = cellIntegral(pdf, c0, c1, p0, p1, eps);
        }
    return e;
}

}  // namespace

double gammaQ(double a, double x) {
    if (x <= 0.0) return 1.0;
    double lnPre = -x + a * std::log(x) - std::lgamma(a);
    if (x < a + 1.0) {
        // Series P(a, x) = e^-x x^a / Gamma(a+1) sum x^n / ((a+1)...(a+n)) (Abramowitz & Stegun 6.5.29).
        double term = 1.0 / a, sum = term;
        for (int n = 1; n < 100000; ++n) {
            term *= x / (a + n);
            sum += term;
            if (std::abs(term) < std::abs(sum) * 1e-15) break;
        }
        return std::clamp(1.0 - sum * std::exp(lnPre), 0.0, 1.0);
    }
    // Continued fraction for Q(a, x) (A&S 6.5.31), evaluated with the modified Lentz method.
    constexpr double kTiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / kTiny, d = 1.0 / b, h = d;
    for (int i = 1; i < 100000; ++i) {
        double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < kTiny) d = kTiny;
        c = b + an / c;
        if (std::abs(c) < kTiny) c = kTiny;
        d = 1.0 / d;
        double del = d * c;
        h *= del;
        if (std::abs(del - 1.0) < 1e-15) break;
    }
    return std::clamp(std::exp(lnPre) * h, 0.0, 1.0);
}

glm::vec3 directionFromAngles(float thetaDeg, float phiDeg) {
    float t = glm::radians(thetaDeg), p = glm::radians(phiDeg);
    return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

double integratePdf(const DirectionPdf& pdf, int cosBins, int phiBins) {
    std::vector<double> e = expectedTable(pdf, cosBins, phiBins, 1e-8);
    double s = 0.0;
    for (double v : e) s += v;
    return s;
}

Chi2Result chi2Test(const DirectionSampler& sample, const DirectionPdf& pdf, const Chi2Config& cfg) {
    Chi2Result r;
    const int nc = cfg.cosBins, np = cfg.phiBins;
    std::vector<double> obs(size_t(nc) * np, 0.0);
    Pcg32 rng(cfg.seed);
    for (int s = 0; s < cfg.samples; ++s) {
        float uLobe = rng.uniform();
        glm::vec2 u(rng.uniform(), rng.uniform());
        std::optional<glm::vec3> w = sample(uLobe, u);
        if (!w) continue;
        glm::vec3 wi = glm::normalize(*w);
        if (!std::isfinite(wi.x + wi.y + wi.z)) {
            r.message = "sample returned a non-finite direction";
            return r;
        }
        int i = std::clamp(int((wi.z + 1.0f) * 0.5f * nc), 0, nc - 1);
        int j = std::clamp(int((std::atan2(wi.y, wi.x) + kPi) / kTwoPi * np), 0, np - 1);
        obs[size_t(i) * np + j] += 1.0;
        r.histogramSum += 1.0;
    }
    r.histogramSum /= cfg.samples;
    // 0.05 expected counts: quadrature error well below the Poisson noise of any cell.
    std::vector<double> e = expectedTable(pdf, nc, np, 0.05 / cfg.samples);
    for (double& v : e) {
        r.pdfIntegral += v;
        v *= cfg.samples;
    }
    std::ostringstream msg;
    if (r.pdfIntegral > 1.001) {  // 1.001: quadrature tolerance
        msg << "pdf integrates to " << r.pdfIntegral << " > 1";
        r.message = msg.str();
        return r;
    }
    std::vector<size_t> order(e.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return e[a] < e[b]; });
    double pooledE = 0.0, pooledO = 0.0, chsq = 0.0;
    int bins = 0;
    for (size_t k : order) {
        if (e[k] <= 0.0) {
            // pbrt-v3: reject immediately when a cell of zero expectation is hit noticeably.
            if (obs[k] > 1e-5 * cfg.samples) {
                msg << "samples in a cell with zero pdf (cell " << k << ", " << obs[k] << " samples)";
                r.message = msg.str();
                return r;
            }
            pooledO += obs[k];
            continue;
        }
        if (e[k] < cfg.minExpected) {
            pooledE += e[k];
            pooledO += obs[k];
            if (pooledE >= cfg.minExpected) {
                chsq += (pooledO - pooledE) * (pooledO - pooledE) / pooledE;
                ++bins;
                pooledE = pooledO = 0.0;
            }
            continue;
        }
        chsq += (obs[k] - e[k]) * (obs[k] - e[k]) / e[k];
        ++bins;
    }
    if (pooledE > 0.0) {
        chsq += (pooledO - pooledE) * (pooledO - pooledE) / pooledE;
        ++bins;
    }
    r.statistic = chsq;
    r.dof = bins - 1;
    if (r.dof < 1) {
        r.passed = true;  // everything in one cell (e.g. a near-delta lobe): nothing to test
        r.pValue = 1.0;
        r.message = "single pooled cell";
        return r;
    }
    r.pValue = gammaQ(0.5 * r.dof, 0.5 * chsq);
    double alpha = 1.0 - std::pow(1.0 - cfg.significance, 1.0 / std::max(1, cfg.testCount));
    r.passed = std::isfinite(r.pValue) && r.pValue >= alpha;
    msg << "chi2 " << chsq << " dof " << r.dof << " p " << r.pValue << " (threshold " << alpha
        << "), pdf integral " << r.pdfIntegral << ", binned fraction " << r.histogramSum;
    r.message = msg.str();
    return r;
}

Chi2Result chi2TestBsdf(const Bsdf& bsdf, float thetaDeg, const Chi2Config& cfg, float phiDeg) {
    glm::vec3 wo = directionFromAngles(thetaDeg, phiDeg);
    auto sampler = [&](float uLobe, glm::vec2 u) -> std::optional<glm::vec3> {
        auto s = bsdf.sample(wo, uLobe, u);
        if (!s || s->delta) return std::nullopt;
        return s->wi;
    };
    auto pdf = [&](const glm::vec3& wi) { return bsdf.pdf(wo, wi); };
    return chi2Test(sampler, pdf, cfg);
}

}  // namespace principled::bsdf
