// SPDX-License-Identifier: Apache-2.0
// Every .usda/.usd file of the usd-wg conformance corpus parses and composes; the *_invalid
// files yield warnings naming the missing file, not errors or crashes.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "scene_adapter/usda/parser.h"
#include "scene_adapter/usda/stage.h"
#include "testUtil.h"

namespace principled::usd {
namespace {

std::vector<std::string> corpusFiles() {
    std::vector<std::string> files;
    for (const auto& e : std::filesystem::recursive_directory_iterator(test::corpusDir())) {
        auto ext = e.path().extension();
        if (e.is_regular_file() && (ext == ".usda" || ext == ".usd"))
            files.push_back(e.path().string());
    }
    std::sort(files.begin(), files.end());
    return files;
}

TEST(Corpus, EveryFileParses) {
    auto files = corpusFiles();
    ASSERT_GE(files.size(), 70u) << "corpus missing at " << test::corpusDir();
    for (const std::string& f : files) {
        SCOPED_TRACE(f);
        EXPECT_NO_THROW(parseLayerFile(f));
    }
}

TEST(Corpus, EveryFileComposes) {
    for (const std::string& f : corpusFiles()) {
        SCOPED_TRACE(f);
        std::unique_ptr<Stage> stage;
        ASSERT_NO_THROW(stage = Stage::open(f));
        bool invalid = f.find("_invalid") != std::string::npos;
        // The corpus ships without test_assets/_common (axis.usda), so the transform tests warn.
        std::ifstream in(f);
        std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        bool expectWarnings = invalid || f.find("reference_prim_in_") != std::string::npos ||
                              text.find("_common/") != std::string::npos;
        if (expectWarnings) {
            EXPECT_FALSE(stage->warnings().empty());
        } else {
            for (const Diagnostic& d : stage->warnings()) ADD_FAILURE() << d.str();
        }
        for (const Diagnostic& d : stage->warnings())
            EXPECT_EQ(d.severity, Diagnostic::Severity::Warning) << d.str();
        EXPECT_FALSE(stage->traverse().empty());
    }
}

}  // namespace
}  // namespace principled::usd
