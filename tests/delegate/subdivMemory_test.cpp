// Memory held per refined triangle by a subdivided mesh's GeometryRecord (docs/geometry.md,
// "Subdivision meshes: memory per refined triangle"). Pins the layout: normals and vertex
// primvars per point, face-varying ones per value through the shared corner map, not per
// triangle corner, and no spare capacity.
#include <gtest/gtest.h>

#include "delegate/mesh.h"
#include "delegate/renderDelegate.h"
#include "tests/support/testSceneDelegate.h"

using namespace principled;
using principled::test::TestSceneDelegate;

namespace {

/// An n x n quad grid, Catmull-Clark at `level`, with face-varying st and vertex displayColor.
void addGrid(TestSceneDelegate& scene, const hd::Path& id, int n, int level) {
    scene.addQuad(id, 1.0f);
    auto& p = scene.prim(id);
    std::vector<glm::vec3> points, colors;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            points.emplace_back(float(i) / n, float(j) / n, 0.1f * float((i * 7 + j * 3) % 5) / n);
            colors.emplace_back(float(i) / n, float(j) / n, 0.5f);
        }
    std::vector<glm::vec2> st;
    p.topology.faceVertexCounts.clear();
    p.topology.faceVertexIndices.clear();
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            p.topology.faceVertexCounts.push_back(4);
            const int v = j * (n + 1) + i;
            for (int c : {v, v + 1, v + n + 2, v + n + 1}) {
                p.topology.faceVertexIndices.push_back(c);
                st.emplace_back(points[size_t(c)].x, points[size_t(c)].y);
            }
        }
    p.topology.scheme = hd::Token("catmullClark");
    p.topology.refineLevel = level;
    p.values[hd::tokens::points()] = points;
    p.values[hd::Token("st")] = st;
    p.values[hd::Token("displayColor")] = colors;
    p.interpolation[hd::Token("st")] = hd::Interpolation::FaceVarying;
    p.interpolation[hd::Token("displayColor")] = hd::Interpolation::Vertex;
}

}  // namespace

TEST(SubdivMemory, RecordBytesPerRefinedTriangle) {
    embree::EmbreeRenderDelegate delegate;
    hd::RenderIndex index{&delegate};
    TestSceneDelegate scene{&index};
    const hd::Path id("/grid");
    addGrid(scene, id, 8, 4);  // 64 quads -> 16384 refined quads, 32768 triangles
    index.sync();
    auto* mesh = dynamic_cast<embree::Mesh*>(index.rprim(id));
    ASSERT_NE(mesh, nullptr);
    EXPECT_EQ(mesh->refineLevel(), 4);
    const embree::GeometryRecord& rec = *mesh->record();
    const size_t tris = rec.triangles.size();
    ASSERT_EQ(tris, size_t(32768));
    ASSERT_NE(rec.primvar(hd::Token("st")), nullptr);
    ASSERT_NE(rec.primvar(hd::Token("displayColor")), nullptr);
    EXPECT_FALSE(rec.vertexNormals.empty());
    const double perTriangle = double(rec.memoryBytes()) / double(tris);
    // Per triangle: indices 12, coarse face 4; per point (about half a point per triangle):
    // position, normal and displayColor 12 each; st per face-varying value (about half a
    // value per triangle) 8: about 38 bytes. Normals, displayColor and st per corner
    // (36 + 36 + 24 bytes) took it to about 118.
    EXPECT_LT(perTriangle, 48.0) << "record bytes per refined triangle";
    ASSERT_TRUE(rec.primvar(hd::Token("st"))->cornerIndex);
    // The whole mesh, with the stencils kept for re-posing (they dominate).
    const double meshPerTriangle = double(mesh->memoryBytes()) / double(tris);
    EXPECT_LT(meshPerTriangle, 400.0) << "mesh bytes per refined triangle";
    RecordProperty("recordBytesPerTriangle", std::to_string(perTriangle));
    RecordProperty("meshBytesPerTriangle", std::to_string(meshPerTriangle));
    std::printf("record %.1f B/tri, mesh (record + stencils) %.1f B/tri\n", perTriangle,
                meshPerTriangle);
}

