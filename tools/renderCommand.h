// SPDX-License-Identifier: Apache-2.0
// `principled render`: render a USD stage (or the built-in default scene) to EXR/PNG.
#pragma once

#include <CLI/CLI.hpp>

namespace principled::tools {

void addRenderCommand(CLI::App& app, int* exitCode);

}  // namespace principled::tools
