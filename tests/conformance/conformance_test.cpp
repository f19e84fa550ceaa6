// usd-wg conformance corpus (docs/conformance.md). The corpus is read in place from
// ../shared/usd-wg (next to the repository root), never copied.
//   Corpus/RendersEveryFile    every .usda/.usd renders at 64x64 without throwing or NaN/Inf
//   Invalid.*                  the intentionally invalid files give their clear message and the
//                              rest of the stage still renders
//   Readme.*                   what the READMEs say a renderer shows, checked on pixels/geometry
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "delegate/hd/tokens.h"
#include "delegate/renderDelegate.h"
#include "plugins/renderSession.h"
#include "scene_adapter/usdSceneDelegate.h"
#include "scene_adapter/usda/stage.h"

using namespace principled;
namespace fs = std::filesystem;

namespace {

const std::string kCorpus = PRINCIPLED_SOURCE_DIR "/../shared/usd-wg";

std::string corpus(const std::string& rel) { return kCorpus + "/" + rel; }

// Files that crash the renderer today: each has its own DISABLED_ test below naming the gap
// (docs/conformance.md); they are left out of the parameterized run so the rest stays green.
// (weird_matrix_transform.usda was one: its projective prim is now skipped with a warning.)
const std::set<std::string> kKnownCrashes = {};

// Every layer of the corpus, relative to kCorpus, sorted (known crashes left out).
std::vector<std::string> corpusFiles(bool withKnownCrashes = false) {
    std::vector<std::string> files;
    std::error_code ec;
    if (!fs::is_directory(kCorpus, ec)) return files;
    for (const auto& e : fs::recursive_directory_iterator(kCorpus, ec)) {
        if (!e.is_regular_file()) continue;
        std::string ext = e.path().extension().string();
        if (ext != ".usda" && ext != ".usd") continue;
        std::string rel = fs::relative(e.path(), kCorpus).generic_string();
        if (withKnownCrashes || !kKnownCrashes.count(rel)) files.push_back(rel);
    }
    std::sort(files.begin(), files.end());
    return files;
}

struct Rendered {
    std::unique_ptr<host::RenderSession> session;
    std::map<std::string, host::RenderSession::AovImage> aov;
    std::vector<std::string> warnings;
    int w = 0, h = 0;
    const float* color(int x, int y) const { return session->color() + 4 * (y * w + x); }
    int primId(int x, int y) const {
        return static_cast<const int32_t*>(aov.at("primId").pixels)[y * w + x];
    }
    glm::vec3 vec3(const std::string& name, int x, int y) const {
        const auto& a = aov.at(name);
        const float* p = static_cast<const float*>(a.pixels) + a.components * (y * w + x);
        return {p[0], a.components > 1 ? p[1] : 0.0f, a.components > 2 ? p[2] : 0.0f};
    }
    bool hit(int x, int y) const { return primId(x, y) >= 0; }
    int hits() const {
        int n = 0;
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) n += hit(x, y);
        return n;
    }
    bool allFinite() const {
        for (const auto& [name, a] : aov) {
            if (a.isInt) continue;
            const float* p = static_cast<const float*>(a.pixels);
            for (int i = 0; i < w * h * a.components; ++i)
                if (!std::isfinite(p[i])) return false;
        }
        return true;
    }
    std::string allWarnings() const {
        std::string s;
        for (const auto& m : warnings) s += m + "\n";
        return s;
    }
};

Rendered render(const std::string& path, int w = 64, int h = 64, int spp = 2,
                std::vector<std::string> aovs = {"primId", "position"}, double time = NAN,
                const std::string& camera = "", const std::map<std::string, std::string>& settings = {}) {
    host::SessionOptions o;
    o.settings = settings;
    o.width = w;
    o.height = h;
    o.samplesPerPixel = spp;
    o.maxDepth = 3;
    o.aovs = std::move(aovs);
    o.time = time;
    o.camera = camera;
    Rendered r;
    r.w = w;
    r.h = h;
    r.session = host::RenderSession::openFile(path, o);
    int guard = 0;
    while (!r.session->step() && ++guard < 10000) {
    }
    for (const auto& a : r.session->aovs()) r.aov[a.name] = a;
    r.warnings = r.session->takeWarnings();
    return r;
}

// A stage populated into a render index through UsdSceneDelegate (no rendering).
struct Populated {
    std::unique_ptr<usd::Stage> stage;
    embree::EmbreeRenderDelegate renderDelegate;
    hd::RenderIndex index{&renderDelegate};
    std::unique_ptr<adapter::UsdSceneDelegate> scene;
    explicit Populated(const std::string& path, const usd::StageOptions& options = {},
                       double time = NAN) {
        stage = usd::Stage::open(path, options);
        adapter::AdapterOptions ao;
        ao.time = time;
        scene = std::make_unique<adapter::UsdSceneDelegate>(*stage, ao);
        scene->populate(&index);
    }
    std::set<std::string> rprims() const {
        std::set<std::string> s;
        for (const auto& id : index.rprimIds()) s.insert(id.str());
        return s;
    }
    bool has(const std::string& path) const { return rprims().count(path) != 0; }
    std::vector<glm::vec3> points(const std::string& path) const {
        hd::Value v = scene->get(hd::Path(path), hd::tokens::points());
        if (auto* p = hd::getIf<std::vector<glm::vec3>>(v)) return *p;
        return {};
    }
    glm::vec3 displayColor(const std::string& path) const {
        hd::Value v = scene->get(hd::Path(path), hd::tokens::displayColor());
        if (auto* p = hd::getIf<std::vector<glm::vec3>>(v); p && !p->empty()) return (*p)[0];
        if (auto* p = hd::getIf<glm::vec3>(v)) return *p;
        return glm::vec3(-1.0f);
    }
    std::string warnings() const {
        std::string s;
        for (const auto& d : stage->warnings()) s += d.str() + "\n";
        for (const auto& m : scene->warnings()) s += m + "\n";
        return s;
    }
};

