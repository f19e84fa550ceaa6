// SPDX-License-Identifier: Apache-2.0
// libFuzzer target for the USDA parser and composer. Build with clang (see docs/usda.md):
//   CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DPRINCIPLED_FUZZ=ON -DPRINCIPLED_BUILD_BENCH=OFF
//   \
//     -DCMAKE_BUILD_TYPE=RelWithDebInfo
//     -DCMAKE_CXX_FLAGS="-fsanitize=fuzzer-no-link,address,undefined"
//   ./build-fuzz/bin/usda_fuzz tests/scene_adapter/usda/fuzz/corpus -max_len=4096
// Any crash, sanitizer report, or ParseError not of the form "fuzz.usda:L:C: expected X,
// found Y" aborts.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "scene_adapter/usda/parser.h"
#include "scene_adapter/usda/stage.h"

using namespace principled::usd;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        Stage::openString(text, "fuzz.usda");
    } catch (const ParseError& e) {
        std::string_view what = e.what();
        if (what.rfind("fuzz.usda:", 0) != 0 ||
            what.find(": expected ") == std::string_view::npos ||
            what.find(", found ") == std::string_view::npos) {
            std::fprintf(stderr, "malformed ParseError: %s\n", e.what());
            std::abort();
        }
    } catch (const Error&) {
        // binary input refused, too many layers...
    }
    return 0;
}
