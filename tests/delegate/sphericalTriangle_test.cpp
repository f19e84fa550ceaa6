// Spherical-triangle sampling (delegate/sphericalTriangle.h): the solid angle against exact
// values, and the sampler's directions against analytic integrals over the triangle (each fails
// if the directions are not uniform over the spherical triangle).
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "delegate/sampler.h"
#include "delegate/sphericalTriangle.h"

using namespace principled::embree;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Moller & Trumbore 1997, "Fast, Minimum Storage Ray-Triangle Intersection": does the ray hit?
bool hits(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    glm::dvec3 e1 = b - a, e2 = c - a, pv = glm::cross(d, e2);
    double det = glm::dot(e1, pv);
    if (std::abs(det) < 1e-14) return false;
    glm::dvec3 tv = o - a;
    double u = glm::dot(tv, pv) / det;
    glm::dvec3 qv = glm::cross(tv, e1);
    double v = glm::dot(d, qv) / det;
    double t = glm::dot(e2, qv) / det;
    const double eps = 1e-5;
    return u >= -eps && v >= -eps && u + v <= 1.0 + eps && t > 0.0;
}

struct Case {
    glm::vec3 p, a, b, c;
};

const Case kCases[] = {
    {{0, 0, 0}, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}},           // half a cube face from its centre
    {{0.2f, -0.3f, 0}, {-0.5f, 0.1f, 2}, {1.5f, 0.2f, 2.5f}, {0.1f, 2, 1}},  // skewed, oblique
    {{0, 0, 0}, {-4, -3, 0.3f}, {5, -2, 0.2f}, {0, 6, 0.25f}},  // large and nearly edge-on
    {{0, 0, 0}, {0, 0, 5}, {0.2f, 0, 5}, {0, 0.1f, 5}},         // small and far (0.0004 sr)
};

}  // namespace

TEST(SphericalTriangle, SolidAngleOfACubeFaceIsFourPiOverSix) {
    // Two triangles of a face of the cube [-1,1]^3 seen from its centre: 4 pi / 12 each.
    glm::vec3 o(0.0f);
    EXPECT_NEAR(triangleSolidAngle(o, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}), 4.0 * kPi / 12.0, 1e-6);
    EXPECT_NEAR(triangleSolidAngle(o, {-1, -1, 1}, {1, 1, 1}, {-1, 1, 1}), 4.0 * kPi / 12.0, 1e-6);
    // An octant triangle (the three axes): pi / 2.
    EXPECT_NEAR(triangleSolidAngle(o, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}), kPi / 2.0, 1e-6);
    // Seen from its own plane: 0.
    EXPECT_NEAR(triangleSolidAngle({0, 0, 1}, {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}), 0.0, 1e-6);
}

TEST(SphericalTriangle, EverySampleHitsTheTriangle) {
    for (const Case& k : kCases) {
        for (uint32_t i = 0; i < 4096; ++i) {
            Sampler s(SamplerKind::Sobol, 3, 0, i);
            glm::vec3 d;
            ASSERT_TRUE(sampleSphericalTriangle(k.p, k.a, k.b, k.c, s.next2D(), &d));
            EXPECT_NEAR(glm::length(d), 1.0f, 1e-5f);
            EXPECT_TRUE(hits(glm::dvec3(k.p), glm::dvec3(d), glm::dvec3(k.a), glm::dvec3(k.b), glm::dvec3(k.c)))
                << "sample " << i << " misses the triangle";
        }
    }
}

// E = Omega * mean(n . w) over uniform directions w (pdf 1/Omega) must equal Lambert's formula
// for several normals n: a first-moment test of uniformity over the spherical triangle.
TEST(SphericalTriangle, IrradianceEstimateMatchesLambertsFormula) {
    const glm::dvec3 normals[] = {{0, 0, 1}, glm::normalize(glm::dvec3(1, 0, 1)), glm::normalize(glm::dvec3(-1, 2, 3))};
    std::mt19937 rng(42);
    std::uniform_real_distribution<float> U(0.0f, 0.99999994f);
    for (const Case& k : kCases) {
        double omega = triangleSolidAngle(k.p, k.a, k.b, k.c);
        std::vector<glm::dvec3> v = {glm::dvec3(k.a - k.p), glm::dvec3(k.b - k.p), glm::dvec3(k.c - k.p)};
        for (const glm::dvec3& n : normals) {
            const int N = 200000;
            double sum = 0.0, sum2 = 0.0;
            for (int i = 0; i < N; ++i) {
                glm::vec3 d;
                ASSERT_TRUE(sampleSphericalTriangle(k.p, k.a, k.b, k.c, {U(rng), U(rng)}, &d));
                double f = omega * glm::dot(n, glm::dvec3(d));
                sum += f, sum2 += f * f;
            }
            double mean = sum / N, se = std::sqrt(std::max(0.0, sum2 / N - mean * mean) / N);
            // The vector irradiance of a unit-radiance polygon, integral of w over it (Lambert's
            // formula; Arvo 1994, "The Irradiance Jacobian for Partially Occluded Polyhedral
            // Sources", eq. 3): 1/2 sum_i theta_i normalize(v_i x v_(i+1)), dotted with n.
            double exact = 0.0;
            {
                double e = 0.0;
                for (size_t i = 0; i < 3; ++i) {
                    glm::dvec3 a = glm::normalize(v[i]), b = glm::normalize(v[(i + 1) % 3]);
                    e += std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) * glm::dot(n, glm::normalize(glm::cross(a, b)));
                }
                // The edge normals point inward when the triple product is negative.
                double orient = glm::dot(v[0], glm::cross(v[1], v[2])) > 0.0 ? 1.0 : -1.0;
                exact = 0.5 * e * orient;
            }
            EXPECT_NEAR(mean, exact, 5.0 * se + 1e-6 * omega) << "normal " << n.x << "," << n.y << "," << n.z;
        }
    }
}