std::string testName(const std::string& rel) {
    std::string s;
    for (char c : rel) s += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    return s;
}

bool contains(const std::string& haystack, const std::string& needle) {
    return haystack.find(needle) != std::string::npos;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// (a) Every file renders.

class Corpus : public ::testing::TestWithParam<std::string> {};

TEST_P(Corpus, RendersEveryFile) {
    const std::string path = corpus(GetParam());
    Rendered r;
    ASSERT_NO_THROW(r = render(path)) << path;
    EXPECT_TRUE(r.allFinite()) << path << ": NaN/Inf in color or AOVs";
    const float* c = r.session->color();
    for (int i = 0; i < r.w * r.h * 4; ++i) ASSERT_TRUE(std::isfinite(c[i])) << path << " pixel " << i / 4;
}

INSTANTIATE_TEST_SUITE_P(UsdWg, Corpus, ::testing::ValuesIn(corpusFiles()),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                             return testName(param.param);
                         });

// weird_matrix_transform.usda authors a projective matrix (last column (4, 8, 12, 1) in USD's
// row-vector layout). It used to abort in Embree (`ray.valid()`); the prim is now skipped with
// a warning naming it and the rest renders.
TEST(CorpusKnownCrash, WeirdMatrixTransformRenders) {
    const std::string path = corpus("test_assets/schemaTests/usdGeom/transforms/weird_matrix_transform.usda");
    Rendered r;
    ASSERT_NO_THROW(r = render(path)) << path;
    EXPECT_TRUE(r.allFinite());
}

TEST(CorpusLayout, CorpusIsPresentAndComplete) {
    auto files = corpusFiles(true);
    ASSERT_FALSE(files.empty()) << "corpus not found at " << kCorpus;
    EXPECT_GE(files.size(), 70u);
}

// ---------------------------------------------------------------------------------------------
// (b) Intentionally invalid files: a clear message naming file:line:col and what is wrong, and
// the rest of the stage (/World/cube) still renders.

namespace {
void expectMissingArcMessage(const std::string& rel, const std::string& arcWord, int line) {
    const std::string path = corpus(rel);
    Rendered r;
    ASSERT_NO_THROW(r = render(path, 64, 64, 1, {"primId"})) << path;
    const std::string w = r.allWarnings();
    const std::string file = fs::path(rel).filename().string();
    // "<file>:<line>:<col>: ... <arc> @file_does_not_exist.usda@ not found"
    EXPECT_TRUE(contains(w, file + ":" + std::to_string(line) + ":")) << w;
    EXPECT_TRUE(contains(w, "file_does_not_exist.usda")) << w;
    EXPECT_TRUE(contains(w, arcWord)) << w;
    EXPECT_TRUE(contains(w, "not found")) << w;
    EXPECT_GT(r.hits(), 0) << "the valid /World/cube must still render";
    EXPECT_TRUE(r.allFinite());
    Populated p(path);
    EXPECT_TRUE(p.has("/World/cube")) << "rprims: " << p.rprims().size();
}
}  // namespace

TEST(Invalid, SublayerInvalidNamesLocationAndRestRenders) {
    expectMissingArcMessage("test_assets/foundation/stage_composition/subLayer/sublayer_invalid.usda",
                            "sublayer", 8);
}
TEST(Invalid, ReferenceInvalidNamesLocationAndRestRenders) {
    expectMissingArcMessage("test_assets/foundation/stage_composition/references/reference_invalid.usda",
                            "reference", 14);
}
TEST(Invalid, PayloadInvalidNamesLocationAndRestRenders) {
    expectMissingArcMessage("test_assets/foundation/stage_composition/payload/payload_invalid.usda",
                            "payload", 14);
}

TEST(Invalid, EmptyMeshIsReportedByPrimPathAndRendersEmpty) {
    // README: "an empty mesh without any set attributes ... This screenshot is empty as expected."
    const std::string path = corpus("test_assets/schemaTests/usdGeom/meshes/empty_mesh/empty.usda");
    Rendered r;
    ASSERT_NO_THROW(r = render(path, 64, 64, 1, {"primId"}));
    const std::string w = r.allWarnings();
    EXPECT_TRUE(contains(w, "/mesh")) << w;
    EXPECT_TRUE(contains(w, "no points")) << w;
    EXPECT_EQ(r.hits(), 0);
    EXPECT_TRUE(r.allFinite());
}

// Extent README: an inverse extent [(1,1,1),(0,0,0)] and a zero extent [(0,0,0),(0,0,0)] on a
// cube whose points span [-0.5, 0.5]: "This screenshot is empty as expected" (usdrecord culls the
// mesh by its authored extent). Issue 5 asks for a clear message on such input.
// The adapter validates `extent` and warns ("extent min > max" / "points lie outside the
// authored extent"); the geometry itself still renders (it is not culled by extent).
TEST(Invalid, InverseExtentIsReported) {
    const std::string path = corpus("test_assets/schemaTests/usdGeom/extent/inverse_extent.usda");
    Rendered r;
    ASSERT_NO_THROW(r = render(path, 64, 64, 1, {"primId"}));
    const std::string w = r.allWarnings();
    EXPECT_TRUE(contains(w, "/mesh")) << w;
    EXPECT_TRUE(contains(w, "extent")) << w;
}
TEST(Invalid, ZeroExtentIsReported) {
    const std::string path = corpus("test_assets/schemaTests/usdGeom/extent/zero_extent.usda");
    Rendered r;
    ASSERT_NO_THROW(r = render(path, 64, 64, 1, {"primId"}));
    const std::string w = r.allWarnings();
    EXPECT_TRUE(contains(w, "/mesh")) << w;
    EXPECT_TRUE(contains(w, "extent")) << w;
}

