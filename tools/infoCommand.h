// SPDX-License-Identifier: Apache-2.0
// `principled info SCENE.usda`: what a stage holds once loaded, refined and committed.
#pragma once

#include <CLI/CLI.hpp>

namespace principled::tools {

void addInfoCommand(CLI::App& app, int* exitCode);

}  // namespace principled::tools
