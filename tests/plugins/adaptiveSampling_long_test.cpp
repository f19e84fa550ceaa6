// Adaptive sampling keeps the image's mean (long label: a few seconds per render).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "plugins/renderSession.h"

using namespace principled;

namespace {

double meanOf(const std::string& usda, int spp, float threshold, int seed) {
    host::SessionOptions o;
    o.width = o.height = 48;
    o.samplesPerPixel = spp;
    o.noiseThreshold = threshold;
    o.seed = seed;
    o.settings = {{"defaultLighting", "0"}};
    auto s = host::RenderSession::openString(usda, "cornell.usda", o);
    while (!s->step()) {
    }
    double sum = 0.0;
    const float* c = s->color();
    for (int i = 0; i < o.width * o.height; ++i) sum += (c[4 * i] + c[4 * i + 1] + c[4 * i + 2]) / 3.0;
    return sum / (o.width * o.height);
}

}  // namespace

TEST(AdaptiveSampling, KeepsTheImageMeanOnTheCornellBox) {
    // Judged on a pixel's own samples alone, pixels that had not drawn their rare bright paths
    // stopped early and low: at threshold 0.1 the Cornell box came out 1.3 % dark over four seeds.
    // Judged over the 3x3 neighbourhood it is within 0.6 % (measured -0.4 %).
    std::ifstream in(std::string(PRINCIPLED_SOURCE_DIR) + "/scenes/cornell.usda");
    ASSERT_TRUE(in);
    std::stringstream text;
    text << in.rdbuf();
    const double reference = 0.5 * (meanOf(text.str(), 1024, 0.0f, 101) + meanOf(text.str(), 1024, 0.0f, 102));
    double adaptive = 0.0;
    for (int seed = 1; seed <= 4; ++seed) adaptive += 0.25 * meanOf(text.str(), 4096, 0.1f, seed);
    EXPECT_NEAR(adaptive / reference - 1.0, 0.0, 0.006) << "adaptive " << adaptive << " reference " << reference;
}
