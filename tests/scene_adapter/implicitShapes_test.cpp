// Implicit UsdGeom shapes as meshes: counts, exact extents, outward normals, silhouette error.
#include "scene_adapter/implicitShapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "delegate/hd/tokens.h"
#include "delegate/renderDelegate.h"
#include "scene_adapter/usdSceneDelegate.h"
#include "scene_adapter/valueConvert.h"
#include "scene_adapter/usda/stage.h"

using namespace principled;
using namespace principled::adapter;

namespace {

struct Case {
    const char* type;
    char axis;
    size_t points, faces;
};

// Newell normal of face f and its centroid.
void faceFrame(const ShapeMesh& m, size_t start, int count, glm::dvec3* n, glm::dvec3* c) {
    *n = glm::dvec3(0.0), *c = glm::dvec3(0.0);
    for (int k = 0; k < count; ++k) {
        glm::dvec3 a(m.points[size_t(m.faceVertexIndices[start + k])]);
        glm::dvec3 b(m.points[size_t(m.faceVertexIndices[start + (k + 1) % count])]);
        *n += glm::cross(a, b);
        *c += a / double(count);
    }
}

}  // namespace

TEST(ImplicitShapes, CountsExtentsAndOutwardNormals) {
    const size_t n = kShapeSegments, r = kCapsuleRings;
    const Case cases[] = {
        {"Cube", 'Z', 8, 6},
        {"Cylinder", 'Z', 2 * n, n + 2},   {"Cylinder", 'X', 2 * n, n + 2},
        {"Cone", 'Y', n + 1, n + 1},       {"Cone", 'Z', n + 1, n + 1},
        {"Capsule", 'Z', 2 + 2 * r * n, n * (2 * r + 1)},
        {"Capsule", 'Y', 2 + 2 * r * n, n * (2 * r + 1)},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(std::string(c.type) + " axis " + c.axis);
        ShapeParams p;
        p.size = 3.0, p.radius = 0.5, p.height = 1.5, p.axis = c.axis;
        ShapeMesh m;
        std::string error;
        ASSERT_TRUE(buildImplicitShape(c.type, p, &m, &error)) << error;
        EXPECT_EQ(m.points.size(), c.points);
        EXPECT_EQ(m.faceVertexCounts.size(), c.faces);
        EXPECT_EQ(m.normals.size(), m.faceVertexIndices.size());
        // Bounds of the tessellation equal the analytic extent (72 segments include the axes).
        glm::vec3 lo(1e30f), hi(-1e30f);
        for (const auto& q : m.points) lo = glm::min(lo, q), hi = glm::max(hi, q);
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(lo[k], m.extentMin[k], 1e-6);
            EXPECT_NEAR(hi[k], m.extentMax[k], 1e-6);
        }
        // Shapes are convex and centred: every face and corner normal points away from 0.
        size_t start = 0;
        for (size_t f = 0; f < m.faceVertexCounts.size(); ++f) {
            int count = m.faceVertexCounts[f];
            glm::dvec3 fn, centroid;
            faceFrame(m, start, count, &fn, &centroid);
            EXPECT_GT(glm::dot(fn, centroid), 0.0) << "face " << f;
            for (int k = 0; k < count; ++k) {
                glm::dvec3 cn(m.normals[start + size_t(k)]);
                EXPECT_NEAR(glm::length(cn), 1.0, 1e-5);
                EXPECT_GT(glm::dot(cn, fn), 0.0) << "face " << f << " corner " << k;
            }
            start += size_t(count);
        }
    }
}

TEST(ImplicitShapes, UsdFallbacksAndSilhouetteError) {
    ShapeMesh m;
    std::string error;
    ASSERT_TRUE(buildImplicitShape("Cylinder", ShapeParams{}, &m, &error));
    EXPECT_EQ(m.extentMin, glm::vec3(-1, -1, -1));  // radius 1, height 2, axis Z
    EXPECT_EQ(m.extentMax, glm::vec3(1, 1, 1));
    // The worst silhouette point is mid-edge: its distance from the axis.
    glm::vec3 a = m.points[0], b = m.points[1];
    double mid = glm::length(glm::dvec2(0.5 * (a.x + b.x), 0.5 * (a.y + b.y)));
    EXPECT_GT(mid, 1.0 - 1e-3);
    ASSERT_TRUE(buildImplicitShape("Cube", ShapeParams{}, &m, &error));
    EXPECT_EQ(m.extentMax, glm::vec3(1, 1, 1));  // size 2
    // Capsule fallbacks: radius 0.5, height 1, and the height excludes the caps.
    ASSERT_TRUE(buildImplicitShape("Capsule", shapeFallbacks("Capsule"), &m, &error));
    EXPECT_EQ(m.extentMax, glm::vec3(0.5f, 0.5f, 1.0f));
    EXPECT_EQ(shapeFallbacks("Cone").radius, 1.0);
    ShapeParams bad;
    bad.radius = -1;
    EXPECT_FALSE(buildImplicitShape("Cone", bad, &m, &error));
    EXPECT_FALSE(error.empty());
}

