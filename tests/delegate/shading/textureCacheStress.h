// SPDX-License-Identifier: Apache-2.0
// Shared by textureCache_test.cpp (a short run in the default suite) and
// textureCache_stress_test.cpp (label "stress", a long run): render-like threads do point
// lookups while another thread rewrites the file (another size, channel count and colour each
// time) and calls TextureCache::invalidate().
#pragma once

#include "delegate/shading/textureCache.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "testImages.h"

namespace principled::shading::test {

/// One version of the file: a solid colour, so every bilinear lookup returns it exactly.
struct SolidVersion {
    int width, height, channels;
    OIIO::TypeDesc type;
    glm::vec4 stored;  ///< the first `channels` values are written
    glm::vec4 looked;  ///< what a lookup returns (UsdUVTexture channel rules)
};

inline const std::vector<SolidVersion>& solidVersions() {
    // Values exact in half and float.
    static const std::vector<SolidVersion> v = {
        {4, 4, 1, OIIO::TypeDesc::FLOAT, {0.25f, 0, 0, 0}, {0.25f, 0.25f, 0.25f, 1.0f}},
        {16, 8, 3, OIIO::TypeDesc::FLOAT, {0.0f, 0.5f, 1.0f, 0}, {0.0f, 0.5f, 1.0f, 1.0f}},
        {8, 32, 4, OIIO::TypeDesc::HALF, {1.0f, 0.5f, 0.25f, 0.75f}, {1.0f, 0.5f, 0.25f, 0.75f}},
        {64, 64, 2, OIIO::TypeDesc::FLOAT, {0.125f, 0.625f, 0, 0}, {0.125f, 0.125f, 0.125f, 0.625f}},
    };
    return v;
}

/// Writes version `k` to `path` atomically (a temporary file renamed over it), as an editor
/// saving the file would: a reader never sees a half-written file.
inline bool writeSolid(const std::string& path, const SolidVersion& v) {
    std::vector<float> px;
    px.reserve(size_t(v.width) * v.height * v.channels);
    for (int i = 0; i < v.width * v.height; ++i)
        for (int c = 0; c < v.channels; ++c) px.push_back(v.stored[c]);
    std::string tmp = path + ".tmp.exr";
    if (!writeImage(tmp, v.width, v.height, v.channels, px, v.type)) return false;
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    return !ec;
}

inline bool isVersionLookup(const glm::vec4& c) {
    for (const SolidVersion& v : solidVersions())
        if (std::abs(c.x - v.looked.x) < 1e-6f && std::abs(c.y - v.looked.y) < 1e-6f &&
            std::abs(c.z - v.looked.z) < 1e-6f && std::abs(c.w - v.looked.w) < 1e-6f)
            return true;
    return false;
}

inline bool isVersionInfo(const TextureInfo& info) {
    for (const SolidVersion& v : solidVersions())
        if (info.width == v.width && info.height == v.height && info.channels == v.channels)
            return true;
    return false;
}

/// Runs `readers` lookup threads for `seconds` while this thread rewrites the file and calls
/// invalidate() in a loop. Every lookup must be one of the versions' colours and every
/// description one of theirs; then, quiescent, the retired versions are collected.
inline void invalidateWhileLooking(double seconds, int readers) {
    TempDir dir;
    TextureCache cache;
    const std::string path = dir.file("edited.exr");
    const auto& versions = solidVersions();
    ASSERT_TRUE(writeSolid(path, versions[0]));
    const Texture* texture = cache.open(path).texture;
    ASSERT_NE(texture, nullptr);

    std::atomic<bool> stop{false};
    std::atomic<long> lookups{0}, badColour{0}, badInfo{0}, otherTexture{0};
    glm::vec4 firstBad(0.0f);
    std::atomic<bool> haveFirstBad{false};
    std::vector<std::thread> threads;
    for (int r = 0; r < readers; ++r)
        threads.emplace_back([&, r] {
            std::mt19937 rng(100 + r);
            std::uniform_real_distribution<float> u(-0.5f, 1.5f);
            long n = 0;
            while (!stop.load(std::memory_order_relaxed)) {
                if (n % 256 == 0) {
                    // What a material sync does: open() (re-reads a stale file) and read the
                    // description.
                    TextureOpenResult o = cache.open(path);
                    if (o.texture != texture) ++otherTexture;
                    if (!isVersionInfo(texture->info())) ++badInfo;
                }
                glm::vec4 c = cache.sample(*texture, Wrap::Clamp, Wrap::Clamp, {u(rng), u(rng)});
                if (!isVersionLookup(c)) {
                    if (!haveFirstBad.exchange(true)) firstBad = c;
                    ++badColour;
                }
                ++n;
            }
            lookups += n;
        });

    int invalidations = 0;
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
        ++invalidations;
        ASSERT_TRUE(writeSolid(path, versions[invalidations % versions.size()]));
        cache.invalidate();
    }
    stop = true;
    for (auto& t : threads) t.join();

    std::printf("%d invalidations, %ld lookups (%ld off-colour) on %d threads in %.1f s\n",
                invalidations, lookups.load(), badColour.load(), readers, seconds);
    EXPECT_EQ(badColour.load(), 0) << "e.g. " << firstBad.x << " " << firstBad.y << " "
                                   << firstBad.z << " " << firstBad.w;
    EXPECT_EQ(badInfo.load(), 0);
    EXPECT_EQ(otherTexture.load(), 0);
    EXPECT_GT(lookups.load(), 0);
    EXPECT_GE(invalidations, 3);

    // Quiescent: the retired versions can go, and the last file is what the cache now reads.
    cache.collectRetired();
    EXPECT_EQ(cache.retiredBytes(), 0u);
    const SolidVersion& last = versions[invalidations % versions.size()];
    ASSERT_EQ(cache.open(path).texture, texture);
    EXPECT_EQ(texture->info().width, last.width);
    EXPECT_EQ(texture->info().height, last.height);
    EXPECT_EQ(texture->info().channels, last.channels);
    glm::vec4 c = cache.sample(*texture, Wrap::Clamp, Wrap::Clamp, {0.3f, 0.7f});
    for (int i = 0; i < 4; ++i) EXPECT_NEAR(c[i], last.looked[i], 1e-6f) << i;
    ASSERT_NE(texture->resident(), nullptr);
    EXPECT_EQ(cache.residentBytes(), texture->resident()->bytes());
}

}  // namespace principled::shading::test