// ---------------------------------------------------------------------------------------------
// (c) README expectations.

// --- Transforms: world matrices computed here from the authored ops, independently of
// scene_adapter/xformOps.cpp, against UsdSceneDelegate::getTransform.
namespace {

glm::dmat4 rotateAxis(double degrees, int axis) {
    glm::dvec3 a(0.0);
    a[axis] = 1.0;
    return glm::rotate(glm::dmat4(1.0), glm::radians(degrees), a);
}

// USD xformOp semantics (column vectors): local = op[0] * op[1] * ... ; rotateXYZ applies X
// first, so its matrix is Rz * Ry * Rx; matrix4d values are row-major row-vector matrices,
// whose flat storage equals glm's column-major storage of the column-vector matrix.
glm::dmat4 independentLocal(const usd::Prim& prim) {
    glm::dmat4 m(1.0);
    const usd::Attribute* order = prim.attribute("xformOpOrder");
    if (!order) return m;
    usd::Value ov = order->get();
    const std::vector<std::string>* ops = ov.strings();
    if (!ops) return m;
    for (std::string op : *ops) {
        bool invert = false;
        if (op.rfind("!invert!", 0) == 0) {
            invert = true;
            op = op.substr(8);
        }
        if (op == "!resetXformStack!") continue;
        const usd::Attribute* a = prim.attribute(op);
        if (!a) {
            ADD_FAILURE() << prim.path() << ": missing " << op;
            continue;
        }
        usd::Value v = a->get();
        std::vector<double> t = v.getTuple().value_or(std::vector<double>{});
        std::string kind = op.substr(8);  // after "xformOp:"
        kind = kind.substr(0, kind.find(':'));
        glm::dmat4 o(1.0);
        if (kind == "translate") {
            o = glm::translate(glm::dmat4(1.0), glm::dvec3(t.at(0), t.at(1), t.at(2)));
        } else if (kind == "scale") {
            o = glm::scale(glm::dmat4(1.0), glm::dvec3(t.at(0), t.at(1), t.at(2)));
        } else if (kind == "rotateX" || kind == "rotateY" || kind == "rotateZ") {
            o = rotateAxis(v.getDouble().value(), kind.back() - 'X');
        } else if (kind.rfind("rotate", 0) == 0 && kind.size() == 9) {
            // rotateABC: A first. Matrix = R_C * R_B * R_A.
            for (int k = 0; k < 3; ++k) o = rotateAxis(t.at(k), kind[6 + k] - 'X') * o;
        } else if (kind == "transform") {
            for (int c = 0; c < 4; ++c)
                for (int r = 0; r < 4; ++r) o[c][r] = t.at(4 * c + r);
        } else {
            ADD_FAILURE() << "test does not know op " << op;
        }
        m = m * (invert ? glm::inverse(o) : o);
    }
    return m;
}

glm::dmat4 independentWorld(const usd::Prim* prim) {
    glm::dmat4 m(1.0);
    std::vector<const usd::Prim*> chain;
    for (const usd::Prim* p = prim; p; p = p->parent()) chain.push_back(p);
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) m = m * independentLocal(**it);
    return m;
}

void expectMatrixNear(const glm::dmat4& a, const glm::dmat4& b, double tol, const std::string& what) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            EXPECT_NEAR(a[c][r], b[c][r], tol) << what << " [" << c << "][" << r << "]";
}

}  // namespace

class Transforms : public ::testing::TestWithParam<std::string> {};

TEST_P(Transforms, WorldMatrixFollowsAuthoredOpOrder) {
    Populated p(corpus("test_assets/schemaTests/usdGeom/transforms/" + GetParam()));
    auto ids = p.rprims();
    ASSERT_FALSE(ids.empty());
    for (const auto& id : ids) {
        const usd::Prim* prim = p.stage->prim(id);
        ASSERT_NE(prim, nullptr) << id;
        glm::dmat4 expected = independentWorld(prim);
        expectMatrixNear(p.scene->getTransform(hd::Path(id)), expected, 1e-5, GetParam() + " " + id);
    }
}

INSTANTIATE_TEST_SUITE_P(UsdWg, Transforms,
                         ::testing::Values("simple_transform.usda", "complex_transform.usda",
                                           "matrix_transform.usda", "weird_matrix_transform.usda",
                                           "xforms_nested.usda", "scopes_and_xforms_nested.usda"),
                         [](const ::testing::TestParamInfo<std::string>& param) {
                             return testName(param.param);
                         });

TEST(Readme, TransformsKnownValues) {
    // Hand-computed: nested translates add; simple_transform maps the origin to its translate
    // and (1,0,0) to translate + R(30,60,90) * (1,0,0).
    {
        Populated p(corpus("test_assets/schemaTests/usdGeom/transforms/xforms_nested.usda"));
        glm::dmat4 m = p.scene->getTransform(hd::Path("/World/A/B/C/Cube"));
        EXPECT_NEAR(m[3][0], 1.11, 1e-9);
        EXPECT_NEAR(m[3][1], 2.22, 1e-9);
        EXPECT_NEAR(m[3][2], 3.33, 1e-9);
    }
    {
        Populated p(corpus("test_assets/schemaTests/usdGeom/transforms/scopes_and_xforms_nested.usda"));
        glm::dmat4 m = p.scene->getTransform(hd::Path("/World/A/B/C/D"));
        EXPECT_NEAR(m[3][0], 4.0, 1e-9);
        EXPECT_NEAR(m[3][1], 5.0, 1e-9);
        EXPECT_NEAR(m[3][2], 6.0, 1e-9);
    }
    {
        Populated p(corpus("test_assets/schemaTests/usdGeom/transforms/simple_transform.usda"));
        glm::dmat4 m = p.scene->getTransform(hd::Path("/World/mesh"));
        // Rx(30) then Ry(60) then Rz(90), scale (1,2,3): x axis (1,0,0) -> Ry(60): (0.5, 0, -0.866)
        // -> Rz(90): (0, 0.5, -0.866).
        glm::dvec4 x = m * glm::dvec4(1, 0, 0, 1);
        EXPECT_NEAR(x.x, 4.0, 1e-6);
        EXPECT_NEAR(x.y, 5.5, 1e-6);
        EXPECT_NEAR(x.z, 6.0 - std::sqrt(3.0) / 2.0, 1e-6);
    }
}

