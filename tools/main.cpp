// SPDX-License-Identifier: Apache-2.0
// The `principled` command line.
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>

#include "plugins/registry/pluginRegistry.h"
#include "tools/bsdfCommand.h"
#include "tools/infoCommand.h"
#include "tools/renderCommand.h"

int main(int argc, char** argv) {
    CLI::App app{"principled: a Disney/UE4 principled path tracer for USD scenes"};
    app.require_subcommand(1);
    int exitCode = 0;
    principled::tools::addRenderCommand(app, &exitCode);
    principled::tools::addBsdfCommands(app, &exitCode);
    principled::tools::addInfoCommand(app, &exitCode);
    app.add_subcommand("plugins", "List the render-delegate plugins found and where they were searched")
        ->callback([] {
            std::fputs(principled::plugins::describePlugins(principled::plugins::PluginRegistry::instance()).c_str(),
                       stdout);
        });
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // Help and version exit 0; every usage error exits 1 with CLI11's message.
        int code = app.exit(e);
        return code == 0 ? 0 : 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "principled: error: %s\n", e.what());
        return 1;
    }
    return exitCode;
}
