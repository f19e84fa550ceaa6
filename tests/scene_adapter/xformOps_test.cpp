#include "scene_adapter/xformOps.h"

#include <gtest/gtest.h>

#include "scene_adapter/usda/stage.h"

using namespace principled;

namespace {

glm::dvec3 apply(const glm::dmat4& m, glm::dvec3 p) { return glm::dvec3(m * glm::dvec4(p, 1.0)); }

adapter::LocalTransform eval(const std::string& body, std::string* warning = nullptr) {
    static std::vector<std::unique_ptr<usd::Stage>> keep;
    keep.push_back(usd::Stage::openString("#usda 1.0\ndef Xform \"X\"\n{\n" + body + "\n}\n", "x.usda"));
    std::string w;
    auto t = adapter::computeLocalTransform(*keep.back()->prim("/X"), NAN, &w);
    if (warning) *warning = w;
    return t;
}

void expectNear(glm::dvec3 a, glm::dvec3 b) {
    EXPECT_NEAR(a.x, b.x, 1e-9);
    EXPECT_NEAR(a.y, b.y, 1e-9);
    EXPECT_NEAR(a.z, b.z, 1e-9);
}

}  // namespace

TEST(XformOps, LaterOpsAreMoreLocal) {
    // translate then scale: the point is scaled first, then translated.
    auto t = eval(R"(double3 xformOp:translate = (1, 2, 3)
        double3 xformOp:scale = (2, 2, 2)
        uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:scale"])");
    expectNear(apply(t.matrix, {1, 0, 0}), {3, 2, 3});
}

TEST(XformOps, RotateXYZAppliesXFirst) {
    // rotateXYZ = (90, 90, 0): X first takes +Y to +Z, then Y takes +Z to +X.
    auto t = eval(R"(float3 xformOp:rotateXYZ = (90, 90, 0)
        uniform token[] xformOpOrder = ["xformOp:rotateXYZ"])");
    expectNear(apply(t.matrix, {0, 1, 0}), {1, 0, 0});
    // rotateZYX with the same angles applies Z (0) then Y then X: +Y -> +Y (Y rot) -> +Z (X rot).
    auto z = eval(R"(float3 xformOp:rotateZYX = (90, 90, 0)
        uniform token[] xformOpOrder = ["xformOp:rotateZYX"])");
    expectNear(apply(z.matrix, {0, 1, 0}), {0, 0, 1});
}

TEST(XformOps, MatrixIsRowVectorWithTranslationInTheLastRow) {
    auto t = eval(R"(matrix4d xformOp:transform = ( (0, 1, 0, 0), (-1, 0, 0, 0), (0, 0, 1, 0), (5, 6, 7, 1) )
        uniform token[] xformOpOrder = ["xformOp:transform"])");
    // Row-vector: p' = p * M; (1,0,0) -> first row (0,1,0) + translation.
    expectNear(apply(t.matrix, {1, 0, 0}), {5, 7, 7});
}

TEST(XformOps, InvertPivotAndResetXformStack) {
    auto t = eval(R"(double3 xformOp:translate:pivot = (1, 0, 0)
        float xformOp:rotateZ = 90
        uniform token[] xformOpOrder = ["!resetXformStack!", "xformOp:translate:pivot", "xformOp:rotateZ", "!invert!xformOp:translate:pivot"])");
    EXPECT_TRUE(t.resetsXformStack);
    // Rotation by 90 degrees about the pivot (1,0,0): (2,0,0) -> (1,1,0).
    expectNear(apply(t.matrix, {2, 0, 0}), {1, 1, 0});
}

TEST(XformOps, OrientQuaternionIsRealFirst) {
    double s = std::sqrt(0.5);
    char body[256];
    std::snprintf(body, sizeof body,
                  "quatf xformOp:orient = (%.9f, 0, 0, %.9f)\n uniform token[] xformOpOrder = [\"xformOp:orient\"]",
                  s, s);
    auto t = eval(body);
    expectNear(apply(t.matrix, {1, 0, 0}), {0, 1, 0});  // 90 degrees about Z
}

TEST(XformOps, MissingOpIsReportedAndSkipped) {
    std::string w;
    auto t = eval(R"(uniform token[] xformOpOrder = ["xformOp:translate"])", &w);
    EXPECT_NE(w.find("xformOp:translate"), std::string::npos);
    expectNear(apply(t.matrix, {1, 2, 3}), {1, 2, 3});
}

TEST(XformOps, AnOpBlockedByNoneIsSkippedAndSaysSo) {
    std::string w;
    auto t = eval(R"(double3 xformOp:translate = None
        double3 xformOp:scale = (2, 2, 2)
        uniform token[] xformOpOrder = ["xformOp:translate", "xformOp:scale"])",
                  &w);
    expectNear(apply(t.matrix, {1, 0, 0}), {2, 0, 0});
    EXPECT_NE(w.find("names 'xformOp:translate', which has no value"), std::string::npos) << w;  // a default None
}

TEST(XformOps, AnOpBlockedAtTheTimeByASampledNoneSaysSo) {
    static auto stage = usd::Stage::openString(R"(#usda 1.0
def Xform "X" {
    double3 xformOp:translate.timeSamples = { 0: (1, 0, 0), 10: None }
    uniform token[] xformOpOrder = ["xformOp:translate"]
}
)",
                                               "t.usda");
    std::string w;
    auto t = adapter::computeLocalTransform(*stage->prim("/X"), 12.0, &w);
    expectNear(apply(t.matrix, {0, 0, 0}), {0, 0, 0});
    EXPECT_NE(w.find("is blocked (None) at this time"), std::string::npos) << w;
}
