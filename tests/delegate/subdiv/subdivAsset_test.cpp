// SPDX-License-Identifier: Apache-2.0
// The usd-wg Pyramid asset (full_assets/SubdivisionSurfaces) with its crease and corner
// variants, read with a minimal array scanner so this test needs no USD parser.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "delegate/subdiv/subdivTopology.h"

using namespace principled;
using namespace principled::subdiv;

namespace {

const char* kPyramid = "../shared/usd-wg/full_assets/SubdivisionSurfaces/Pyramid/geo.usda";

/// Numbers of the first `name = [...]` array in text (parentheses and commas skipped).
std::vector<double> firstArray(const std::string& text, const std::string& name) {
    std::vector<double> out;
    size_t at = text.find(name + " = [");
    if (at == std::string::npos) return out;
    size_t begin = at + name.size() + 4, end = text.find(']', begin);  // after " = ["
    std::string body = text.substr(begin, end - begin);
    for (char& c : body)
        if (c == '(' || c == ')' || c == ',') c = ' ';
    std::istringstream in(body);
    for (double v; in >> v;) out.push_back(v);
    return out;
}

struct Pyramid {
    hd::MeshTopology topology;
    std::vector<glm::vec3> points;
    std::string text;
};

bool loadPyramid(Pyramid* p) {
    std::ifstream f(kPyramid);
    if (!f) return false;
    std::stringstream ss;
    ss << f.rdbuf();
    p->text = ss.str();
    for (double v : firstArray(p->text, "int[] faceVertexCounts"))
        p->topology.faceVertexCounts.push_back(int(v));
    for (double v : firstArray(p->text, "int[] faceVertexIndices"))
        p->topology.faceVertexIndices.push_back(int(v));
    std::vector<double> xyz = firstArray(p->text, "point3f[] points");
    for (size_t i = 0; i + 2 < xyz.size(); i += 3)
        p->points.emplace_back(float(xyz[i]), float(xyz[i + 1]), float(xyz[i + 2]));
    return !p->points.empty() && !p->topology.faceVertexCounts.empty();
}

float distanceToSegment(glm::vec3 p, glm::vec3 a, glm::vec3 b) {
    float t = glm::clamp(glm::dot(p - a, b - a) / glm::dot(b - a, b - a), 0.0f, 1.0f);
    return glm::length(p - (a + t * (b - a)));
}

}  // namespace

TEST(SubdivAsset, UsdWgPyramidCreasesAndCorners) {
    Pyramid p;
    if (!loadPyramid(&p)) GTEST_SKIP() << kPyramid << " not found (run from the repository root)";
    // The "edges" variant: every cage edge of the outer tetrahedron (points 0..3) at sharpness
    // 100 (>= 10 is infinitely sharp); the "corners" variant pins points 0 and 2 at 25.
    hd::SubdivTags edges;
    for (double v : firstArray(p.text, "int[] creaseIndices"))
        edges.creaseIndices.push_back(int(v));
    for (double v : firstArray(p.text, "int[] creaseLengths"))
        edges.creaseLengths.push_back(int(v));
    for (double v : firstArray(p.text, "float[] creaseSharpnesses"))
        edges.creaseSharpnesses.push_back(float(v));
    hd::SubdivTags corners;
    for (double v : firstArray(p.text, "int[] cornerIndices"))
        corners.cornerIndices.push_back(int(v));
    for (double v : firstArray(p.text, "float[] cornerSharpnesses"))
        corners.cornerSharpnesses.push_back(float(v));
    ASSERT_EQ(edges.creaseLengths.size(), 6u);
    ASSERT_EQ(corners.cornerIndices.size(), 2u);

    auto refineWith = [&](const hd::SubdivTags& tags, RefinedMesh* m) {
        std::string err;
        auto t = SubdivTopology::create(p.topology, tags, p.points.size(), BuildOptions{3}, &err);
        ASSERT_TRUE(t) << err;
        EXPECT_TRUE(t->warnings().empty()) << t->warnings()[0];
        ASSERT_TRUE(t->refine(p.points, m));
        EXPECT_EQ(m->triangles.size(), p.topology.faceVertexCounts.size() * 2 * 64);
    };
    auto nearest = [](const RefinedMesh& m, glm::vec3 q) {
        float best = 1e30f;
        for (const glm::vec3& x : m.points) best = std::min(best, glm::length(x - q));
        return best;
    };
    RefinedMesh plain, sharpEdges, sharpCorners;
    refineWith({}, &plain);
    refineWith(edges, &sharpEdges);
    refineWith(corners, &sharpCorners);
    // Smooth: the apex (point 0) is pulled in. Corners: points 0 and 2 stay, 1 does not.
    EXPECT_GT(nearest(plain, p.points[0]), 1e-2f);
    EXPECT_LT(nearest(sharpCorners, p.points[0]), 1e-5f);
    EXPECT_LT(nearest(sharpCorners, p.points[2]), 1e-5f);
    EXPECT_GT(nearest(sharpCorners, p.points[1]), 1e-2f);
    // Edges: all four tetrahedron corners stay, and 8 refined points per crease edge lie on it
    // (each crease is a single cage edge between two fixed crease corners).
    for (int v = 0; v < 4; ++v) EXPECT_LT(nearest(sharpEdges, p.points[v]), 1e-5f);
    for (size_t e = 0; e < 6; ++e) {
        glm::vec3 a = p.points[edges.creaseIndices[2 * e]],
                  b = p.points[edges.creaseIndices[2 * e + 1]];
        int on = 0;
        for (const glm::vec3& x : sharpEdges.points) on += distanceToSegment(x, a, b) < 1e-5f;
        EXPECT_EQ(on, 9) << "crease " << e;  // 2^3 segments -> 9 points including the ends
    }
}

