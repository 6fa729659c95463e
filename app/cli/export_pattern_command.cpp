/// `atelier-cli export-pattern PROJECT.atelier --out PATTERN.svg [--seam-allowance MM]
/// [--sheet-width MM]`: the
/// garment's 2D pattern at real size as SVG, for printing and plotting (io/pattern_svg.h).

#include "app/cli/commands.h"
#include "app/cli/limits_option.h"
#include "app/cli/preflight.h"

#include "io/atomic_file.h"
#include "io/pattern_svg.h"
#include "io/project_file.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace atelier::app {

namespace {

struct ExportPatternOptions {
    std::string project;
    std::string out;
    double seamAllowanceMm = io::PatternSvgOptions{}.seamAllowanceMm;
    double sheetWidthMm = 0;         ///< 0 = chosen
    std::vector<std::string> limits; ///< --limit NAME=VALUE
};

int runExportPattern(const ExportPatternOptions& options) {
    if (!(options.seamAllowanceMm >= 0 && options.seamAllowanceMm <= io::MAX_SEAM_ALLOWANCE_MM)) {
        std::fprintf(stderr, "error: --seam-allowance %g: must be from 0 to %g mm\n",
                     options.seamAllowanceMm, io::MAX_SEAM_ALLOWANCE_MM);
        return EXIT_BAD_INPUT;
    }
    if (!(options.sheetWidthMm >= 0 && std::isfinite(options.sheetWidthMm))) {
        std::fprintf(stderr, "error: --sheet-width %g: must be 0 (chosen) or more mm\n",
                     options.sheetWidthMm);
        return EXIT_BAD_INPUT;
    }
    if (auto problem = checkOutputs({{"project", options.project}}, {{"--out", options.out}})) {
        std::cerr << "error: " << *problem << "\n";
        return EXIT_BAD_INPUT;
    }
    const std::optional<io::Limits> limits = limitsOrReport(options.limits);
    if (!limits) {
        return EXIT_BAD_INPUT;
    }
    // The pattern needs no body: the project is parsed without looking for its body mesh.
    auto text = io::readFile(options.project, limits->maxJsonBytes);
    if (!text.ok()) {
        std::cerr << inputErrorText(text.error());
        return EXIT_BAD_INPUT;
    }
    auto project = io::parseProject(text.value(), options.project, *limits);
    if (!project.ok()) {
        std::cerr << inputErrorText(project.error());
        return EXIT_BAD_INPUT;
    }
    io::PatternSvgOptions svgOptions;
    svgOptions.seamAllowanceMm = options.seamAllowanceMm;
    svgOptions.sheetWidthMm = options.sheetWidthMm;
    auto svg = io::patternSvg(project.value().garment, svgOptions);
    if (!svg.ok()) {
        Error e = svg.error();
        e.file = options.project;
        std::cerr << inputErrorText(e);
        return EXIT_BAD_INPUT;
    }
    if (auto written = io::writeFileAtomically(options.out, svg.value().text); !written.ok()) {
        std::cerr << "error: " << written.error().toString() << "\n";
        return EXIT_RUN_FAILED;
    }
    std::fprintf(stderr, "export-pattern: %zu panels on a %.0f x %.0f mm sheet -> %s\n",
                 svg.value().panels.size(), svg.value().widthMm, svg.value().heightMm,
                 options.out.c_str());
    return EXIT_OK;
}

} // namespace

void addExportPatternCommand(CLI::App& app) {
    auto options = std::make_shared<ExportPatternOptions>();
    CLI::App* cmd = app.add_subcommand(
        "export-pattern",
        "Write a project's 2D pattern at real size as SVG (mm): cut and sewing lines, notches, "
        "grain lines, seam marks, labels");
    cmd->add_option("project", options->project, "Garment project (.atelier)")->required();
    cmd->add_option("--out,-o", options->out, "The pattern (.svg)")->required();
    cmd->add_option("--seam-allowance", options->seamAllowanceMm,
                    "Cut line outside the sewing line [mm]; 0 = cut on the outline")
        ->capture_default_str();
    cmd->add_option("--sheet-width", options->sheetWidthMm,
                    "Sheet (plotter roll) width [mm]; 0 = the width giving the smallest sheet")
        ->capture_default_str();
    addLimitOption(cmd, &options->limits);
    cmd->callback([options] {
        const int code = runExportPattern(*options);
        if (code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

} // namespace atelier::app