// Re-posing (new points, same topology) refines into the same arrays: the triangles are not
// copied again and the record's layout and size stay the same.
TEST(SubdivMemory, ReposeReusesTheRecordArrays) {
    embree::EmbreeRenderDelegate delegate;
    hd::RenderIndex index{&delegate};
    TestSceneDelegate scene{&index};
    const hd::Path id("/grid");
    addGrid(scene, id, 4, 3);
    index.sync();
    auto* mesh = dynamic_cast<embree::Mesh*>(index.rprim(id));
    ASSERT_NE(mesh, nullptr);
    const embree::GeometryRecord& rec = *mesh->record();
    const std::vector<glm::vec3> before = rec.points;
    const std::vector<glm::uvec3> triangles = rec.triangles;
    const void* triangleData = rec.triangles.data();
    const size_t bytes = mesh->memoryBytes();
    const uint64_t builds = subdiv::SubdivTopology::refinerBuildCount();
    auto points = std::get<std::vector<glm::vec3>>(scene.prim(id).values[hd::tokens::points()]);
    for (auto& p : points) p.z += 1.0f;
    scene.prim(id).values[hd::tokens::points()] = points;
    index.changeTracker().markRprimDirty(id, hd::RprimDirty::Points);
    index.sync();
    ASSERT_EQ(rec.points.size(), before.size());
    for (size_t i = 0; i < before.size(); ++i)
        ASSERT_NEAR(rec.points[i].z, before[i].z + 1.0f, 1e-5f) << i;
    EXPECT_EQ(rec.triangles, triangles);
    EXPECT_EQ(rec.triangles.data(), triangleData);
    EXPECT_EQ(mesh->memoryBytes(), bytes);
    EXPECT_EQ(subdiv::SubdivTopology::refinerBuildCount(), builds) << "re-posed, not rebuilt";
    EXPECT_EQ(rec.vertexNormals.size(), rec.points.size());
}


namespace {

size_t triangles(hd::RenderIndex& index, const std::vector<hd::Path>& ids, std::vector<int>* levels) {
    size_t sum = 0;
    levels->clear();
    for (const hd::Path& id : ids) {
        auto* mesh = dynamic_cast<embree::Mesh*>(index.rprim(id));
        sum += mesh->record()->triangles.size();
        levels->push_back(mesh->refineLevel());
    }
    return sum;
}

bool warnedAboutBudget(embree::EmbreeRenderDelegate& delegate) {
    for (const std::string& w : delegate.takeWarnings())
        if (w.find("subdivisionBudget") != std::string::npos) return true;
    return false;
}

}  // namespace

// The scene-wide budget (render setting subdivisionBudget): meshes that together would refine
// past it are lowered alike until they fit; under it nothing changes.
TEST(SubdivMemory, TheSceneBudgetLowersEveryMeshAlikeUntilTheSceneFits) {
    std::vector<hd::Path> ids{hd::Path("/a"), hd::Path("/b"), hd::Path("/c")};
    std::vector<int> levels;
    {
        embree::EmbreeRenderDelegate delegate;  // default budget 16M triangles: no change
        hd::RenderIndex index{&delegate};
        TestSceneDelegate scene{&index};
        for (const auto& id : ids) addGrid(scene, id, 8, 4);  // 32768 triangles each
        index.sync();
        EXPECT_EQ(triangles(index, ids, &levels), size_t(3 * 32768));
        EXPECT_EQ(levels, (std::vector<int>{4, 4, 4}));
        EXPECT_FALSE(warnedAboutBudget(delegate));
    }
    embree::EmbreeRenderDelegate delegate;
    delegate.setRenderSetting(hd::Token("subdivisionBudget"), hd::Value(50000));
    hd::RenderIndex index{&delegate};
    TestSceneDelegate scene{&index};
    for (const auto& id : ids) addGrid(scene, id, 8, 4);
    index.sync();
    // Level 3 would be 3 x 8192 = 24576 triangles; level 4 is 98304. Fixed levels lose one
    // level every two half steps, so all three stand at 3.
    EXPECT_EQ(triangles(index, ids, &levels), size_t(3 * 8192));
    EXPECT_EQ(levels, (std::vector<int>{3, 3, 3}));
    EXPECT_TRUE(warnedAboutBudget(delegate));
    // A colour edit rebuilds /a alone; the fit still covers the whole scene, so it stays at 3.
    index.changeTracker().markRprimDirty(ids[0], hd::RprimDirty::Primvar);
    index.sync();
    EXPECT_EQ(triangles(index, ids, &levels), size_t(3 * 8192));
    EXPECT_EQ(levels, (std::vector<int>{3, 3, 3}));
    // A fourth mesh: four at level 3 (32768) still fit, so it gets 3 and nothing else moves.
    const hd::Path late("/d");
    addGrid(scene, late, 8, 4);
    index.sync();
    ids.push_back(late);
    EXPECT_EQ(triangles(index, ids, &levels), size_t(4 * 8192));
    EXPECT_EQ(levels, (std::vector<int>{3, 3, 3, 3}));
    // A tighter budget and a fifth mesh: five at level 3 (40960) do not fit 35000, so all five
    // go to level 2, the four clean ones rebuilt in the same sync, as a fresh scene would be.
    delegate.setRenderSetting(hd::Token("subdivisionBudget"), hd::Value(35000));
    const hd::Path fifth("/e");
    addGrid(scene, fifth, 8, 4);
    index.sync();
    ids.push_back(fifth);
    EXPECT_EQ(triangles(index, ids, &levels), size_t(5 * 2048));
    EXPECT_EQ(levels, (std::vector<int>{2, 2, 2, 2, 2}));
    EXPECT_TRUE(warnedAboutBudget(delegate));
}