// --- Primitive extents: tessellated bounds of Cube/Cylinder/Cone/Capsule and the rendered
// hits of the Sphere equal the analytic extents (all_primitives.usda authors them).
TEST(Readme, PrimitiveExtentsMatchAnalytic) {
    const std::string path = corpus("test_assets/schemaTests/usdGeom/primitives/all_primitives.usda");
    Populated p(path);
    struct Expect {
        const char* prim;
        glm::vec3 lo, hi;
    };
    // Local (untransformed) extents from the schema: Capsule axis Z, height 1, radius 0.5 ->
    // z in [-1, 1]; Cone/Cylinder height 2 radius 1; Cube size 2.
    const Expect shapes[] = {{"/World/Capsule", {-0.5f, -0.5f, -1.0f}, {0.5f, 0.5f, 1.0f}},
                             {"/World/Cone", {-1, -1, -1}, {1, 1, 1}},
                             {"/World/Cube", {-1, -1, -1}, {1, 1, 1}},
                             {"/World/Cylinder", {-1, -1, -1}, {1, 1, 1}}};
    for (const auto& s : shapes) {
        SCOPED_TRACE(s.prim);
        ASSERT_TRUE(p.has(s.prim));
        auto pts = p.points(s.prim);
        ASSERT_FALSE(pts.empty());
        glm::vec3 lo(1e30f), hi(-1e30f);
        for (auto q : pts) {
            lo = glm::min(lo, q);
            hi = glm::max(hi, q);
        }
        for (int k = 0; k < 3; ++k) {
            EXPECT_NEAR(lo[k], s.lo[k], 1e-4) << "axis " << k;
            EXPECT_NEAR(hi[k], s.hi[k], 1e-4) << "axis " << k;
        }
    }
    // Every primitive's world placement: translate (2i, 0, 0).
    const char* order[] = {"/World/Capsule", "/World/Cone", "/World/Cube", "/World/Cylinder", "/World/Sphere"};
    for (int i = 0; i < 5; ++i) {
        if (!p.has(order[i])) {
            ADD_FAILURE() << order[i] << " not populated";
            continue;
        }
        glm::dmat4 m = p.scene->getTransform(hd::Path(order[i]));
        EXPECT_NEAR(m[3][0], 2.0 * i, 1e-9) << order[i];
    }
    // The sphere: every rendered hit lies on |p - (8,0,0)| = 1 (within tessellation tolerance
    // if it is tessellated), and hits exist.
    Rendered r = render(corpus("test_assets/schemaTests/usdGeom/primitives/sphere.usda"), 64, 64, 1,
                        {"primId", "position"});
    int n = 0;
    double maxErr = 0.0;
    for (int y = 0; y < r.h; ++y)
        for (int x = 0; x < r.w; ++x) {
            if (!r.hit(x, y)) continue;
            glm::vec3 q = r.vec3("position", x, y);
            maxErr = std::max(maxErr, std::abs(double(glm::length(q)) - 1.0));
            ++n;
        }
    EXPECT_GT(n, 100);
    EXPECT_LT(maxErr, 0.01);
}

// --- Subdivision limit positions (meshes/subdiv_*: the cube with points at +-0.5).
namespace {
struct Hits {
    std::vector<glm::vec3> pos;
    float maxInf = 0.0f;  // max |p|_inf
};
Hits hitPositions(const Rendered& r) {
    Hits h;
    for (int y = 0; y < r.h; ++y)
        for (int x = 0; x < r.w; ++x)
            if (r.hit(x, y)) {
                glm::vec3 q = r.vec3("position", x, y);
                h.pos.push_back(q);
                h.maxInf = std::max({h.maxInf, std::abs(q.x), std::abs(q.y), std::abs(q.z)});
            }
    return h;
}
}  // namespace

TEST(Readme, SubdivCatmullClarkLimitPositions) {
    // Limit of Catmull-Clark on the cube [-0.5,0.5]^3 (hand-derived, see docs/conformance.md):
    //  - a corner (valence 3): (n^2 v + 4 sum e + sum f) / (n (n + 5)) = 0.25 * (+-1, +-1, +-1)
    //  - a face centre: after one step a regular vertex; its limit is 0.5 * 0.839506 = 0.419753
    //    (= 68/81 * 0.5) along the face normal.
    Rendered r = render(corpus("test_assets/schemaTests/usdGeom/meshes/subdiv_catmullClark/subdiv_catmullClark.usda"),
                        96, 96, 1, {"primId", "position"});
    Hits h = hitPositions(r);
    ASSERT_GT(h.pos.size(), 200u);
    const double faceLimit = 0.5 * 68.0 / 81.0;
    EXPECT_LT(h.maxInf, faceLimit + 0.01) << "surface reaches beyond the limit face centre";
    EXPECT_GT(h.maxInf, faceLimit - 0.02) << "no hit near a face centre's limit";
    // Hits along a corner diagonal sit at distance 0.25 * sqrt(3) from the centre.
    int nearCorner = 0;
    for (auto q : h.pos) {
        glm::vec3 d = glm::normalize(q);
        glm::vec3 diag = glm::normalize(glm::sign(q));
        if (glm::dot(d, diag) > std::cos(glm::radians(2.5f))) {
            ++nearCorner;
            EXPECT_NEAR(glm::length(q), 0.25 * std::sqrt(3.0), 0.01) << q.x << "," << q.y << "," << q.z;
        }
    }
    EXPECT_GT(nearCorner, 0) << "no pixel looked along a corner diagonal";
}

