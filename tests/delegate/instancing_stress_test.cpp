// PointInstancer cost at scale (label "stress", not in the default run): RSS growth per
// instance and the time to sync + commit 100k and 1M instances of one 2-triangle mesh through
// the render index. The figures are quoted in docs/geometry.md.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <string>

#include "delegate/renderDelegate.h"
#include "tests/support/testSceneDelegate.h"

using namespace principled;

namespace {

// A TestSceneDelegate whose quad "/Proto" is drawn only by the instancer "/Inst".
class InstancingDelegate : public test::TestSceneDelegate {
public:
    InstancingDelegate(hd::RenderIndex* index, int count) : TestSceneDelegate(index), _count(count) {
        _positions.resize(size_t(count));
        for (int i = 0; i < count; ++i) _positions[size_t(i)] = glm::vec3(float(i % 1000), float(i / 1000), 0.0f);
        addQuad(hd::Path("/Proto"), 0.5f);
    }
    hd::Path getInstancerId(const hd::Path& id) const override {
        return id == hd::Path("/Proto") ? hd::Path("/Inst") : hd::Path();
    }
    std::vector<int> getInstanceIndices(const hd::Path&, const hd::Path&) const override {
        std::vector<int> out(static_cast<size_t>(_count));
        for (int i = 0; i < _count; ++i) out[size_t(i)] = i;
        return out;
    }
    hd::Value get(const hd::Path& id, const hd::Token& key) const override {
        if (id == hd::Path("/Inst"))
            return key == hd::tokens::instanceTranslations() ? hd::Value(_positions) : hd::Value();
        return TestSceneDelegate::get(id, key);
    }

private:
    int _count;
    std::vector<glm::vec3> _positions;
};

double rssBytes() {
    std::ifstream f("/proc/self/statm");
    long pages = 0, resident = 0;
    f >> pages >> resident;
    return double(resident) * 4096.0;
}

void measure(int count) {
    embree::EmbreeRenderDelegate delegate;
    hd::RenderIndex index(&delegate);
    InstancingDelegate scene(&index, count);
    double before = rssBytes();
    auto t0 = std::chrono::steady_clock::now();
    index.sync();  // prim sync + commitResources (top-level BVH build)
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    double perInstance = (rssBytes() - before) / count;
    auto stats = delegate.renderStats();
    std::printf("%d instances: sync+commit %.3f s, RSS +%.1f MB, %.0f bytes/instance, blasBuilds %.0f\n",
                count, seconds, (rssBytes() - before) / 1e6, perInstance, stats["blasBuilds"]);
    EXPECT_EQ(stats["blasBuilds"], 1.0);
}

}  // namespace

TEST(InstancingStress, HundredThousand) { measure(100000); }
TEST(InstancingStress, OneMillion) { measure(1000000); }