// Uniformity in 2-D: split the triangle at its centroid into three sub-triangles; the fraction of
// samples in each must be its share of the solid angle (chi-square, 2 degrees of freedom).
TEST(SphericalTriangle, SamplesFallInSubTrianglesInProportionToTheirSolidAngle) {
    for (const Case& k : kCases) {
        glm::vec3 m = (k.a + k.b + k.c) / 3.0f;
        const glm::vec3 sub[3][3] = {{k.a, k.b, m}, {k.b, k.c, m}, {k.c, k.a, m}};
        double omega = triangleSolidAngle(k.p, k.a, k.b, k.c), expected[3], sumSub = 0.0;
        for (int j = 0; j < 3; ++j) sumSub += expected[j] = triangleSolidAngle(k.p, sub[j][0], sub[j][1], sub[j][2]) / omega;
        ASSERT_NEAR(sumSub, 1.0, 1e-4);
        const int N = 100000;
        int count[3] = {0, 0, 0};
        std::mt19937 rng(7);
        std::uniform_real_distribution<float> U(0.0f, 0.99999994f);
        for (int i = 0; i < N; ++i) {
            glm::vec3 d;
            ASSERT_TRUE(sampleSphericalTriangle(k.p, k.a, k.b, k.c, {U(rng), U(rng)}, &d));
            for (int j = 0; j < 3; ++j)
                if (hits(glm::dvec3(k.p), glm::dvec3(d), glm::dvec3(sub[j][0]), glm::dvec3(sub[j][1]), glm::dvec3(sub[j][2]))) {
                    ++count[j];
                    break;
                }
        }
        double chi2 = 0.0;
        for (int j = 0; j < 3; ++j) {
            double e = expected[j] * N;
            chi2 += (count[j] - e) * (count[j] - e) / e;
        }
        EXPECT_LT(chi2, 13.8) << "p = 0.001 critical value for 2 dof";  // chi2(2) 99.9 %
    }
}

// The float solid angle (unit-vector form of Van Oosterom & Strackee 1983, eq. 8) against the
// same formula evaluated in double on the original, unnormalised vectors.
TEST(SphericalTriangle, SolidAngleMatchesADoublePrecisionReference) {
    auto reference = [](const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
        glm::dvec3 A = a - p, B = b - p, C = c - p;
        double la = glm::length(A), lb = glm::length(B), lc = glm::length(C);
        double num = std::abs(glm::dot(A, glm::cross(B, C)));
        double den = la * lb * lc + glm::dot(A, B) * lc + glm::dot(A, C) * lb + glm::dot(B, C) * la;
        return 2.0 * std::atan2(num, den);
    };
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> U(-2.0f, 2.0f);
    for (int i = 0; i < 2000; ++i) {
        glm::vec3 p(U(rng), U(rng), U(rng)), a(U(rng), U(rng), U(rng)), b(U(rng), U(rng), U(rng)),
            c(U(rng), U(rng), U(rng));
        double ref = reference(p, a, b, c);
        EXPECT_NEAR(triangleSolidAngle(p, a, b, c), ref, 2e-5 * std::max(1.0, ref)) << "triangle " << i;
    }
    for (const Case& k : kCases) {
        double ref = reference(k.p, k.a, k.b, k.c);
        EXPECT_NEAR(triangleSolidAngle(k.p, k.a, k.b, k.c), ref, 1e-5 * ref);
    }
}

