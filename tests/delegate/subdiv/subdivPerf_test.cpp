// SPDX-License-Identifier: Apache-2.0
// Build and re-pose timings of large refinements (label "stress": not in the default run).
// Run: ./build/bin/subdiv_perf   (figures recorded in docs/subdivision.md)
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <ctime>

#include "delegate/subdiv/subdivTopology.h"
#include "tests/delegate/subdiv/subdivTestMeshes.h"

using namespace principled;
using namespace principled::subdiv;

namespace {

double cpuSeconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

struct Time {
    double wall = 0, cpu = 0;  ///< cpu: all threads of the process
};

Time timeOf(const auto& f) {
    const double c0 = cpuSeconds();
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return {std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(),
            cpuSeconds() - c0};
}

void measure(int n, int level, bool varying, bool flat = false) {
    test::Cage g = test::grid(n);
    // A gentle bump so the surface is not planar (no effect on the cost).
    for (glm::vec3& p : g.points) p.z = 0.1f * std::sin(p.x) * std::cos(p.y);
    std::vector<float> st;
    for (const glm::vec3& p : g.points) st.insert(st.end(), {p.x / n, p.y / n});
    BuildOptions o{level};
    o.varying = varying;
    o.flatStencils = flat;
    o.faceVarying = {{g.topology.faceVertexIndices, g.points.size()}};
    std::unique_ptr<SubdivTopology> t;
    std::string err;
    Time build =
        timeOf([&] { t = SubdivTopology::create(g.topology, {}, g.points.size(), o, &err); });
    ASSERT_TRUE(t) << err;
    RefinedMesh m;
    Time first = timeOf([&] { ASSERT_TRUE(t->refine(g.points, &m)); });
    const int runs = 5;
    Time repose, fvar;
    std::vector<float> out;
    for (int r = 0; r < runs; ++r) {
        for (glm::vec3& p : g.points) p.z += 0.01f;
        Time r1 = timeOf([&] { ASSERT_TRUE(t->refine(g.points, &m)); });
        Time r2 = timeOf(
            [&] { ASSERT_TRUE(t->refineFaceVarying(0, st.data(), g.points.size(), 2, &out)); });
        repose.wall += r1.wall / runs;
        repose.cpu += r1.cpu / runs;
        fvar.wall += r2.wall / runs;
        fvar.cpu += r2.cpu / runs;
    }
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    const BuildTimings& bt = t->timings();
    std::printf(
        "grid %dx%d level %d, st channel, varying %s, %s stencils\n  %s\n"
        "  build %.3f s wall, %.3f s cpu (refiner %.3f, vertex stencils %.3f, varying %.3f,"
        " limit masks %.3f, fvar %.3f, triangles %.3f)\n"
        "  stencil+topology memory %.1f MB, peak RSS so far %.1f MB\n"
        "  first refine %.1f ms wall (copies triangles); re-pose %.1f ms wall, %.1f ms cpu"
        " (points+normals); fvar st %.1f ms wall, %.1f ms cpu\n",
        n, n, level, varying ? "on" : "off", flat ? "flat Far" : "per-level", t->describe().c_str(),
        build.wall, build.cpu, bt.refiner, bt.vertexStencils, bt.varyingStencils, bt.limitMasks,
        bt.faceVarying, bt.triangles, double(t->memoryBytes()) / 1e6, double(ru.ru_maxrss) / 1e3,
        first.wall * 1e3, repose.wall * 1e3, repose.cpu * 1e3, fvar.wall * 1e3, fvar.cpu * 1e3);
    EXPECT_EQ(t->triangleCount(), size_t(2) * size_t(n * n) << (2 * level));
}

}  // namespace

TEST(SubdivPerf, Grid45Level4OneMillionTriangles) {
    measure(45, 4, false);
}
TEST(SubdivPerf, Grid45Level4FlatFarTables) {
    measure(45, 4, false, true);
}
TEST(SubdivPerf, Grid64Level4TwoMillionTriangles) {
    measure(64, 4, true);
}
