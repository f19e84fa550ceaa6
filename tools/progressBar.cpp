// SPDX-License-Identifier: Apache-2.0
#include "tools/progressBar.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace principled::tools {

ProgressBar::ProgressBar(std::string label, bool enabled, bool checkTerminal)
    : _label(std::move(label)), _enabled(enabled && (!checkTerminal || isatty(STDERR_FILENO))) {
    _start = _lastDraw = std::chrono::steady_clock::now();
}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(double done, double total, const std::string& detail) {
    if (!_enabled || total <= 0.0) return;
    auto now = std::chrono::steady_clock::now();
    bool last = done >= total;
    if (_drawn && !last && now - _lastDraw < std::chrono::milliseconds(100)) return;
    _lastDraw = now;
    double frac = std::clamp(done / total, 0.0, 1.0);
    double elapsed = std::chrono::duration<double>(now - _start).count();
    double eta = frac > 0.0 ? elapsed * (1.0 - frac) / frac : 0.0;
    constexpr int kWidth = 30;
    int filled = static_cast<int>(frac * kWidth + 0.5);
    std::string bar(filled, '#');
    bar.resize(kWidth, '-');
    std::fprintf(stderr, "\r%s [%s] %3d%% %s  %.1fs elapsed, ETA %.1fs   ", _label.c_str(),
                 bar.c_str(), static_cast<int>(frac * 100.0 + 0.5), detail.c_str(), elapsed, eta);
    std::fflush(stderr);
    _drawn = true;
}

void ProgressBar::finish() {
    if (_enabled && _drawn) {
        std::fputc('\n', stderr);
        _drawn = false;
    }
}

}  // namespace principled::tools
