// SPDX-License-Identifier: Apache-2.0
// ProgressBar: a one-line progress bar with ETA on stderr, drawn only when stderr is a terminal.
#pragma once

#include <chrono>
#include <string>

namespace principled::tools {

class ProgressBar {
public:
    /// enabled=false (or stderr not a terminal) makes every call a no-op. checkTerminal=false
    /// skips the terminal test (MPI rank 0, whose stderr is a pipe to mpirun's terminal).
    ProgressBar(std::string label, bool enabled, bool checkTerminal = true);
    ~ProgressBar();
    /// done of total units; redraws at most ~10 times a second.
    void update(double done, double total, const std::string& detail = "");
    void finish();

private:
    std::string _label;
    bool _enabled;
    bool _drawn = false;
    std::chrono::steady_clock::time_point _start, _lastDraw;
};

}  // namespace principled::tools