TEST(Readme, SubdivNoneAndBilinearKeepTheCube) {
    for (const char* f : {"subdiv_none/subdiv_none.usda", "subdiv_bilinear/subdiv_bilinear.usda"}) {
        SCOPED_TRACE(f);
        Rendered r = render(corpus(std::string("test_assets/schemaTests/usdGeom/meshes/") + f), 64, 64, 1,
                            {"primId", "position"});
        Hits h = hitPositions(r);
        ASSERT_GT(h.pos.size(), 100u);
        EXPECT_NEAR(h.maxInf, 0.5, 1e-3);
        // Every hit lies on the cube's surface: max coordinate 0.5.
        for (auto q : h.pos) {
            float m = std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)});
            ASSERT_NEAR(m, 0.5f, 1e-3f);
        }
    }
}

TEST(Readme, SubdivLoopShrinksTheCube) {
    // Loop is an approximating scheme: the limit surface lies strictly inside the control cube.
    for (const char* f : {"subdiv_loop_triangles/subdiv_loop_triangles.usda", "subdiv_loop_quads/subdiv_loop_quads.usda"}) {
        SCOPED_TRACE(f);
        Rendered r = render(corpus(std::string("test_assets/schemaTests/usdGeom/meshes/") + f), 64, 64, 1,
                            {"primId", "position"});
        Hits h = hitPositions(r);
        ASSERT_GT(h.pos.size(), 100u);
        EXPECT_LT(h.maxInf, 0.48f);
        EXPECT_GT(h.maxInf, 0.25f);
    }
}

// --- Crease sharpness (full_assets/SubdivisionSurfaces): at time 1 (no spin) the three
// pyramids stand at x = -2 (NoCreases), 0 (EdgeCreases), 2 (CornerCreases); the apex is control
// vertex 0 at y = 1.3333. Sharp corners (cornerSharpnesses 25) and fully creased edges
// (creaseSharpnesses 100) keep the apex on the control point; the smooth one pulls it down.
TEST(Readme, CreasedPyramidsKeepTheirApex) {
    Rendered r = render(corpus("full_assets/SubdivisionSurfaces/Creases_SpinningPyramids.usda"), 256, 110,
                        1, {"primId", "position"}, 1.0, "/World/Camera");
    float apex[3] = {-1e9f, -1e9f, -1e9f};
    int n[3] = {0, 0, 0};
    for (int y = 0; y < r.h; ++y)
        for (int x = 0; x < r.w; ++x) {
            if (!r.hit(x, y)) continue;
            glm::vec3 q = r.vec3("position", x, y);
            int k = q.x < -1.0f ? 0 : (q.x < 1.0f ? 1 : 2);
            apex[k] = std::max(apex[k], q.y);
            ++n[k];
        }
    for (int k = 0; k < 3; ++k) ASSERT_GT(n[k], 50) << "pyramid " << k << " not visible";
    const float control = 1.3333297f;
    // Pixel footprint at z = -52 with this camera: about 0.025 units; allow two pixels.
    EXPECT_GT(apex[2], control - 0.06f) << "CornerCreases apex rounded off";
    EXPECT_GT(apex[1], control - 0.06f) << "EdgeCreases apex rounded off";
    EXPECT_LT(apex[0], control - 0.1f) << "NoCreases apex should be smoothed";
    EXPECT_LT(apex[0], apex[1] - 0.05f);
    std::cout << "apex y: none " << apex[0] << " edges " << apex[1] << " corners " << apex[2] << "\n";
}

// --- Texture orientation (TextureCoordinateTest): each quadrant mesh maps its corners to the
// matching quarter of st space ("TopLeft" mesh: s in [0,0.4], t in [0.6,1]), so the 'Top Left'
// label of the texture lands top left. Checked two ways: (1) the st0 primvar AOV at the pixels of
// each mesh lies in that mesh's range and the TopLeft mesh is in the image's top-left quarter;
// (2) the rendered luminance over the TopLeft and BottomRight meshes correlates with the texture
// sampled with t up (row = (1 - t) * height) and not with the vertically flipped lookup.
namespace {
struct Texture {
    int w = 0, h = 0, c = 0;
    std::vector<float> px;
    float lum(float s, float t, bool flip) const {
        s = s - std::floor(s);
        t = t - std::floor(t);
        int x = std::clamp(int(s * w), 0, w - 1);
        int y = std::clamp(int((flip ? t : 1.0f - t) * h), 0, h - 1);
        // 5x5 texel box (the pixel footprint is a few texels wide).
        float sum = 0.0f;
        int cnt = 0;
        for (int dy = -2; dy <= 2; ++dy)
            for (int dx = -2; dx <= 2; ++dx) {
                int xx = std::clamp(x + dx, 0, w - 1), yy = std::clamp(y + dy, 0, h - 1);
                const float* p = &px[(size_t(yy) * w + xx) * c];
                sum += (p[0] + p[1] + p[2]) / 3.0f;
                ++cnt;
            }
        return sum / cnt;
    }
};
double correlation(const std::vector<double>& a, const std::vector<double>& b) {
    double ma = 0, mb = 0;
    for (size_t i = 0; i < a.size(); ++i) ma += a[i], mb += b[i];
    ma /= a.size();
    mb /= b.size();
    double sab = 0, saa = 0, sbb = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        sab += (a[i] - ma) * (b[i] - mb);
        saa += (a[i] - ma) * (a[i] - ma);
        sbb += (b[i] - mb) * (b[i] - mb);
    }
    return sab / std::sqrt(saa * sbb + 1e-30);
}
}  // namespace