TEST(SubdivAsset, UsdWgSchemeCubes) {
    // schemaTests/usdGeom/meshes/subdiv_*: unit cubes (12 triangles for loop) per scheme.
    struct Expect {
        const char* name;
        Scheme scheme;
        bool warns;
    };
    const Expect cases[] = {{"subdiv_catmullClark", Scheme::CatmullClark, false},
                            {"subdiv_bilinear", Scheme::Bilinear, false},
                            {"subdiv_loop_triangles", Scheme::Loop, false},
                            {"subdiv_loop_quads", Scheme::CatmullClark, true},
                            {"subdiv_none", Scheme::None, false}};
    for (const Expect& e : cases) {
        const std::string path =
            std::string("../shared/usd-wg/test_assets/schemaTests/usdGeom/meshes/") + e.name + "/" +
            e.name + ".usda";
        std::ifstream f(path);
        if (!f) GTEST_SKIP() << path << " not found (run from the repository root)";
        std::stringstream ss;
        ss << f.rdbuf();
        const std::string text = ss.str();
        hd::MeshTopology t;
        for (double v : firstArray(text, "int[] faceVertexCounts"))
            t.faceVertexCounts.push_back(int(v));
        for (double v : firstArray(text, "int[] faceVertexIndices"))
            t.faceVertexIndices.push_back(int(v));
        std::vector<glm::vec3> points;
        std::vector<double> xyz = firstArray(text, "point3f[] points");
        for (size_t i = 0; i + 2 < xyz.size(); i += 3)
            points.emplace_back(float(xyz[i]), float(xyz[i + 1]), float(xyz[i + 2]));
        const size_t q = text.find("subdivisionScheme = \"");
        ASSERT_NE(q, std::string::npos) << e.name;
        const size_t b = q + 21;
        t.scheme = hd::Token(text.substr(b, text.find('"', b) - b));

        std::string err;
        auto topo = SubdivTopology::create(t, {}, points.size(), BuildOptions{2}, &err);
        ASSERT_TRUE(topo) << e.name << ": " << err;
        EXPECT_EQ(topo->scheme(), e.scheme) << e.name;
        EXPECT_EQ(!topo->warnings().empty(), e.warns) << e.name;
        RefinedMesh m;
        ASSERT_TRUE(topo->refine(points, &m));
        const size_t faces = t.faceVertexCounts.size();
        const size_t expected = e.scheme == Scheme::None   ? 2 * faces
                                : e.scheme == Scheme::Loop ? faces * 16
                                                           : 2 * faces * 16;
        EXPECT_EQ(m.triangles.size(), expected) << e.name;
        for (size_t i = 0; i < m.points.size(); ++i) {
            const glm::vec3& p = m.points[i];
            const float box = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
            ASSERT_LE(box, 0.5f + 1e-6f) << e.name;  // inside the cage
            if (e.scheme == Scheme::Bilinear || e.scheme == Scheme::None) {
                ASSERT_NEAR(box, 0.5f, 1e-6f) << e.name;  // on the cage
            }
            if (!m.normals.empty()) {
                ASSERT_GT(glm::dot(m.normals[i], p), 0.0f) << e.name;
            }
        }
        if (e.scheme == Scheme::CatmullClark) {  // Halstead limit of a cube corner: 0.25
            float best = 1.0f;
            for (const glm::vec3& p : m.points)
                best = std::min(best, glm::length(p - glm::vec3(0.25f)));
            EXPECT_LT(best, 1e-5f) << e.name;
        }
    }
}
