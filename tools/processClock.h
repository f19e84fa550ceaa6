// SPDX-License-Identifier: Apache-2.0
// Time since the process started (for the --stats startup figures, docs/performance.md).
#pragma once

namespace principled::tools {

/// Seconds from the kernel's start time of this process (/proc/self/stat, counted from fork;
/// the kernel reports it in clock ticks, 10 ms steps, so this is up to 10 ms high) to now.
/// Negative when /proc is unavailable.
double secondsSinceProcessStart();

/// Seconds from process start to this executable's static initialisation, i.e. the time the
/// dynamic loader spent mapping and relocating the shared libraries (same 10 ms steps).
double processStartToInitSeconds();

/// CPU time of the whole process so far (all threads, user + system), seconds.
double processCpuSeconds();

/// The wall clock now, seconds since the Unix epoch (for exact figures measured outside:
/// a harness that takes the time before exec subtracts it).
double unixSeconds();

}  // namespace principled::tools
