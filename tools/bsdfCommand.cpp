// SPDX-License-Identifier: Apache-2.0
#include "tools/bsdfCommand.h"

namespace principled::tools {

void addBsdfCommands(CLI::App& app, int* exitCode) {
    auto* bsdf = app.add_subcommand("bsdf", "Inspect the shading models");
    bsdf->require_subcommand(1);
    (void)exitCode;
}

}  // namespace principled::tools
