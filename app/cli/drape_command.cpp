/// `atelier-cli drape PROJECT.atelier --out DRAPED.obj --report REPORT.json`: mesh the
/// garment's panels, place them around the body, sew and drape until rest; write the draped
/// garment (one group per panel, UVs = pattern coordinates [m], normals), the body beside it
/// (`DRAPED.body.obj`) and a report.

#include "app/cli/commands.h"

#include "io/body_file.h"
#include "io/obj.h"
#include "io/project_file.h"
#include "io/report.h"

#include "patterns/assemble.h"
#include "patterns/drape.h"
#include "patterns/mesh.h"

#include "sim/core/parallel.h"
#include "sim/simulation.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <unistd.h>

namespace atelier::app {

namespace {

struct DrapeOptions {
    std::string project;
    std::string out;
    std::string report;
    int threads = 0;
    double timeLimit = -1;        ///< override of the project's time limit [s]; < 0 = keep
    double particleDistanceMm = -1; ///< override of the project's particle distance [mm]
    std::string framesDir;          ///< write the garment at every frame here (OBJ)
};

/// The draped garment as one OBJ: triangles offset per panel, pattern coordinates as UVs, one
/// group per panel.
struct GarmentObj {
    sim::MatX3i triangles;
    io::ObjWriteOptions options;
};

GarmentObj garmentObj(const patterns::Garment& garment, const patterns::GarmentMesh& mesh,
                      const patterns::AssembledGarment& assembled) {
    GarmentObj out;
    out.triangles.resize(mesh.triangleCount, 3);
    out.options.uvs.resize(assembled.panelOffsets.back(), 2);
    int t = 0;
    for (std::size_t p = 0; p < mesh.panels.size(); ++p) {
        const patterns::PanelMesh& pm = mesh.panels[p];
        const int offset = assembled.panelOffsets[p];
        const int count = static_cast<int>(pm.triangles.rows());
        out.triangles.middleRows(t, count) = pm.triangles.array() + offset;
        out.options.uvs.middleRows(offset, pm.pattern.rows()) = pm.pattern;
        out.options.groups.push_back(io::ObjGroup{garment.panels[p].name, t, count});
        t += count;
    }
    return out;
}

int runDrape(const DrapeOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    auto loaded = io::loadProject(options.project);
    if (!loaded.ok()) {
        std::cerr << "error: " << loaded.error().toString() << "\n";
        return EXIT_BAD_INPUT;
    }
    patterns::Project project = std::move(loaded).value();
    if (options.timeLimit > 0) {
        project.drape.timeLimit = options.timeLimit;
    }
    if (options.particleDistanceMm > 0) {
        project.drape.particleDistance = options.particleDistanceMm / 1000.0;
    }
    if (options.threads > 0) {
        sim::setThreadCount(options.threads);
    }
    const std::filesystem::path projectDir =
        std::filesystem::absolute(options.project).parent_path();
    auto body = io::loadBody(project.body, projectDir, options.project);
    if (!body.ok()) {
        std::cerr << "error: " << body.error().toString() << "\n";
        return EXIT_BAD_INPUT;
    }

    patterns::MeshOptions meshOptions;
    meshOptions.particleDistance = project.drape.particleDistance;
    patterns::GarmentMesh mesh;
    if (auto err = patterns::meshGarment(project.garment, meshOptions, mesh)) {
        std::cerr << "error: " << options.project << ": " << *err << "\n";
        return EXIT_BAD_INPUT;
    }
    for (const std::string& w : mesh.warnings) {
        std::cerr << "warning: " << options.project << ": " << w << "\n";
    }
    std::fprintf(stderr, "drape: %zu panels, %ld triangles (min angle %.1f deg) in %.2f s\n",
                 mesh.panels.size(), mesh.triangleCount, mesh.minAngleDeg, mesh.seconds);

    patterns::AssembledGarment assembled;
    if (auto err = patterns::assembleGarment(project.garment, mesh, body.value(), project.drape,
                                             assembled)) {
        std::cerr << "error: " << options.project << ": " << *err << "\n";
        return EXIT_BAD_INPUT;
    }
    auto simulation = std::make_unique<sim::Simulation>(assembled.scene);
    if (!simulation->error().empty()) {
        std::cerr << "error: " << options.project << ": " << simulation->error() << "\n";
        return EXIT_BAD_INPUT;
    }
    const double startPenetration = simulation->penetration();
    if (startPenetration > 0) {
        std::fprintf(stderr, "warning: the placed garment starts %.4f m inside the body\n",
                     startPenetration);
    }

    const bool tty = ::isatty(STDERR_FILENO) != 0;
    int lastReported = -1;
    GarmentObj frameObj;
    if (!options.framesDir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(options.framesDir, ec);
        if (ec) {
            std::cerr << "error: " << options.framesDir << ": " << ec.message() << "\n";
            return EXIT_BAD_INPUT;
        }
        frameObj = garmentObj(project.garment, mesh, assembled);
    }
    const patterns::DrapeOutcome outcome = patterns::drapeUntilRest(
        *simulation, project.drape, [&](int frame, double t, double ke) {
            if (!options.framesDir.empty()) {
                char name[32];
                std::snprintf(name, sizeof name, "frame_%04d.obj", frame);
                auto written = io::writeObj(std::filesystem::path(options.framesDir) / name,
                                            simulation->positions(), frameObj.triangles,
                                            frameObj.options);
                if (!written.ok()) {
                    std::cerr << "warning: " << written.error().toString() << "\n";
                }
            }
            if (!tty && frame / 15 == lastReported) {
                return;
            }
            lastReported = frame / 15;
            std::fprintf(stderr, "%sdrape: t = %.3f s  kinetic energy/vertex %.2e J  steps %ld  "
                                 "contacts %ld  wall %.1f s%s",
                         tty ? "\r\033[K" : "", t, ke, simulation->stats().steps,
                         simulation->stats().contacts, simulation->stats().wallTime,
                         tty ? "" : "\n");
        });
    if (tty) {
        std::fprintf(stderr, "\n");
    }

    const sim::MatX3& x = simulation->positions();
    const bool finite = simulation->stats().finite && x.allFinite();
    int code = EXIT_OK;
    if (outcome.status == sim::RunStatus::Failed || !finite) {
        const std::string why =
            !simulation->error().empty() ? simulation->error() : simulation->stats().error;
        std::cerr << "error: " << options.project << ": drape failed at t = "
                  << simulation->time() << " s" << (why.empty() ? "" : ": " + why) << "\n";
        code = EXIT_RUN_FAILED;
    } else if (!outcome.rested) {
        std::fprintf(stderr, "drape: not at rest after the time limit (%.2f s simulated)\n",
                     outcome.simulatedTime);
    }

    const std::vector<patterns::ForcedWeld> forced =
        patterns::forcedWelds(project.garment, assembled, simulation->stats().forcedWeldGaps);
    if (simulation->stats().largestForcedWeld > 0.005) {
        std::string seams;
        for (const patterns::ForcedWeld& w : forced) {
            if (w.widest > 0.005) {
                char line[160];
                std::snprintf(line, sizeof line, "%s%s %.1f mm (%d pairs)", seams.empty() ? "" : ", ",
                              w.seam.c_str(), 1000 * w.widest, w.pairs);
                seams += line;
            }
        }
        std::fprintf(stderr,
                     "warning: sewing did not close every seam in %.2f s; welded at its end, "
                     "widest pair per seam: %s (a longer sewing_time_s, panels placed closer, "
                     "or more ease where the garment is tight)\n",
                     project.drape.sewingTime, seams.c_str());
    }
    const double gap = patterns::seamGapMax(assembled, x);
    const double ratio = patterns::areaRatio(assembled.scene, x);
    std::fprintf(stderr,
                 "drape: %s at t = %.2f s in %.1f s wall; seam gap max %.2e m, area ratio "
                 "%.4f\n",
                 outcome.rested ? "at rest" : "stopped", outcome.simulatedTime,
                 outcome.wallSeconds, gap, ratio);

    if (!options.out.empty()) {
        if (finite) {
            GarmentObj obj = garmentObj(project.garment, mesh, assembled);
            obj.options.comment = "atelier-cli drape " + options.project + "\nt = " +
                                  std::to_string(simulation->time()) + " s";
            auto written = io::writeObj(options.out, x, obj.triangles, obj.options);
            if (written.ok()) {
                std::filesystem::path bodyPath = options.out;
                bodyPath.replace_extension(".body.obj");
                io::ObjWriteOptions bodyOptions;
                bodyOptions.comment = "body of atelier-cli drape " + options.project;
                bodyOptions.groups.push_back(
                    io::ObjGroup{"body", 0, static_cast<int>(body.value().triangles.rows())});
                written = io::writeObj(bodyPath, body.value().vertices, body.value().triangles,
                                       bodyOptions);
            }
            if (!written.ok()) {
                std::cerr << "error: " << written.error().toString() << "\n";
                code = code == EXIT_OK ? EXIT_RUN_FAILED : code;
            }
        } else {
            std::cerr << "drape: the state is not finite; " << options.out << " is not written\n";
        }
    }
    if (!options.report.empty()) {
        const double totalSeconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const io::ReportFields extra = {
            {"project", options.project},
            {"status", std::string(outcome.status == sim::RunStatus::Failed ? "failed"
                                   : outcome.rested                         ? "rested"
                                                                            : "time-limit")},
            {"exit_code", static_cast<std::int64_t>(code)},
            {"threads", static_cast<std::int64_t>(sim::threadCount())},
            {"seam_gap_max_m", gap},
            {"area_ratio", ratio},
            {"mesh_min_angle_deg", mesh.minAngleDeg},
            {"triangles", static_cast<std::int64_t>(mesh.triangleCount)},
            {"panels", static_cast<std::int64_t>(mesh.panels.size())},
            {"seam_pairs", static_cast<std::int64_t>(assembled.scene.seams.size())},
            {"welded_seam_pairs", static_cast<std::int64_t>(simulation->stats().weldedSeamPairs)},
            {"largest_forced_weld_m", simulation->stats().largestForcedWeld},
            {"deferred_welds", static_cast<std::int64_t>(simulation->stats().deferredWelds)},
            {"largest_forced_weld_seam",
             forced.empty() ? io::ReportValue(nullptr) : io::ReportValue(forced.front().seam)},
            {"sewn_at_s", simulation->stats().sewingEndTime >= 0
                              ? io::ReportValue(simulation->stats().sewingEndTime)
                              : io::ReportValue(nullptr)},
            {"meshing_time_s", mesh.seconds},
            {"time_to_rest_s", outcome.wallSeconds},
            {"rested", outcome.rested},
            {"sim_time_to_rest_s", outcome.simulatedTime},
            {"kinetic_energy_per_vertex_j", outcome.kineticEnergyPerVertex},
            {"start_penetration_m", startPenetration},
            {"warnings", static_cast<std::int64_t>(mesh.warnings.size())},
            {"total_wall_time_s", totalSeconds},
        };
        auto written = io::writeReport(options.report, *simulation, extra);
        if (!written.ok()) {
            std::cerr << "error: " << written.error().toString() << "\n";
            code = code == EXIT_OK ? EXIT_RUN_FAILED : code;
        }
    }
    return code;
}

} // namespace

void addDrapeCommand(CLI::App& app) {
    auto options = std::make_shared<DrapeOptions>();
    CLI::App* cmd = app.add_subcommand(
        "drape", "Mesh, place, sew and drape a garment project until rest; write the mesh");
    cmd->add_option("project", options->project, "Garment project (.atelier)")->required();
    cmd->add_option("--out,-o", options->out,
                    "Draped garment (OBJ: one group per panel, UV = pattern [m], normals); the "
                    "body goes to OUT.body.obj");
    cmd->add_option("--report,-r", options->report, "Drape report (JSON)");
    cmd->add_option("--threads,-j", options->threads, "Engine threads (default: all cores)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--time-limit", options->timeLimit,
                    "Simulated time limit [s] (default: the project's)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--particle-distance", options->particleDistanceMm,
                    "Mesh particle distance [mm] (default: the project's)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--frames-dir", options->framesDir,
                    "Write the garment at every output frame to DIR/frame_NNNN.obj");
    cmd->callback([options] {
        const int code = runDrape(*options);
        if (code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

} // namespace atelier::app