TEST(ImplicitShapes, UsdWgPrimitivesMatchTheirAuthoredExtents) {
    // usd-wg schemaTests/usdGeom/primitives: every authored extent equals the bounds of the
    // mesh the adapter serves (capsule.usda authors none: its extent is the analytic one).
    std::string dir = std::string(PRINCIPLED_SOURCE_DIR) +
                      "/../shared/usd-wg/test_assets/schemaTests/usdGeom/primitives";
    int checked = 0;
    for (const auto& f : std::filesystem::directory_iterator(dir)) {
        if (f.path().extension() != ".usda") continue;
        SCOPED_TRACE(f.path().filename().string());
        auto stage = usd::Stage::open(f.path().string());
        embree::EmbreeRenderDelegate rd;
        hd::RenderIndex index(&rd);
        UsdSceneDelegate sd(*stage);
        sd.populate(&index);
        EXPECT_TRUE(sd.warnings().empty()) << sd.warnings().front();
        for (const usd::Prim* prim : stage->traverse()) {
            if (!isImplicitShape(prim->typeName())) continue;
            hd::Path id(prim->path());
            ASSERT_NE(index.rprim(id), nullptr);
            const usd::Attribute* extent = prim->attribute("extent");
            if (!extent) continue;
            hd::Value ev = toHdValue(extent->get());
            auto* e = hd::getIf<std::vector<glm::vec3>>(ev);
            ASSERT_TRUE(e && e->size() == 2);
            hd::Value pv = sd.get(id, hd::tokens::points());
            auto* pts = hd::getIf<std::vector<glm::vec3>>(pv);
            ASSERT_TRUE(pts);
            glm::vec3 lo(1e30f), hi(-1e30f);
            for (const auto& q : *pts) lo = glm::min(lo, q), hi = glm::max(hi, q);
            for (int k = 0; k < 3; ++k) {
                EXPECT_NEAR(lo[k], (*e)[0][k], 1e-5) << prim->path();
                EXPECT_NEAR(hi[k], (*e)[1][k], 1e-5) << prim->path();
            }
            ++checked;
        }
    }
    EXPECT_GE(checked, 4);
}

TEST(ImplicitShapes, PlanesLieAcrossTheirAxisWithWidthAndLengthWhereTheSchemaPutsThem) {
    // UsdGeomPlane: width along x (axis Z or Y) or z (axis X), length along y (axis Z or X) or z
    // (axis Y); one quad facing +axis, wound counter-clockwise seen from the front.
    struct Case {
        char axis;
        glm::vec3 normal, extent;
    };
    for (const Case& c : {Case{'Z', {0, 0, 1}, {1.5f, 2.5f, 0}}, Case{'Y', {0, 1, 0}, {1.5f, 0, 2.5f}},
                          Case{'X', {1, 0, 0}, {0, 2.5f, 1.5f}}}) {
        adapter::ShapeParams p = adapter::shapeFallbacks("Plane");
        p.width = 3.0;
        p.length = 5.0;
        p.axis = c.axis;
        adapter::ShapeMesh m;
        std::string error;
        ASSERT_TRUE(adapter::buildImplicitShape("Plane", p, &m, &error)) << error;
        ASSERT_EQ(m.points.size(), 4u);
        EXPECT_EQ(m.faceVertexCounts, std::vector<int>{4});
        EXPECT_EQ(m.extentMax, c.extent) << c.axis;
        EXPECT_EQ(m.extentMin, -c.extent) << c.axis;
        const glm::vec3 n = glm::cross(m.points[1] - m.points[0], m.points[2] - m.points[0]);
        EXPECT_GT(glm::dot(n, c.normal), 0.0f) << c.axis;
        for (const glm::vec3& v : m.normals) EXPECT_EQ(v, c.normal);
    }
    adapter::ShapeParams bad = adapter::shapeFallbacks("Plane");
    bad.width = -1.0;
    adapter::ShapeMesh m;
    std::string error;
    EXPECT_FALSE(adapter::buildImplicitShape("Plane", bad, &m, &error));
    EXPECT_NE(error.find("width"), std::string::npos);
}