TEST(Readme, TextureCoordinateOrientation) {
    const std::string dir = corpus("test_assets/TextureCoordinateTest/");
    Texture tex;
    {
        auto in = OIIO::ImageInput::open(dir + "TextureCoordinateTemplate.png");
        ASSERT_TRUE(in);
        const auto& spec = in->spec();
        tex.w = spec.width;
        tex.h = spec.height;
        tex.c = spec.nchannels;
        tex.px.resize(size_t(tex.w) * tex.h * tex.c);
        ASSERT_TRUE(in->read_image(0, 0, 0, tex.c, OIIO::TypeDesc::FLOAT, tex.px.data()));
    }
    Rendered r = render(dir + "TextureCoordinateTest.usda", 160, 160, 8, {"primId", "position", "primvars:st0"});
    struct Quadrant {
        const char* name;
        float s0, s1, t0, t1;
        bool left, top;
    };
    const Quadrant quads[] = {{"TopLeft", 0.0f, 0.4f, 0.6f, 1.0f, true, true},
                              {"TopRight", 0.6f, 1.0f, 0.6f, 1.0f, false, true},
                              {"BottomLeft", 0.0f, 0.4f, 0.0f, 0.4f, true, false},
                              {"BottomRight", 0.6f, 1.0f, 0.0f, 0.4f, false, false}};
    for (const auto& q : quads) {
        SCOPED_TRACE(q.name);
        int n = 0, wrongSide = 0;
        std::vector<double> rendered, upright, flipped;
        for (int y = 0; y < r.h; ++y)
            for (int x = 0; x < r.w; ++x) {
                if (!r.hit(x, y)) continue;
                glm::vec3 p = r.vec3("position", x, y);
                if (std::abs(p.z) > 0.01f) continue;  // the back plane is at z = -0.0526
                glm::vec3 st = r.vec3("primvars:st0", x, y);
                // The mesh by its world position (README geometry: quadrants of [-1.2, 1.2]^2).
                bool left = p.x < 0.0f, top = p.y > 0.0f;
                if (left != q.left || top != q.top) continue;
                // Interior only (no edge pixels mixing with the back plane).
                if (std::abs(std::abs(p.x) - 0.7f) > 0.4f || std::abs(std::abs(p.y) - 0.7f) > 0.4f) continue;
                ++n;
                EXPECT_GE(st.x, q.s0 - 0.01f);
                EXPECT_LE(st.x, q.s1 + 0.01f);
                EXPECT_GE(st.y, q.t0 - 0.01f);
                EXPECT_LE(st.y, q.t1 + 0.01f);
                // st follows the position: s grows with x, t grows with y.
                EXPECT_NEAR(st.x, q.s0 + (std::abs(p.x) - 0.2f) * (q.left ? -1.0f : 1.0f) * 0.4f +
                                      (q.left ? 0.4f : 0.0f),
                            0.02f);
                EXPECT_NEAR(st.y, q.t0 + (std::abs(p.y) - 0.2f) * (q.top ? 1.0f : -1.0f) * 0.4f +
                                      (q.top ? 0.0f : 0.4f),
                            0.02f);
                wrongSide += (x < r.w / 2) != q.left || (y < r.h / 2) != q.top;
                const float* c = r.color(x, y);
                rendered.push_back((c[0] + c[1] + c[2]) / 3.0);
                upright.push_back(tex.lum(st.x, st.y, false));
                flipped.push_back(tex.lum(st.x, st.y, true));
            }
        ASSERT_GT(n, 300) << "mesh not found in the image";
        EXPECT_EQ(wrongSide, 0) << "the " << q.name << " mesh is not in the image's " << q.name << " quarter";
        double cu = correlation(rendered, upright), cf = correlation(rendered, flipped);
        std::cout << q.name << ": correlation upright " << cu << ", flipped " << cf << " over " << n << " px\n";
        EXPECT_GT(cu, 0.5) << "rendered texture does not follow the texture read with t up";
        // The template is mostly white with symmetric corner checkers; only the labels differ
        // between the two lookups, hence the modest margin (measured: 0.18-0.25).
        EXPECT_GT(cu, cf + 0.1);
    }
}

// --- Many textured sessions in one process (what a host such as a DCC plug-in does).
// Fixed by one process-wide TextureSystem; it was: SIGSEGV in OpenImageIO ImageCacheTile::~ImageCacheTile, called
// from TextureSystem::texture in shading::TextureCache::lookupFile (textureCache.cpp:253,
// get_perthread_info()) once several RenderSessions, each creating and destroying its private
// TextureSystem, have rendered textures on the same TBB worker threads. ctest runs every test
// in its own process, so only this test (and running the binary directly) shows it.
TEST(TextureSessions, ManyTexturedSessionsInOneProcess) {
    const std::string dir = corpus("test_assets/TextureFileFormatTests/");
    for (int round = 0; round < 3; ++round)
        for (const char* f : {"jpeg_rgb_8-bit.usda", "jpeg_cmyk_8-bit.usda", "jpeg_grayscale_8-bit.usda",
                              "png_rgb_8-bit.usda", "png_rgb_16-bit.usda", "png_rgb_32-bit.usda",
                              "png_grayscale_8-bit.usda", "png_grayscale_16-bit.usda", "all_files.usda"}) {
            Rendered r = render(dir + f, 64, 64, 2, {"primId"});
            EXPECT_TRUE(r.allFinite()) << f;
        }
}

