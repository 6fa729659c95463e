/// `atelier-cli import garmentcode SPEC.json --out PROJECT.atelier`: a GarmentCode / pygarment
/// specification as an Atelier project on the default body (docs/garmentcode.md);
/// `atelier-cli import dxf PATTERN.dxf --out PROJECT.atelier`: a DXF-AAMA / ASTM D6673 pattern
/// (docs/dxf-aama.md).
#include "app/cli/commands.h"
#include "app/cli/limits_option.h"
#include "app/cli/preflight.h"

#include "io/body_file.h"
#include "io/dxf_aama.h"
#include "io/garmentcode.h"
#include "io/project_file.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace atelier::app {

namespace {

/// What every importer takes: the file read, the project written and its settings.
struct ImportCommon {
    std::string input;
    std::string out;
    std::string fabric = "cotton";
    double particleDistanceMm = 0; ///< 0: the project default
    std::vector<std::string> limits;
};

/// The input and output checked and the limits read, or nullopt (the reason printed).
std::optional<io::Limits> prepareImport(const char* inputName, const ImportCommon& common) {
    if (auto problem = checkOutputs({{inputName, common.input}}, {{"--out", common.out}})) {
        std::cerr << "error: " << *problem << "\n";
        return std::nullopt;
    }
    return limitsOrReport(common.limits);
}

/// Prints the importer's warnings and writes the project; EXIT_OK or why not.
int saveImport(const ImportCommon& common, patterns::Project& project,
               const std::vector<std::string>& warnings) {
    for (const std::string& w : warnings) {
        std::cerr << "warning: " << common.input << ": " << w << "\n";
    }
    if (common.particleDistanceMm > 0) {
        project.drape.particleDistance = common.particleDistanceMm / 1000;
    }
    auto saved = io::saveProject(common.out, project);
    if (!saved.ok()) {
        std::cerr << "error: " << saved.error().toString() << "\n";
        return EXIT_RUN_FAILED;
    }
    return EXIT_OK;
}

void addCommonOptions(CLI::App* cmd, const char* inputName, const char* inputWhat,
                      ImportCommon* common) {
    cmd->add_option(inputName, common->input, inputWhat)->required()->check(CLI::ExistingFile);
    cmd->add_option("--out", common->out, "Project to write (.atelier)")->required();
    cmd->add_option("--fabric", common->fabric, "Fabric preset of every panel")
        ->capture_default_str();
    cmd->add_option("--particle-distance", common->particleDistanceMm,
                    "The project's mesh edge length [mm] (default: the project default, 10)")
        ->check(CLI::Range(1.0, 1000.0));
    addLimitOption(cmd, &common->limits);
}

struct ImportOptions {
    ImportCommon common;
    std::string slots = "auto";
    double clearanceMm = 30;
};

int runImportGarmentCode(const ImportOptions& options) {
    const std::optional<io::Limits> limits = prepareImport("SPEC", options.common);
    if (!limits) {
        return EXIT_BAD_INPUT;
    }
    // The project's body is the default mannequin: its slots place the panels.
    const patterns::BodySource source;
    auto body = io::makeBody(source, "");
    if (!body.ok()) {
        std::cerr << "error: " << body.error().toString() << "\n";
        return EXIT_RUN_FAILED;
    }
    io::GarmentCodeOptions gc;
    gc.fabric = options.common.fabric;
    gc.slots = options.slots;
    gc.clearance = options.clearanceMm / 1000;
    auto imported = io::importGarmentCode(options.common.input, body.value().body, gc, *limits);
    if (!imported.ok()) {
        std::cerr << inputErrorText(imported.error());
        return EXIT_BAD_INPUT;
    }
    io::GarmentCodeImport& result = imported.value();
    if (const int code = saveImport(options.common, result.project, result.warnings);
        code != EXIT_OK) {
        return code;
    }
    std::fprintf(stderr, "import: %zu panels, %zu seams, %zu warnings -> %s\n",
                 result.project.garment.panels.size(), result.project.garment.seams.size(),
                 result.warnings.size(), options.common.out.c_str());
    for (const patterns::Panel& p : result.project.garment.panels) {
        std::fprintf(stderr, "  %-16s %-12s %-5s rotation %7.1f deg, offset (%.0f, %.0f) mm\n",
                     p.name.c_str(), p.placement.slot.c_str(),
                     p.side == patterns::PanelSide::Back ? "back" : "front",
                     p.placement.rotation * 180 / 3.141592653589793, p.placement.offset.x() * 1000,
                     p.placement.offset.y() * 1000);
    }
    return EXIT_OK;
}

struct DxfOptions {
    ImportCommon common;
    std::string units = "auto";
    double toleranceMm = 0.2;
};

int runImportDxf(const DxfOptions& options) {
    const std::optional<io::Limits> limits = prepareImport("DXF", options.common);
    if (!limits) {
        return EXIT_BAD_INPUT;
    }
    io::DxfImportOptions dxf;
    dxf.fabric = options.common.fabric;
    dxf.units = options.units;
    dxf.fitTolerance = options.toleranceMm / 1000;
    auto imported = io::importDxfAama(options.common.input, dxf, *limits);
    if (!imported.ok()) {
        std::cerr << inputErrorText(imported.error());
        return EXIT_BAD_INPUT;
    }
    io::DxfImport& result = imported.value();
    if (const int code = saveImport(options.common, result.project, result.warnings);
        code != EXIT_OK) {
        return code;
    }
    std::fprintf(stderr, "import: %zu pieces, units %s, %zu warnings -> %s\n", result.pieces.size(),
                 result.units.c_str(), result.warnings.size(), options.common.out.c_str());
    std::fprintf(stderr, "  %-16s %5s %9s %9s %8s %5s %7s %7s %5s\n", "piece", "qty", "cut mm",
                 "outline", "fit mm", "segs", "notches", "inner", "holes");
    for (const io::DxfPiece& p : result.pieces) {
        std::fprintf(stderr, "  %-16s %5d %9.1f %9.1f %8.3f %5d %7d %7d %5d\n", p.name.c_str(),
                     p.quantity, p.cutLength * 1000, p.outlineLength * 1000, p.fitError * 1000,
                     p.segments, p.notches, p.internalLines, p.holes);
    }
    return EXIT_OK;
}

} // namespace

