/// atelier-cli: headless Atelier. Subcommands are registered from app/cli/*_command.cpp.

#include "app/cli/commands.h"
#include "app/cli/interrupt.h"
#include "app/cli/limits_option.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

namespace {

int run(int argc, char** argv) {
    CLI::App app{"Atelier: cloth and garment simulation, headless"};
    app.name("atelier-cli");
    app.require_subcommand(1);
    app.set_version_flag("--version", "atelier-cli 0.1.0");

    atelier::app::addSimulateCommand(app);
    // ---- Further subcommands: register them here. ----
    atelier::app::addBenchCommand(app);
    atelier::app::addDrapeCommand(app);
    atelier::app::addRenderCommand(app);
    atelier::app::addRenderBatchCommand(app);
    atelier::app::addBodyCommand(app);
    atelier::app::addBatchCommand(app);
    atelier::app::addBatchSummaryCommand(app);
    atelier::app::addExportPatternCommand(app);
    atelier::app::addImportCommand(app);
    atelier::app::addFabricCommand(app);
    atelier::app::addAnimateCommand(app);
    atelier::app::addLimitsCommand(app);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        // Usage errors exit 2 (bad input); --help and --version exit 0.
        const int code = app.exit(e);
        return code == 0 || e.get_name() == "RuntimeError" ? code : atelier::app::EXIT_BAD_INPUT;
    }
    return atelier::app::EXIT_OK;
}

} // namespace

int main(int argc, char** argv) {
    // Before anything else: a signal at any moment from here on stops the command cleanly.
    const atelier::app::InterruptGuard interrupts;
    try {
        return run(argc, argv);
    } catch (const std::exception& e) {
        // Nothing should throw this far; if something does, say what instead of aborting.
        std::fprintf(stderr, "error: %s\n", e.what());
    } catch (...) {
        std::fputs("error: unexpected exception\n", stderr);
    }
    return atelier::app::EXIT_RUN_FAILED;
}