// --- singleSided vs doubleSided: the authored doubleSided reaches the delegate.
TEST(Readme, SingleAndDoubleSided) {
    for (auto [file, expected] : {std::pair{"singleSided/singleSided.usda", false},
                                  std::pair{"doubleSided/doubleSided_quad.usda", true}}) {
        SCOPED_TRACE(file);
        Populated p(corpus(std::string("test_assets/schemaTests/usdGeom/meshes/") + file));
        auto ids = p.rprims();
        ASSERT_FALSE(ids.empty());
        for (const auto& id : ids) EXPECT_EQ(p.scene->getDoubleSided(hd::Path(id)), expected) << id;
    }
}

// Camera rays skip the back of doubleSided = 0 meshes, as Storm/usdrecord cull them.
TEST(Readme, SingleSidedBackFacesAreNotDrawnWithBackfaceCulling) {
    // singleSided.usda: Plane_0 (x < 0) winds counter-clockwise seen from +z, Plane_1 (x > 0)
    // clockwise, both doubleSided = 0. Seen from the front (+z, the default camera), Plane_1 shows
    // its back: with backfaceCulling = 1 it is not drawn (usdrecord: one plane); by default both
    // sides are drawn, as Cycles and Karma do (the schema leaves culling to the renderer).
    const std::string file = corpus("test_assets/schemaTests/usdGeom/meshes/singleSided/singleSided.usda");
    for (const bool cull : {true, false}) {
        Rendered single = render(file, 64, 64, 1, {"primId", "position"}, NAN, "",
                                 cull ? std::map<std::string, std::string>{{"backfaceCulling", "1"}}
                                      : std::map<std::string, std::string>{});
        int left = 0, right = 0;
        for (int y = 0; y < single.h; ++y)
            for (int x = 0; x < single.w; ++x)
                if (single.hit(x, y)) (single.vec3("position", x, y).x < 0.0f ? left : right)++;
        EXPECT_GT(left, 200) << "front-facing Plane_0 missing";
        if (cull) EXPECT_EQ(right, 0) << "back-facing single-sided Plane_1 was drawn";
        else EXPECT_GT(right, 200) << "back-facing Plane_1 culled without backfaceCulling";
    }
}

TEST(Readme, DoubleSidedBothPlanesDrawn) {
    Rendered r = render(corpus("test_assets/schemaTests/usdGeom/meshes/doubleSided/doubleSided_quad.usda"), 64, 64, 1,
                        {"primId", "position"});
    int left = 0, right = 0;
    for (int y = 0; y < r.h; ++y)
        for (int x = 0; x < r.w; ++x)
            if (r.hit(x, y)) (r.vec3("position", x, y).x < 0.0f ? left : right)++;
    EXPECT_GT(left, 200);
    EXPECT_GT(right, 200);
}

// --- normals_types / points_types: every Mesh prim loads; points of a 3-component array type
// keep their count, normals of a 3-component array type keep theirs.
namespace {
size_t authoredCount(const usd::Prim& prim, const char* attr, int* components) {
    const usd::Attribute* a = prim.attribute(attr);
    *components = 0;
    if (!a) return 0;
    usd::Value v = a->get();
    if (!v.isArray() || !v.numbers()) return 0;
    *components = v.components();
    return v.size();
}
}  // namespace

TEST(Readme, NormalsAndPointsTypesLoadWithRightCounts) {
    for (const char* file : {"normals_types/normalsTypes.usda", "points_types/pointsTypes.usda"}) {
        SCOPED_TRACE(file);
        Populated p(corpus(std::string("test_assets/schemaTests/usdGeom/meshes/") + file));
        // The whole file renders; the render delegate reports meshes it cannot draw.
        Rendered r;
        ASSERT_NO_THROW(r = render(corpus(std::string("test_assets/schemaTests/usdGeom/meshes/") + file), 48, 48, 1,
                                   {"primId"}));
        EXPECT_GT(r.hits(), 0);
        const std::string w = p.warnings() + r.allWarnings();
        int meshes = 0;
        for (const usd::Prim* prim : p.stage->traverse()) {
            if (prim->typeName() != "Mesh") continue;
            ++meshes;
            SCOPED_TRACE(prim->path());
            int pc = 0, nc = 0;
            size_t np = authoredCount(*prim, "points", &pc);
            size_t nn = authoredCount(*prim, "normals", &nc);
            if (pc == 3 && np > 0) {
                ASSERT_TRUE(p.has(prim->path())) << p.warnings();
                EXPECT_EQ(p.points(prim->path()).size(), np);
                hd::MeshTopology t = p.scene->getMeshTopology(hd::Path(prim->path()));
                const usd::Attribute* fvc = prim->attribute("faceVertexCounts");
                ASSERT_NE(fvc, nullptr);
                EXPECT_EQ(t.faceVertexCounts.size(), fvc->get().size());
                if (nc == 3) {
                    hd::Value nv = p.scene->get(hd::Path(prim->path()), hd::tokens::normals());
                    auto* n = hd::getIf<std::vector<glm::vec3>>(nv);
                    ASSERT_NE(n, nullptr) << "normals of a 3-component type not served";
                    EXPECT_EQ(n->size(), nn);
                }
            } else {
                // Points of a type that is not a 3-vector array: the mesh draws nothing and a
                // warning names it (not a crash).
                EXPECT_TRUE(p.points(prim->path()).empty());
                EXPECT_TRUE(contains(w, prim->path() + ":") || contains(w, prim->path() + " ")) << w;
            }
        }
        EXPECT_GE(meshes, 5);
    }
}

