// SPDX-License-Identifier: Apache-2.0
#include "tools/processClock.h"

#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace principled::tools {

namespace {

// CLOCK_BOOTTIME now, minus the start time in /proc/self/stat (field 22: clock ticks since
// boot, the same clock).
double sinceStart() {
    std::FILE* f = std::fopen("/proc/self/stat", "r");
    if (!f) return -1.0;
    char buf[1024];
    size_t n = std::fread(buf, 1, sizeof buf - 1, f);
    std::fclose(f);
    buf[n] = '\0';
    // Field 2 (comm) is in parentheses and may hold spaces: count fields after the last ')'.
    const char* p = std::strrchr(buf, ')');
    if (!p) return -1.0;
    unsigned long long start = 0;
    // After ')': field 3 (state) ... field 22 (starttime) is the 20th.
    int field = 2;
    for (const char* q = p + 1; *q; ++q) {
        if (*q == ' ') {
            ++field;
            if (field == 22) {
                start = std::strtoull(q + 1, nullptr, 10);
                break;
            }
        }
    }
    long ticks = sysconf(_SC_CLK_TCK);
    timespec now{};
    if (field != 22 || ticks <= 0 || clock_gettime(CLOCK_BOOTTIME, &now) != 0) return -1.0;
    return double(now.tv_sec) + double(now.tv_nsec) * 1e-9 - double(start) / double(ticks);
}

// Static initialisation of the executable runs after every shared library is loaded.
const double gInitSeconds = sinceStart();

}  // namespace

double secondsSinceProcessStart() { return sinceStart(); }

double processStartToInitSeconds() { return gInitSeconds; }

double processCpuSeconds() {
    rusage u{};
    if (getrusage(RUSAGE_SELF, &u) != 0) return -1.0;
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           double(u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-6;
}

double unixSeconds() {
    timespec now{};
    clock_gettime(CLOCK_REALTIME, &now);
    return double(now.tv_sec) + double(now.tv_nsec) * 1e-9;
}

}  // namespace principled::tools