// Meshes that will not be built ask nothing of the budget: a broken cage does not push the
// others down.
TEST(SubdivMemory, MeshesThatWillNotBuildTakeNoBudget) {
    embree::EmbreeRenderDelegate delegate;
    delegate.setRenderSetting(hd::Token("subdivisionBudget"), hd::Value(40000));
    hd::RenderIndex index{&delegate};
    TestSceneDelegate scene{&index};
    addGrid(scene, hd::Path("/good"), 8, 4);  // 32768 triangles: fits alone
    addGrid(scene, hd::Path("/broken"), 8, 4);
    scene.prim(hd::Path("/broken")).topology.faceVertexCounts[0] = 1000000000;
    addGrid(scene, hd::Path("/nan"), 8, 4);
    std::get<std::vector<glm::vec3>>(scene.prim(hd::Path("/nan")).values[hd::tokens::points()])[3].x = NAN;
    index.sync();
    auto* good = dynamic_cast<embree::Mesh*>(index.rprim(hd::Path("/good")));
    EXPECT_EQ(good->refineLevel(), 4);
    EXPECT_FALSE(warnedAboutBudget(delegate));
}

// A mesh dirty for another reason (its transform) that the fit moves is rebuilt at the new
// level in the same sync, not left at its old one.
TEST(SubdivMemory, AMeshDirtyForAnotherReasonStillFollowsTheFit) {
    embree::EmbreeRenderDelegate delegate;
    delegate.setRenderSetting(hd::Token("subdivisionBudget"), hd::Value(35000));
    hd::RenderIndex index{&delegate};
    TestSceneDelegate scene{&index};
    std::vector<hd::Path> ids{hd::Path("/a"), hd::Path("/b"), hd::Path("/c"), hd::Path("/d")};
    for (const auto& id : ids) addGrid(scene, id, 8, 4);
    index.sync();  // four at level 3: 32768
    std::vector<int> levels;
    EXPECT_EQ(triangles(index, ids, &levels), size_t(4 * 8192));
    index.changeTracker().markRprimDirty(ids[0], hd::RprimDirty::Transform);
    const hd::Path fifth("/e");
    addGrid(scene, fifth, 8, 4);
    index.sync();  // five at level 3 would be 40960: all go to 2, /a included
    ids.push_back(fifth);
    EXPECT_EQ(triangles(index, ids, &levels), size_t(5 * 2048));
    EXPECT_EQ(levels, (std::vector<int>{2, 2, 2, 2, 2}));
}