// The pdf 1 / Omega integrates to 1 over the triangle: the fraction of directions uniform over
// the whole sphere that hit the triangle, times 4 pi, estimates the same Omega.
TEST(SphericalTriangle, PdfIntegratesToOneOverTheTriangle) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> U(0.0, 1.0);
    for (const Case& k : kCases) {
        double omega = triangleSolidAngle(k.p, k.a, k.b, k.c);
        if (omega < 0.01) continue;  // the far case would need ~10^8 directions
        const int N = 400000;
        int hitCount = 0;
        for (int i = 0; i < N; ++i) {
            // Uniform on the sphere: z uniform in [-1, 1], phi uniform (Archimedes).
            double z = 2.0 * U(rng) - 1.0, phi = 2.0 * kPi * U(rng), r = std::sqrt(std::max(0.0, 1.0 - z * z));
            glm::dvec3 d(r * std::cos(phi), r * std::sin(phi), z);
            hitCount += hits(glm::dvec3(k.p), d, glm::dvec3(k.a), glm::dvec3(k.b), glm::dvec3(k.c));
        }
        double f = double(hitCount) / N, se = std::sqrt(f * (1.0 - f) / N);
        double integral = 4.0 * kPi * f / omega;  // integral of the pdf 1 / Omega over the triangle
        EXPECT_NEAR(integral, 1.0, 5.0 * 4.0 * kPi * se / omega + 2e-3) << "omega " << omega;
    }
}

// Degenerate triangles: zero area, a repeated vertex, seen edge-on, the point on a vertex, and
// non-finite input. No sample, no NaN, the output direction untouched.
TEST(SphericalTriangle, DegenerateTrianglesReturnFalseWithoutNaN) {
    const float nan = std::nanf(""), inf = INFINITY;
    const Case degenerate[] = {
        {{0, 0, 0}, {-1, 0, 1}, {0, 0, 1}, {1, 0, 1}},     // collinear vertices
        {{0, 0, 0}, {1, 1, 1}, {1, 1, 1}, {0, 1, 1}},      // repeated vertex
        {{0, 0, 0}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}},      // one point
        {{0, 0, 1}, {2, -1, 1}, {3, -1, 1}, {3, 1, 1}},    // edge-on: p in the triangle's plane
        {{1, 1, 1}, {1, 1, 1}, {2, 1, 1}, {1, 2, 1}},      // p on a vertex
        {{0, 0, 0}, {-1, -1, 1}, {1, -1, 1}, {0, 0, 0}},   // p on a vertex (last)
        {{0, 0, 0}, {nan, -1, 1}, {1, -1, 1}, {1, 1, 1}},  // NaN vertex
        {{0, 0, 0}, {inf, -1, 1}, {1, -1, 1}, {1, 1, 1}},  // infinite vertex
    };
    int index = 0;
    for (const Case& k : degenerate) {
        SphericalTriangle t;
        EXPECT_FALSE(makeSphericalTriangle(k.p, k.a, k.b, k.c, &t)) << "case " << index;
        float omega = triangleSolidAngle(k.p, k.a, k.b, k.c);
        EXPECT_TRUE(std::isfinite(omega) && omega >= 0.0f) << "case " << index << ": " << omega;
        for (glm::vec2 u : {glm::vec2(0.0f), glm::vec2(0.5f), glm::vec2(0.99999994f)}) {
            glm::vec3 d(7.0f);
            EXPECT_FALSE(sampleSphericalTriangle(k.p, k.a, k.b, k.c, u, &d)) << "case " << index;
            EXPECT_FALSE(sampleSphericalTriangle(t, u, &d)) << "case " << index;
            EXPECT_EQ(d, glm::vec3(7.0f)) << "case " << index;
        }
        ++index;
    }
}

// The extremes of u land on the triangle's vertices and edges, not outside it.
TEST(SphericalTriangle, CornerSamplesStayInsideTheTriangle) {
    for (const Case& k : kCases) {
        SphericalTriangle t;
        ASSERT_TRUE(makeSphericalTriangle(k.p, k.a, k.b, k.c, &t));
        for (float ux : {0.0f, 1e-7f, 0.5f, 0.99999994f, 1.0f})
            for (float uy : {0.0f, 1e-7f, 0.5f, 0.99999994f, 1.0f}) {
                glm::vec3 d;
                ASSERT_TRUE(sampleSphericalTriangle(t, {ux, uy}, &d));
                ASSERT_TRUE(std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z));
                EXPECT_NEAR(glm::length(d), 1.0f, 1e-5f);
                EXPECT_TRUE(hits(glm::dvec3(k.p), glm::dvec3(d), glm::dvec3(k.a), glm::dvec3(k.b), glm::dvec3(k.c)))
                    << "u = " << ux << ", " << uy;
            }
    }
}