void addImportCommand(CLI::App& app) {
    CLI::App* import = app.add_subcommand("import", "Import a pattern made by another tool");
    import->require_subcommand(1);
    auto options = std::make_shared<ImportOptions>();
    CLI::App* gc = import->add_subcommand(
        "garmentcode", "A GarmentCode / pygarment specification (JSON) as an Atelier project on "
                       "the default body");
    addCommonOptions(gc, "SPEC", "Specification (JSON)", &options->common);
    gc->add_option("--slots", options->slots,
                   "Slots of the panels that are not sleeves: auto, torso or waist")
        ->check(CLI::IsMember({"auto", "torso", "waist"}))
        ->capture_default_str();
    gc->add_option("--clearance", options->clearanceMm,
                   "Gap between each placed panel and the body [mm]")
        ->check(CLI::Range(0.0, 200.0))
        ->capture_default_str();
    gc->callback([options]() {
        if (const int code = runImportGarmentCode(*options); code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });

    auto dxfOptions = std::make_shared<DxfOptions>();
    CLI::App* dxf = import->add_subcommand(
        "dxf", "A DXF-AAMA / ASTM D6673 pattern file (ASCII DXF) as an Atelier project: its "
               "pieces, unsewn, on the default body");
    addCommonOptions(dxf, "DXF", "Pattern file (.dxf)", &dxfOptions->common);
    dxf->add_option("--units", dxfOptions->units,
                    "Unit of the file's coordinates: auto (its Units: text or $INSUNITS), mm, "
                    "cm, m or in")
        ->check(CLI::IsMember({"auto", "mm", "cm", "m", "in"}))
        ->capture_default_str();
    dxf->add_option("--tolerance", dxfOptions->toleranceMm,
                    "Largest distance of a fitted outline curve from a digitised point [mm]")
        ->check(CLI::Range(0.001, 5.0))
        ->capture_default_str();
    dxf->callback([dxfOptions]() {
        if (const int code = runImportDxf(*dxfOptions); code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

} // namespace atelier::app