// Changing a dicing setting or the budget re-plans every subdivision mesh at the next sync,
// with nothing else dirty.
TEST(SubdivMemory, ChangingTheBudgetReplansEveryMeshAtTheNextSync) {
    embree::EmbreeRenderDelegate delegate;
    delegate.setRenderSetting(hd::Token("subdivisionBudget"), hd::Value(50000));
    hd::RenderIndex index{&delegate};
    TestSceneDelegate scene{&index};
    std::vector<hd::Path> ids{hd::Path("/a"), hd::Path("/b"), hd::Path("/c")};
    for (const auto& id : ids) addGrid(scene, id, 8, 4);
    index.sync();
    std::vector<int> levels;
    triangles(index, ids, &levels);
    EXPECT_EQ(levels, (std::vector<int>{3, 3, 3}));
    delegate.setRenderSetting(hd::Token("subdivisionBudget"), hd::Value(0));  // no limit
    index.sync();
    triangles(index, ids, &levels);
    EXPECT_EQ(levels, (std::vector<int>{4, 4, 4}));
    delegate.setRenderSetting(hd::Token("subdivisionBudget"), hd::Value(10000));
    index.sync();
    EXPECT_EQ(triangles(index, ids, &levels), size_t(3 * 2048));
    EXPECT_EQ(levels, (std::vector<int>{2, 2, 2}));
    index.sync();  // nothing changed: nothing rebuilt
    EXPECT_TRUE(index.lastSync().rprims.empty());
}

// Removing a mesh fits the budget again: the others may rise to where a fresh scene puts them.
TEST(SubdivMemory, RemovingAMeshRefitsTheOthers) {
    embree::EmbreeRenderDelegate delegate;
    delegate.setRenderSetting(hd::Token("subdivisionBudget"), hd::Value(35000));
    hd::RenderIndex index{&delegate};
    TestSceneDelegate scene{&index};
    std::vector<hd::Path> ids{hd::Path("/a"), hd::Path("/b"), hd::Path("/c"), hd::Path("/d"), hd::Path("/e")};
    for (const auto& id : ids) addGrid(scene, id, 8, 4);
    index.sync();
    std::vector<int> levels;
    EXPECT_EQ(triangles(index, ids, &levels), size_t(5 * 2048));  // five at 3 would be 40960
    index.removeRprim(ids.back());
    ids.pop_back();
    index.sync();
    EXPECT_EQ(triangles(index, ids, &levels), size_t(4 * 8192));  // four at 3: 32768
    EXPECT_EQ(levels, (std::vector<int>{3, 3, 3, 3}));
}

// A flat cage is drawn unrefined only when its primvars are their own limit too: a linear st
// and colour keep level 0, a painted colour (smoothed by the refinement) does not.
TEST(SubdivMemory, AFlatCageStaysUnrefinedOnlyWithPrimvarsThatFollowIt) {
    auto levelWith = [](bool painted) {
        embree::EmbreeRenderDelegate delegate;
        delegate.setDicingView(glm::vec3(0.5f, 0.5f, 2.0f), 0.8f, 500);
        hd::RenderIndex index{&delegate};
        TestSceneDelegate scene{&index};
        const hd::Path id("/flat");
        addGrid(scene, id, 8, -1);  // adaptive
        auto& p = scene.prim(id);
        auto& points = std::get<std::vector<glm::vec3>>(p.values[hd::tokens::points()]);
        for (glm::vec3& q : points) q.z = 0.0f;
        if (painted) std::get<std::vector<glm::vec3>>(p.values[hd::Token("displayColor")])[40] = glm::vec3(1, 0, 0);
        index.sync();
        return dynamic_cast<embree::Mesh*>(index.rprim(id))->refineLevel();
    };
    EXPECT_EQ(levelWith(false), 0);
    EXPECT_GT(levelWith(true), 0);
}

// One sync, one budget warning, however many times the fit runs in it.
TEST(SubdivMemory, OneSyncGivesOneBudgetWarning) {
    embree::EmbreeRenderDelegate delegate;
    delegate.setRenderSetting(hd::Token("subdivisionBudget"), hd::Value(35000));
    hd::RenderIndex index{&delegate};
    TestSceneDelegate scene{&index};
    for (const char* id : {"/a", "/b", "/c", "/d"}) addGrid(scene, hd::Path(id), 8, 4);
    index.sync();
    delegate.takeWarnings();
    addGrid(scene, hd::Path("/e"), 8, 4);  // moves the four clean meshes: the fit runs twice
    index.sync();
    int count = 0;
    for (const std::string& w : delegate.takeWarnings()) count += w.find("subdivisionBudget") != std::string::npos;
    EXPECT_EQ(count, 1);
}
