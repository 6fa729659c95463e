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

struct ImportOptions {
    std::string spec;
    std::string out;
    std::string fabric = "cotton";
    std::string slots = "auto";
    double clearanceMm = 30;
    double particleDistanceMm = 0; ///< 0: the project default
    std::vector<std::string> limits;
};

int runImportGarmentCode(const ImportOptions& options) {
    if (auto problem = checkOutputs({{"SPEC", options.spec}}, {{"--out", options.out}})) {
        std::cerr << "error: " << *problem << "\n";
        return EXIT_BAD_INPUT;
    }
    const std::optional<io::Limits> limits = limitsOrReport(options.limits);
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
    gc.fabric = options.fabric;
    gc.slots = options.slots;
    gc.clearance = options.clearanceMm / 1000;
    auto imported = io::importGarmentCode(options.spec, body.value().body, gc, *limits);
    if (!imported.ok()) {
        std::cerr << inputErrorText(imported.error());
        return EXIT_BAD_INPUT;
    }
    io::GarmentCodeImport& result = imported.value();
    for (const std::string& w : result.warnings) {
        std::cerr << "warning: " << options.spec << ": " << w << "\n";
    }
    if (options.particleDistanceMm > 0) {
        result.project.drape.particleDistance = options.particleDistanceMm / 1000;
    }
    auto saved = io::saveProject(options.out, result.project);
    if (!saved.ok()) {
        std::cerr << "error: " << saved.error().toString() << "\n";
        return EXIT_RUN_FAILED;
    }
    std::fprintf(stderr, "import: %zu panels, %zu seams, %zu warnings -> %s\n",
                 result.project.garment.panels.size(), result.project.garment.seams.size(),
                 result.warnings.size(), options.out.c_str());
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
    std::string file;
    std::string out;
    std::string fabric = "cotton";
    std::string units = "auto";
    double toleranceMm = 0.2;
    double particleDistanceMm = 0; ///< 0: the project default
    std::vector<std::string> limits;
};

int runImportDxf(const DxfOptions& options) {
    if (auto problem = checkOutputs({{"DXF", options.file}}, {{"--out", options.out}})) {
        std::cerr << "error: " << *problem << "\n";
        return EXIT_BAD_INPUT;
    }
    const std::optional<io::Limits> limits = limitsOrReport(options.limits);
    if (!limits) {
        return EXIT_BAD_INPUT;
    }
    io::DxfImportOptions dxf;
    dxf.fabric = options.fabric;
    dxf.units = options.units;
    dxf.fitTolerance = options.toleranceMm / 1000;
    auto imported = io::importDxfAama(options.file, dxf, *limits);
    if (!imported.ok()) {
        std::cerr << inputErrorText(imported.error());
        return EXIT_BAD_INPUT;
    }
    io::DxfImport& result = imported.value();
    for (const std::string& w : result.warnings) {
        std::cerr << "warning: " << options.file << ": " << w << "\n";
    }
    if (options.particleDistanceMm > 0) {
        result.project.drape.particleDistance = options.particleDistanceMm / 1000;
    }
    auto saved = io::saveProject(options.out, result.project);
    if (!saved.ok()) {
        std::cerr << "error: " << saved.error().toString() << "\n";
        return EXIT_RUN_FAILED;
    }
    std::fprintf(stderr, "import: %zu pieces, units %s, %zu warnings -> %s\n", result.pieces.size(),
                 result.units.c_str(), result.warnings.size(), options.out.c_str());
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
    gc->add_option("SPEC", options->spec, "Specification (JSON)")
        ->required()
        ->check(CLI::ExistingFile);
    gc->add_option("--out", options->out, "Project to write (.atelier)")->required();
    gc->add_option("--fabric", options->fabric, "Fabric preset of every panel")
        ->capture_default_str();
    gc->add_option("--slots", options->slots,
                   "Slots of the panels that are not sleeves: auto, torso or waist")
        ->check(CLI::IsMember({"auto", "torso", "waist"}))
        ->capture_default_str();
    gc->add_option("--clearance", options->clearanceMm,
                   "Gap between each placed panel and the body [mm]")
        ->check(CLI::Range(0.0, 200.0))
        ->capture_default_str();
    gc->add_option("--particle-distance", options->particleDistanceMm,
                   "The project's mesh edge length [mm] (default: the project default, 10)")
        ->check(CLI::Range(1.0, 1000.0));
    addLimitOption(gc, &options->limits);
    gc->callback([options]() {
        if (const int code = runImportGarmentCode(*options); code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });

    auto dxfOptions = std::make_shared<DxfOptions>();
    CLI::App* dxf = import->add_subcommand(
        "dxf", "A DXF-AAMA / ASTM D6673 pattern file (ASCII DXF) as an Atelier project: its "
               "pieces, unsewn, on the default body");
    dxf->add_option("DXF", dxfOptions->file, "Pattern file (.dxf)")
        ->required()
        ->check(CLI::ExistingFile);
    dxf->add_option("--out", dxfOptions->out, "Project to write (.atelier)")->required();
    dxf->add_option("--fabric", dxfOptions->fabric, "Fabric preset of every panel")
        ->capture_default_str();
    dxf->add_option("--units", dxfOptions->units,
                    "Unit of the file's coordinates: auto (its Units: text or $INSUNITS), mm, "
                    "cm, m or in")
        ->check(CLI::IsMember({"auto", "mm", "cm", "m", "in"}))
        ->capture_default_str();
    dxf->add_option("--tolerance", dxfOptions->toleranceMm,
                    "Largest distance of a fitted outline curve from a digitised point [mm]")
        ->check(CLI::Range(0.001, 5.0))
        ->capture_default_str();
    dxf->add_option("--particle-distance", dxfOptions->particleDistanceMm,
                    "The project's mesh edge length [mm] (default: the project default, 10)")
        ->check(CLI::Range(1.0, 1000.0));
    addLimitOption(dxf, &dxfOptions->limits);
    dxf->callback([dxfOptions]() {
        if (const int code = runImportDxf(*dxfOptions); code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

} // namespace atelier::app
