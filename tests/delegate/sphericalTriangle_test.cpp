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
