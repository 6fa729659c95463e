/// `atelier-cli fabric fit`: a fabric preset from what a textile lab measures (areal density,
/// bending length or rigidity per direction, tensile stiffness per direction at small strain),
/// and what a preset will show in the lab: bending lengths (ASTM D1388) and the Cusick drape
/// coefficient (BS 5058 / ISO 9073-9). The fit is patterns/fabric_fit.h; the drape test is
/// patterns/cusick.h.

#include "app/cli/commands.h"

#include "io/atomic_file.h"
#include "io/materials.h"

#include "patterns/cusick.h"
#include "patterns/fabric_fit.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

namespace atelier::app {

namespace {

struct FabricFitOptions {
    std::string name = "fitted";
    std::string base = "cotton"; ///< preset that gives what the lab did not measure
    std::string fabricsFile;     ///< presets file to read `base` from (default: the built-in)
    std::string out;             ///< preset file to write
    std::string description;
    std::string source;
    patterns::LabFabric lab;
    bool densityGiven = false;
    bool drape = true;
    double particleDistance = 0.01; ///< of the Cusick test [m]
};

bool anyMeasurement(const patterns::LabFabric& l) {
    return l.bendingLengthWeft || l.bendingLengthWarp || l.bendingLengthBias || l.bendingWeft ||
           l.bendingWarp || l.bendingBias || l.tensileWeft || l.tensileWarp || l.tensileBias ||
           l.poisson;
}

int runFabricFit(FabricFitOptions o) {
    io::MaterialPresets loaded;
    if (!o.fabricsFile.empty()) {
        auto read = io::loadMaterialPresets(o.fabricsFile);
        if (!read.ok()) {
            std::cerr << "error: " << read.error().toString() << "\n";
            return EXIT_BAD_INPUT;
        }
        loaded = read.value();
    }
    const io::MaterialPresets& presets =
        o.fabricsFile.empty() ? io::builtinMaterialPresets() : loaded;
    const auto base = presets.find(o.base);
    if (base == presets.end()) {
        std::cerr << "error: fabric fit: no fabric \"" << o.base
                  << "\" (presets: " << io::presetNames(presets) << ")\n";
        return EXIT_BAD_INPUT;
    }
    sim::Material material = base->second;
    const bool fitting = o.densityGiven || anyMeasurement(o.lab);
    if (fitting) {
        if (!o.densityGiven) {
            o.lab.density = material.density;
        }
        auto fitted = patterns::fitFabric(o.lab, material);
        if (!fitted.ok()) {
            const Error& e = fitted.error();
            std::string option = e.where; // the measurement, named as its option
            std::replace(option.begin(), option.end(), '_', '-');
            std::cerr << "error: fabric fit: --" << option << ": " << e.message << "\n";
            return EXIT_BAD_INPUT;
        }
        material = fitted.value();
        material.name = o.name;
    } else if (!o.out.empty()) {
        std::cerr << "error: fabric fit: --out needs measurements to fit (--density, "
                     "--bending-length-weft, --tensile-weft, ...)\n";
        return EXIT_BAD_INPUT;
    }

    const auto figures = patterns::fabricFigures(material);
    if (!figures.ok()) {
        std::cerr << "error: fabric fit: " << figures.error().toString() << "\n";
        return EXIT_BAD_INPUT;
    }
    const patterns::FabricFigures& f = figures.value();
    const std::string label = fitting ? o.name : o.base;
    char line[320];
    std::snprintf(line, sizeof line,
                  "%s: %.0f g/m², stretch weft %.4g / warp %.4g N/m, shear %.4g N/m, "
                  "poisson %.3g\n",
                  label.c_str(), 1000 * material.density, material.stretchWeft,
                  material.stretchWarp, material.shear, material.poisson);
    std::cout << line;
    std::snprintf(line, sizeof line,
                  "bending length (ASTM D1388): weft %.1f mm, warp %.1f mm, bias %.1f mm "
                  "(B = %.3g / %.3g / %.3g N·m)\n",
                  1000 * f.bendingLengthWeft, 1000 * f.bendingLengthWarp,
                  1000 * f.bendingLengthBias, f.bendingWeft, f.bendingWarp, f.bendingBias);
    std::cout << line;
    std::snprintf(line, sizeof line, "tensile stiffness on the bias: %.4g N/m\n", f.tensileBias);
    std::cout << line;

    if (!o.out.empty()) {
        const std::string description =
            o.description.empty() ? "fitted by atelier-cli fabric fit" : o.description;
        const std::string source =
            o.source.empty() ? "lab measurements given to atelier-cli fabric fit; what was not "
                               "measured comes from the preset '" +
                                   o.base + "'"
                             : o.source;
        const std::string text = io::formatMaterialPreset(o.name, material, description, source);
        if (auto written = io::writeFileAtomically(o.out, text); !written.ok()) {
            std::cerr << "error: " << written.error().toString() << "\n";
            return EXIT_RUN_FAILED;
        }
        std::cout << "wrote preset \"" << o.name << "\" to " << o.out << "\n";
    }

    if (o.drape) {
        patterns::CusickOptions test;
        test.material = material;
        test.bendingModel = sim::BendingModel::Continuum; // the rigidity is the lab's
        test.particleDistance = o.particleDistance;
        const patterns::CusickResult r = patterns::runCusick(test);
        if (!r.error.empty()) {
            std::cerr << "error: fabric fit: the Cusick drape test: " << r.error << "\n";
            return EXIT_RUN_FAILED;
        }
        std::snprintf(line, sizeof line,
                      "Cusick drape coefficient (300 mm on 180 mm, continuum bending, %.0f mm "
                      "particles, one start): %.3f, %d nodes%s\n",
                      1000 * o.particleDistance, r.drapeCoefficient, r.nodes,
                      r.atRest ? "" : " (not at rest)");
        std::cout << line;
    }
    return EXIT_OK;
}

} // namespace

void addFabricCommand(CLI::App& app) {
    CLI::App* fabric = app.add_subcommand("fabric", "Fabric presets from lab measurements");
    fabric->require_subcommand(1);
    auto o = std::make_shared<FabricFitOptions>();
    CLI::App* cmd = fabric->add_subcommand(
        "fit", "A preset from what a textile lab measures (--out), and the bending lengths and "
               "Cusick drape coefficient a preset will show");
    patterns::LabFabric& lab = o->lab;
    cmd->add_option("--fabric", o->base,
                    "Preset shown, or the one that gives what the lab did not measure")
        ->capture_default_str();
    cmd->add_option("--fabrics", o->fabricsFile,
                    "Preset file to read --fabric from (default: the built-in presets)");
    cmd->add_option("--name", o->name, "Name of the fitted preset")->capture_default_str();
    cmd->add_option("--out,-o", o->out, "Write the fitted preset file (JSON)");
    cmd->add_option("--description", o->description, "Description of the fitted preset");
    cmd->add_option("--source", o->source, "Where the measurements come from");
    cmd->add_option("--density", lab.density, "Areal density [g/m^2]");
    // Lengths in mm and densities in g/m² as lab reports give them; converted in the callback.
    cmd->add_option("--bending-length-weft", lab.bendingLengthWeft,
                    "Bending length, weft strip [mm]");
    cmd->add_option("--bending-length-warp", lab.bendingLengthWarp,
                    "Bending length, warp strip [mm]");
    cmd->add_option("--bending-length-bias", lab.bendingLengthBias,
                    "Bending length, 45° strip [mm]");
    cmd->add_option("--bending-weft", lab.bendingWeft, "Bending rigidity, weft strip [N m]");
    cmd->add_option("--bending-warp", lab.bendingWarp, "Bending rigidity, warp strip [N m]");
    cmd->add_option("--bending-bias", lab.bendingBias, "Bending rigidity, 45° strip [N m]");
    cmd->add_option("--tensile-weft", lab.tensileWeft, "Tensile stiffness, weft [N/m]");
    cmd->add_option("--tensile-warp", lab.tensileWarp, "Tensile stiffness, warp [N/m]");
    cmd->add_option("--tensile-bias", lab.tensileBias, "Tensile stiffness, 45° [N/m]");
    cmd->add_option("--poisson", lab.poisson, "Poisson ratio nu12 [-]");
    auto noDrape = std::make_shared<bool>(false);
    cmd->add_flag("--no-drape", *noDrape, "Skip the Cusick drape test");
    auto particleMm = std::make_shared<double>(10.0);
    cmd->add_option("--particle-distance", *particleMm, "Of the Cusick drape test [mm]")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->callback([o, cmd, noDrape, particleMm] {
        FabricFitOptions run = *o;
        run.densityGiven = cmd->count("--density") > 0;
        run.drape = !*noDrape;
        run.particleDistance = *particleMm / 1000;
        run.lab.density /= 1000; // g/m² → kg/m²
        for (std::optional<double>* c :
             {&run.lab.bendingLengthWeft, &run.lab.bendingLengthWarp, &run.lab.bendingLengthBias}) {
            if (*c) {
                **c /= 1000; // mm → m
            }
        }
        if (const int code = runFabricFit(std::move(run)); code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

} // namespace atelier::app
