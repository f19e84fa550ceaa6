// IesProfile (delegate/iesProfile.h): LM-63 type C files parsed into the table they state,
// evaluated with bilinear interpolation and the standard's horizontal symmetries, with their mean
// over the sphere, and malformed or unsupported files refused with the line that is wrong.
#include <gtest/gtest.h>

#include <string>

#include "delegate/iesProfile.h"

using namespace principled::embree;

namespace {

// A type C file: header, TILT=NONE, the counts line, the ballast line, then the given angles and
// values (as text, so tests can wrap them over lines).
std::string ies(int nv, int nh, const std::string& body, const std::string& tilt = "TILT=NONE", int type = 1) {
    return "IESNA:LM-63-2002\n[TEST] unit test\n[MANUFAC] none\n" + tilt + "\n1 1000 1.0 " + std::to_string(nv) +
           " " + std::to_string(nh) + " " + std::to_string(type) + " 2 0 0 0\n1.0 1.0 10\n" + body + "\n";
}

std::shared_ptr<const IesProfile> parse(const std::string& text, std::string* error = nullptr) {
    std::string e;
    auto p = parseIes(text, "t.ies", &e);
    if (error) *error = e;
    return p;
}

}  // namespace

TEST(IesProfile, AxialProfileIsInterpolatedAlongTheVerticalAngle) {
    auto p = parse(ies(4, 1, "0 45 90 180\n0\n100 50 0 0"));
    ASSERT_TRUE(p);
    EXPECT_FLOAT_EQ(p->maxCandela, 100.0f);
    EXPECT_FLOAT_EQ(p->evaluate(0.0f, 0.0f), 100.0f);
    EXPECT_FLOAT_EQ(p->evaluate(22.5f, 0.0f), 75.0f);
    EXPECT_FLOAT_EQ(p->evaluate(22.5f, 137.0f), 75.0f);  // one plane: the same at every azimuth
    EXPECT_FLOAT_EQ(p->evaluate(120.0f, 0.0f), 0.0f);
    // Mean over the sphere: (1/2) integral of I sin(theta) with I = 100 (1 - 2 theta / pi) on
    // [0, pi/2] and 0 beyond: 50 (1 - 2 / pi) = 18.17.
    EXPECT_NEAR(p->meanCandela, 100.0 / 2.0 * (1.0 - 2.0 / 3.14159265358979), 0.05);
}

TEST(IesProfile, HorizontalSymmetriesFoldTheAzimuth) {
    // Quadrant symmetry (0-90): 180 - phi and 360 - phi read as phi.
    auto q = parse(ies(2, 2, "0 90\n0 90\n100 0\n20 0"));
    ASSERT_TRUE(q);
    EXPECT_FLOAT_EQ(q->evaluate(0.0f, 0.0f), 100.0f);
    EXPECT_FLOAT_EQ(q->evaluate(0.0f, 45.0f), 60.0f);
    EXPECT_FLOAT_EQ(q->evaluate(0.0f, 135.0f), 60.0f);
    EXPECT_FLOAT_EQ(q->evaluate(0.0f, 180.0f), 100.0f);
    EXPECT_FLOAT_EQ(q->evaluate(0.0f, 270.0f), 20.0f);
    EXPECT_FLOAT_EQ(q->evaluate(0.0f, -90.0f), 20.0f);
    // Mirror about the 0-180 plane: 360 - phi reads as phi.
    auto m = parse(ies(2, 3, "0 90\n0 90 180\n100 0\n20 0\n60 0"));
    ASSERT_TRUE(m);
    EXPECT_FLOAT_EQ(m->evaluate(0.0f, 270.0f), 20.0f);
    EXPECT_FLOAT_EQ(m->evaluate(0.0f, 315.0f), 60.0f);
    EXPECT_FLOAT_EQ(m->evaluate(0.0f, 180.0f), 60.0f);
    // Mirror about the 90-270 plane: 180 - phi reads as phi.
    auto b = parse(ies(2, 3, "0 90\n90 180 270\n20 0\n60 0\n40 0"));
    ASSERT_TRUE(b);
    EXPECT_FLOAT_EQ(b->evaluate(0.0f, 0.0f), 60.0f);
    EXPECT_FLOAT_EQ(b->evaluate(0.0f, 45.0f), 40.0f);   // as 135
    EXPECT_NEAR(b->evaluate(0.0f, 300.0f), 60.0f - 20.0f * 60.0f / 90.0f, 1e-4f);  // as 240
    // No symmetry (0-360).
    auto f = parse(ies(2, 5, "0 90\n0 90 180 270 360\n10 0\n20 0\n30 0\n40 0\n10 0"));
    ASSERT_TRUE(f);
    EXPECT_FLOAT_EQ(f->evaluate(0.0f, 225.0f), 35.0f);
    EXPECT_FLOAT_EQ(f->evaluate(0.0f, 315.0f), 25.0f);
}