// --- Composition.
TEST(Readme, CompositionArcsInEveryFolderGiveOneCube) {
    // README (references/payload/subLayer): "If loaded successfully, a single cube is visible."
    for (const char* f : {"subLayer/sublayer_same_folder.usda", "subLayer/sublayer_child_folder.usda",
                          "subLayer/sublayer_parent_folder.usda", "references/reference_same_folder.usda",
                          "references/reference_child_folder.usda", "references/reference_parent_folder.usda",
                          "payload/payload_same_folder.usda", "payload/payload_child_folder.usda",
                          "payload/payload_parent_folder.usda"}) {
        SCOPED_TRACE(f);
        Populated p(corpus(std::string("test_assets/foundation/stage_composition/") + f));
        EXPECT_EQ(p.rprims(), (std::set<std::string>{"/World/Cube"})) << p.warnings();
        EXPECT_EQ(p.stage->warnings().size(), 0u) << p.warnings();
    }
}

TEST(Readme, ActiveOverClassInheritPurpose) {
    const std::string dir = corpus("test_assets/foundation/stage_composition/");
    {
        // "One inactive (active = false), red cube and one active (active = true), green cube."
        Populated p(dir + "active.usda");
        EXPECT_EQ(p.rprims(), (std::set<std::string>{"/World/CubeActive"}));
        EXPECT_EQ(p.displayColor("/World/CubeActive"), glm::vec3(0, 0.8f, 0));
    }
    {
        // over.usda: the over recolours the parent stage's /World/Cube blue; definedCube is a
        // def; undefinedCube has only an `over` and is not defined, so not drawn.
        Populated p(dir + "over.usda");
        EXPECT_TRUE(p.has("/World/Cube"));
        EXPECT_TRUE(p.has("/World/definedCube"));
        EXPECT_FALSE(p.has("/World/undefinedCube"));
        EXPECT_EQ(p.displayColor("/World/Cube"), glm::vec3(0, 0, 0.8f));
    }
    {
        // class_inherit: the class is abstract (not drawn); the inheriting cube without its own
        // colour takes the class's green, the one with its own colour stays red.
        Populated p(dir + "class_inherit.usda");
        EXPECT_EQ(p.rprims(), (std::set<std::string>{"/World/cubeWithoutSetColor", "/World/cubeWithSetColor"}));
        EXPECT_EQ(p.displayColor("/World/cubeWithoutSetColor"), glm::vec3(0, 0.8f, 0));
        EXPECT_EQ(p.displayColor("/World/cubeWithSetColor"), glm::vec3(0.8f, 0, 0));
    }
    {
        // inherit_and_specialize: in the referenced copy, the local override of `source` (green)
        // reaches `inherits` (inherit arcs are stronger than the reference) but not `specializes`
        // (specializes is weakest, so its own yellow wins).
        Populated p(dir + "inherit_and_specialize.usda");
        const glm::vec3 red(0.8f, 0, 0), yellow(0.8f, 0.8f, 0), green(0, 0.8f, 0);
        EXPECT_EQ(p.displayColor("/World/cubeScene/source"), red);
        EXPECT_EQ(p.displayColor("/World/cubeScene/specializes"), yellow);
        EXPECT_EQ(p.displayColor("/World/cubeScene/inherits"), yellow);
        EXPECT_EQ(p.displayColor("/World/cubeSceneReferenced/source"), green);
        EXPECT_EQ(p.displayColor("/World/cubeSceneReferenced/specializes"), yellow);
        EXPECT_EQ(p.displayColor("/World/cubeSceneReferenced/inherits"), green);
        glm::dmat4 m = p.scene->getTransform(hd::Path("/World/cubeSceneReferenced/inherits"));
        EXPECT_NEAR(m[3][0], 6.0, 1e-9);
        EXPECT_NEAR(m[3][1], 3.0, 1e-9);
    }
    {
        // purpose: a final render draws default and "render" purpose, never "guide" (nor
        // "proxy", which stands in for render geometry in viewports).
        Populated p(dir + "purpose.usda");
        auto ids = p.rprims();
        std::string all;
        for (const auto& s : ids) all += s + " ";
        EXPECT_TRUE(contains(all, "CubeIsRender")) << all;
        EXPECT_FALSE(contains(all, "CubeIsGuide")) << all;
        EXPECT_FALSE(contains(all, "CubeIsProxy")) << all;
    }
}

TEST(Readme, ReferencesToPrims) {
    const std::string dir = corpus("test_assets/foundation/stage_composition/references_prim/");
    {
        // Cube_with_reference references an existing mesh; the two others reference a missing
        // prim in a valid file and a missing file: each of those is a clear diagnostic naming
        // the layer location, and only the valid one is drawn.
        Populated p(dir + "reference_prim_in_other_file.usda");
        EXPECT_EQ(p.rprims(), (std::set<std::string>{"/World/Cube_with_reference"})) << p.warnings();
        const std::string w = p.warnings();
        EXPECT_TRUE(contains(w, "reference_prim_in_other_file.usda:20:")) << w;
        EXPECT_TRUE(contains(w, "Cube_does_not_exist")) << w;
        EXPECT_TRUE(contains(w, "reference_prim_in_other_file.usda:29:")) << w;
        EXPECT_TRUE(contains(w, "file_does_not_exist.usda")) << w;
    }
    {
        // Same file: </World/cube> (lower case) and </World/cube_does_not_exist> do not exist
        // (paths are case-sensitive), so only /World/Cube is drawn and both arcs are reported.
        Populated p(dir + "reference_prim_in_same_file.usda");
        EXPECT_EQ(p.rprims(), (std::set<std::string>{"/World/Cube"})) << p.warnings();
        const std::string w = p.warnings();
        EXPECT_TRUE(contains(w, "/World/cube_does_not_exist")) << w;
        EXPECT_TRUE(contains(w, "/World/cube>") || contains(w, "/World/cube ") || contains(w, "/World/cube\n")) << w;
    }
}
