// SPDX-License-Identifier: Apache-2.0
// Replays the fuzzer's corpus and crash reproducers (fuzz/corpus/*) through parse + compose, so
// every input the fuzzer ever found interesting stays a regression test.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "scene_adapter/usda/stage.h"

namespace principled::usd {
namespace {

TEST(FuzzCorpus, ReplaysWithoutCrashing) {
    const std::filesystem::path dir =
        std::filesystem::path(PRINCIPLED_SOURCE_DIR) / "tests/scene_adapter/usda/fuzz/corpus";
    std::size_t files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(dir)) {
        if (!entry.is_regular_file()) continue;
        std::ifstream in(entry.path(), std::ios::binary);
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        ++files;
        try {
            auto stage = Stage::openString(text, "fuzz.usda");
            for (const Prim* p : stage->traverse())
                for (const Attribute* a : p->attributes()) (void)a->get(1.0);
        } catch (const ParseError& e) {
            std::string what = e.what();
            EXPECT_EQ(what.rfind("fuzz.usda:", 0), 0u) << entry.path() << ": " << what;
            EXPECT_NE(what.find(": expected "), std::string::npos) << entry.path() << ": " << what;
        } catch (const Error&) {
        }
    }
    EXPECT_GT(files, 0u);
}

}  // namespace
}  // namespace principled::usd