TEST(IesProfile, TiltDataAndWrappedNumbersAreRead) {
    // TILT=INCLUDE: geometry 1, 3 angles and 3 multipliers, skipped; numbers wrap over lines and
    // may be comma separated; the candela multiplier scales the table.
    const std::string text =
        "IESNA91\nTILT=INCLUDE\n1\n3\n0 45 90\n1.0 0.9\n0.8\n1 1000 2.0 2 1 1 2 0 0 0\n1 1 10\n0,\n90\n0\n50,\n25\n";
    auto p = parse(text);
    ASSERT_TRUE(p);
    EXPECT_FLOAT_EQ(p->evaluate(0.0f, 0.0f), 100.0f);
    EXPECT_FLOAT_EQ(p->evaluate(90.0f, 0.0f), 50.0f);
    // An isotropic profile's mean is its value.
    auto iso = parse(ies(2, 1, "0 180\n0\n40 40"));
    ASSERT_TRUE(iso);
    EXPECT_NEAR(iso->meanCandela, 40.0f, 0.01f);
}

TEST(IesProfile, MalformedAndUnsupportedFilesAreRefusedWithTheirLine) {
    std::string error;
    EXPECT_FALSE(parse("just text\n", &error));
    EXPECT_NE(error.find("t.ies:"), std::string::npos);
    EXPECT_NE(error.find("TILT"), std::string::npos);
    EXPECT_FALSE(parse(ies(4, 1, "0 45 90 180\n0\n100 50"), &error));  // two values short
    EXPECT_NE(error.find("fewer than the 9 its angle counts need"), std::string::npos) << error;
    EXPECT_FALSE(parse(ies(2, 1, "0 90\n0\n100 x"), &error));
    EXPECT_NE(error.find("t.ies:9: expected a candela value, found 'x'"), std::string::npos) << error;
    EXPECT_FALSE(parse(ies(2, 1, "0 90\n0\n100 0", "TILT=NONE", 3), &error));
    EXPECT_NE(error.find("photometric type A is not supported"), std::string::npos) << error;
    EXPECT_FALSE(parse(ies(3, 1, "0 90 45\n0\n1 1 1"), &error));
    EXPECT_NE(error.find("must not decrease"), std::string::npos) << error;
    EXPECT_FALSE(parse(ies(2, 1, "0 90\n0\n0 0"), &error));
    EXPECT_NE(error.find("emits nothing"), std::string::npos) << error;
    EXPECT_FALSE(parse(ies(2, 1, "0 200\n0\n1 1"), &error));
    EXPECT_NE(error.find("[0, 180]"), std::string::npos) << error;
    // Counts the file cannot back are refused before anything is sized by them.
    EXPECT_FALSE(parse(ies(10000, 10000, "0 90\n0\n1 1"), &error));
    EXPECT_NE(error.find("fewer than the 100020000"), std::string::npos) << error;
    // Vertical angles within the first half degree: no power over the sphere to normalize by.
    EXPECT_FALSE(parse(ies(2, 1, "0 0.2\n0\n100 100"), &error));
    EXPECT_NE(error.find("emits nothing over the sphere"), std::string::npos) << error;
    EXPECT_FALSE(loadIes("/nonexistent/x.ies", &error));
    EXPECT_NE(error.find("cannot open"), std::string::npos) << error;
}
