/// `atelier-cli bench`: benchmarks of the engine as subcommands. Only the CLI11 parsing lives
/// here; the work is in bench_work_precision.cpp and bench_material.cpp (plain C++).

#include "app/cli/bench_cantilever.h"
#include "app/cli/bench_cusick.h"
#include "app/cli/bench_drape.h"
#include "app/cli/bench_material.h"
#include "app/cli/bench_work_precision.h"
#include "app/cli/commands.h"
#include "app/cli/limits_option.h"

#include "io/materials.h"

#include "sim/simulation.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <array>
#include <iostream>
#include <memory>
#include <string>

namespace atelier::app {

namespace {

void addWorkPrecision(CLI::App& bench) {
    auto o = std::make_shared<WorkPrecisionOptions>();
    CLI::App* cmd = bench.add_subcommand(
        "work-precision",
        "Every integrator over a sweep of steps/tolerances: wall time and force evaluations "
        "against the end-position error relative to a tight rk45 reference (CSV, SVG)");
    cmd->add_option("scene", o->scene, "Scene file (JSON)")->required()->check(CLI::ExistingFile);
    cmd->add_option("--out,-o", o->out, "CSV output")->required();
    cmd->add_option("--plot", o->plot, "SVG plot: RMS error against wall time, log-log");
    cmd->add_option("--duration", o->duration, "Simulated time [s] (default: the scene's)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--integrators", o->integrators,
                    "Integrators to sweep (default: euler midpoint rk4 rk45 implicit-euler)")
        ->delimiter(',');
    cmd->add_option("--min-dt", o->minDt, "Smallest fixed step of the sweep [s]")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--min-tolerance", o->minTolerance, "Tightest rk45 tolerance [m]")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--reference-tolerance", o->referenceTolerance,
                    "Tolerance of the rk45 reference run [m]")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--reference-max-dt", o->referenceMaxDt,
                    "Largest step of the reference run [s]")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--max-steps", o->maxSteps, "Skip fixed steps that need more steps than this")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    addLimitOption(cmd, &o->limits);
    cmd->add_option("--max-run-seconds", o->maxRunSeconds,
                    "Stop a run after this wall time; it counts as unstable [s]")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--threads,-j", o->threads, "Engine threads (default: all cores)")
        ->check(CLI::PositiveNumber);
    cmd->callback([o] {
        if (const int code = runWorkPrecision(*o); code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

void addCantilever(CLI::App& bench) {
    auto o = std::make_shared<CantileverBenchOptions>();
    CLI::App* cmd = bench.add_subcommand(
        "cantilever",
        "Peirce's heavy cantilever (ASTM D1388): a strip clamped along one short edge, settled "
        "under gravity, tip-line angle and tip drop against the exact heavy elastica (CSV, SVG)");
    cmd->add_option("--ratios", o->ratios, "Values of rho g L^3 / B")
        ->delimiter(',')
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--particle-distance", o->particleDistancesMm, "Particle distances [mm]")
        ->delimiter(',')
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--mesh", o->meshes, "Meshes: regular, irregular, rotated (45 deg to weft)")
        ->delimiter(',')
        ->capture_default_str()
        ->check(CLI::IsMember({"regular", "irregular", "rotated"}));
    auto bendingModel = std::make_shared<std::string>("continuum");
    cmd->add_option("--bending-model", *bendingModel,
                    "continuum (bending_n_m is the plate's rigidity) or hinge (per-hinge "
                    "coefficient, discrete shells)")
        ->capture_default_str()
        ->check(CLI::IsMember({"continuum", "hinge"}));
    cmd->add_option("--out,-o", o->out, "Output folder (cantilever.csv, cantilever.svg)")
        ->required();
    CantileverOptions& s = o->scene;
    cmd->add_option("--length", s.length, "Overhang L [m]")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--width", s.width, "Strip width [m]")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    s.material.density = 0.12;
    cmd->add_option("--density", s.material.density, "Areal density [kg/m^2]")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--dt", s.dt, "Implicit Euler step [s]")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->callback([o, bendingModel] {
        o->scene.bendingModel = *sim::bendingModelFromName(*bendingModel);
        if (const int code = runCantileverBench(*o); code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

void addMaterial(CLI::App& bench) {
    auto o = std::make_shared<MaterialBenchOptions>();
    CLI::App* cmd = bench.add_subcommand(
        "tensile",
        "Quasi-static uniaxial tension test of a stretch model on a strip cut along the weft, "
        "the warp or the bias: measured stretch stiffness and Poisson ratio against the "
        "orthotropic plate's (JSON; also `bench material`)");
    cmd->alias("material");
    // Names are kept as strings (the transformers of CLI11 print enum values as numbers in
    // their error messages) and converted in the callback.
    auto names = std::make_shared<std::array<std::string, 3>>(
        std::array<std::string, 3>{"", "regular", "weft"});
    TensionTestOptions& t = o->test;
    cmd->add_option("--model", (*names)[0], "Stretch model")
        ->required()
        ->check(CLI::IsMember({"springs", "volino", "fem"}));
    cmd->add_option("--mesh", (*names)[1], "Triangulation of the strip")
        ->capture_default_str()
        ->check(CLI::IsMember({"regular", "irregular"}));
    cmd->add_option("--direction", (*names)[2], "Pull along weft (x), warp (y) or bias (45°)")
        ->capture_default_str()
        ->check(CLI::IsMember({"weft", "warp", "bias"}));
    cmd->add_option("--out,-o", o->out, "JSON output (default: stdout)");
    cmd->add_option("--strain", t.strain, "Imposed strain along the pull [-]")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--weft", t.material.stretchWeft, "Weft stretch stiffness [N/m]")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--warp", t.material.stretchWarp, "Warp stretch stiffness [N/m]")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--shear", t.material.shear, "Shear stiffness [N/m]")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--poisson", t.material.poisson, "Poisson ratio nu12 [-]")
        ->capture_default_str()
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--knee", t.material.stretchKnee,
                    "Stiffening law (fem): Green strain beyond which it stiffens [-] (0 = linear)")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 0.999999));
    cmd->add_option("--weft-beyond", t.material.stretchWeftBeyond,
                    "Stiffening law (fem): weft tangent stiffness beyond the knee [N/m]")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--warp-beyond", t.material.stretchWarpBeyond,
                    "Stiffening law (fem): warp tangent stiffness beyond the knee [N/m]")
        ->check(CLI::NonNegativeNumber);
    CLI::Option* fabric =
        cmd->add_option("--fabric", o->fabric,
                        "Take the stretch parameters (and stiffening law) from this built-in "
                        "preset instead of --weft, --warp, --shear, --poisson and the law's");
    for (const char* name :
         {"--weft", "--warp", "--shear", "--poisson", "--knee", "--weft-beyond", "--warp-beyond"}) {
        fabric->excludes(name);
    }
    cmd->add_option("--cells", t.cellsLong, "Cells along the pull (half as many across)")
        ->capture_default_str()
        ->check(CLI::PositiveNumber)
        ->each([o](const std::string& s) { o->test.cellsWide = std::max(1, std::stoi(s) / 2); });
    cmd->add_option("--seed", t.seed, "Seed of the irregular triangulation")->capture_default_str();
    cmd->add_flag("--cross-springs", t.crossSprings, "springs: add cross springs over hinges");
    cmd->callback([o, names] {
        o->test.model = *sim::stretchModelFromName((*names)[0]);
        o->test.triangulation = (*names)[1] == "irregular" ? sim::Triangulation::Irregular
                                                           : sim::Triangulation::Regular;
        o->test.direction = (*names)[2] == "warp"   ? PullDirection::Warp
                            : (*names)[2] == "bias" ? PullDirection::Bias
                                                    : PullDirection::Weft;
        if (!o->fabric.empty()) {
            const io::MaterialPresets& presets = io::builtinMaterialPresets();
            const auto it = presets.find(o->fabric);
            if (it == presets.end()) {
                std::cerr << "error: bench tensile: no built-in preset '" << o->fabric
                          << "' (assets/materials/fabrics.json)\n";
                throw CLI::RuntimeError(EXIT_BAD_INPUT);
            }
            o->test.material = it->second;
        }
        if (const int code = runMaterialBench(*o); code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

void addDrape(CLI::App& bench) {
    auto o = std::make_shared<DrapeBenchOptions>();
    CLI::App* cmd = bench.add_subcommand(
        "drape", "A project draped step by step as a window drapes it: simulated seconds per "
                 "wall second, step times, with a snapshot reader and busy cores if asked (JSON)");
    cmd->add_option("project", o->project, "Garment project (.atelier)")
        ->required()
        ->check(CLI::ExistingFile);
    cmd->add_option("--out,-o", o->out, "JSON output (default: stdout)");
    cmd->add_option("--particle-distance", o->particleDistanceMm,
                    "Mesh particle distance [mm] (default: the project's)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--time-limit", o->timeLimit,
                    "Simulated time limit [s] (default: the project's)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--dt", o->dt,
                    "Step [s] (default: the window's, the project's enlarged on coarse meshes)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--linear-solver", o->linearSolver,
                    "Implicit solve's preconditioner, throughout (default: the project's while "
                    "sewing, then block-ic0 as the window; with --dt the project's throughout)")
        ->check(CLI::IsMember({"block-jacobi", "block-ic0"}));
    cmd->add_flag("--no-settling-step{false}", o->settlingStep,
                  "Keep the sewing step once sewn (default: one step a frame while the garment "
                  "is slow, as the window)");
    cmd->add_option("--threads,-j", o->threads, "Engine threads (default: all cores)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--reader-hz", o->readerHz,
                    "Another thread reads a snapshot this many times a second (a viewport: 60)")
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--busy", o->busy, "Processes that each keep a core busy meanwhile")
        ->check(CLI::Range(0, 64));
    cmd->add_option("--max-vertices", o->maxVertices,
                    "Refuse a garment whose mesh is estimated larger than this")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    addLimitOption(cmd, &o->limits);
    cmd->add_option("--spin-us", o->spinUs,
                    "The engine threads' spin before sleeping [us] (default: the pool's)")
        ->check(CLI::NonNegativeNumber);
    cmd->callback([o] {
        if (const int code = runDrapeBench(*o); code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

void addCusick(CLI::App& bench) {
    auto o = std::make_shared<CusickBenchOptions>();
    CLI::App* cmd = bench.add_subcommand(
        "cusick", "Cusick drape test of a fabric preset (300 mm specimen on a 180 mm disc): "
                  "drape coefficient and nodes over a few perturbed starts, a top view (SVG)");
    auto particleMm = std::make_shared<double>(10.0);
    cmd->add_option("--fabric", o->fabric, "Fabric preset")->capture_default_str();
    cmd->add_option("--particle-distance", *particleMm, "Particle distance [mm]")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--starts", o->starts, "Perturbed starts")
        ->capture_default_str()
        ->check(CLI::Range(1, 100));
    cmd->add_option("--max-time", o->test.maxTime, "Give up settling after [s]")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    cmd->add_option("--out,-o", o->out, "Folder for cusick.csv, cusick.json and cusick.svg");
    cmd->callback([o, particleMm] {
        o->test.particleDistance = *particleMm / 1000;
        if (const int code = runCusickBench(*o); code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

} // namespace

void addBenchCommand(CLI::App& app) {
    CLI::App* bench =
        app.add_subcommand("bench", "Benchmarks: integrator work-precision, "
                                    "material tension test, heavy cantilever, interactive drape, "
                                    "Cusick drape");
    bench->require_subcommand(1);
    addWorkPrecision(*bench);
    addMaterial(*bench);
    addCantilever(*bench);
    addDrape(*bench);
    addCusick(*bench);
}

} // namespace atelier::app
