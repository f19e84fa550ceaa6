// SPDX-License-Identifier: Apache-2.0
// `principled bsdf ...`: inspect the shading models (albedo, lobes, chi-square) from the shell.
#pragma once

#include <CLI/CLI.hpp>

namespace principled::tools {

/// Registers the `bsdf` subcommand and its children on the application. The callbacks run when
/// the subcommand is parsed; they return the process exit status through *exitCode.
void addBsdfCommands(CLI::App& app, int* exitCode);

}  // namespace principled::tools
