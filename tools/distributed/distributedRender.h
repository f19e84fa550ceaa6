// SPDX-License-Identifier: Apache-2.0
// Distributed and resumable final renders for `principled render`: under mpirun every rank
// renders a contiguous range of sample indices (or whole frames of a --frames range), rank 0
// merges the accumulation in rank order and writes; --checkpoint-every/--resume save and
// restore partial accumulation. See docs/distributed.md.
#pragma once

#include <string>
#include <vector>

namespace CLI {
class App;
}
namespace principled::host {
struct SessionOptions;
}

namespace principled::tools::distributed {

struct Options {
    std::string frames;         ///< "A:B" or "A:B:STEP" time codes; empty: the stage's default time
    int checkpointEvery = 0;    ///< samples per pixel between checkpoints (0: none)
    std::string checkpointDir;  ///< default: FIRST_OUTPUT.ckpt
    bool resume = false;
    std::string statsPath;      ///< --stats (set by the render command): rank 0 writes the job's statistics
};

/// Adds --frames, --checkpoint-every, --checkpoint-dir and --resume to the render command.
void addOptions(CLI::App* render, Options* options);
/// True when the render must go through run(): started by an MPI launcher or any of the
/// options above given.
bool wanted(const Options& options);
/// Renders as described above; returns the process exit code (a failing rank ends the whole
/// job with exit code 1 and a message naming the rank).
int run(const host::SessionOptions& session, const std::string& scene,
        const std::vector<std::string>& outputs, bool split, bool quiet, const Options& options);

}  // namespace principled::tools::distributed
