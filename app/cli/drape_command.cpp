/// `atelier-cli drape PROJECT.atelier --out DRAPED.obj --report REPORT.json`: mesh the
/// garment's panels, place them around the body, sew and drape until rest; write the draped
/// garment (one group per panel, UVs = pattern coordinates [m], normals), the body beside it
/// (`DRAPED.body.obj`) and a report.

#include "app/cli/commands.h"
#include "app/cli/run_loop.h"

#include "io/body_file.h"
#include "io/obj.h"
#include "io/project_file.h"
#include "io/report.h"

#include "patterns/drape_session.h"

#include "sim/core/parallel.h"
#include "sim/simulation.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

namespace atelier::app {

namespace {

struct DrapeOptions {
    std::string project;
    std::string out;
    std::string report;
    int threads = 0;
    double timeLimit = -1;          ///< override of the project's time limit [s]; < 0 = keep
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

/// The drape session's body provider: the project's mannequin or body mesh (io/).
patterns::BodyProvider projectBodies(const std::string& projectFile) {
    const std::filesystem::path dir = std::filesystem::absolute(projectFile).parent_path();
    return [dir, projectFile](const patterns::BodySource& source) {
        return io::loadBody(source, dir, projectFile);
    };
}

/// The figures behind the report's drape fields.
io::ReportFields drapeReportFields(const DrapeOptions& options,
                                   const patterns::DrapeSession& session,
                                   const patterns::DrapeFigures& f, RunEnd end, int code,
                                   double wallSeconds, double totalSeconds) {
    const sim::RunStats& stats = session.simulation()->stats();
    const std::string status = end == RunEnd::Cancelled ? "cancelled"
                               : end == RunEnd::Failed  ? "failed"
                               : f.rested               ? "rested"
                                                        : "time-limit";
    const auto orNull = [](bool have, double value) {
        return have ? io::ReportValue(value) : io::ReportValue(nullptr);
    };
    return {
        {"project", options.project},
        {"status", status},
        {"phase", std::string(patterns::phaseName(f.phase))},
        {"exit_code", static_cast<std::int64_t>(code)},
        {"threads", static_cast<std::int64_t>(sim::threadCount())},
        {"seam_gap_max_m", f.seamGapMax},
        {"area_ratio", f.areaRatio},
        {"mesh_min_angle_deg", f.minAngleDeg},
        {"triangles", static_cast<std::int64_t>(f.triangles)},
        {"panels", static_cast<std::int64_t>(session.mesh().panels.size())},
        {"seam_pairs", static_cast<std::int64_t>(f.seamPairs)},
        {"welded_seam_pairs", static_cast<std::int64_t>(stats.weldedSeamPairs)},
        {"largest_forced_weld_m", stats.largestForcedWeld},
        {"deferred_welds", static_cast<std::int64_t>(stats.deferredWelds)},
        {"largest_forced_weld_seam", f.forcedWelds.empty()
                                         ? io::ReportValue(nullptr)
                                         : io::ReportValue(f.forcedWelds.front().seam)},
        {"sewn_at_s", orNull(f.sewnAt >= 0, f.sewnAt)},
        {"meshing_time_s", f.meshSeconds},
        // Wall time until rest, only when the drape rested (null otherwise).
        {"time_to_rest_s", orNull(f.rested, wallSeconds)},
        {"drape_wall_time_s", wallSeconds},
        {"rested", f.rested},
        {"sim_time_to_rest_s", f.time},
        {"kinetic_energy_per_vertex_j", f.kineticEnergyPerVertex},
        {"start_penetration_m", f.startPenetration},
        {"warnings", static_cast<std::int64_t>(session.warnings().size())},
        {"total_wall_time_s", totalSeconds},
    };
}

int runDrape(const DrapeOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    RunLoop loop("drape", 0, options.framesDir); // from here on, Ctrl-C stops the drape
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
    loop.setEndTime(project.drape.timeLimit);
    if (!loop.prepare()) {
        return EXIT_BAD_INPUT;
    }

    patterns::DrapeSession session(projectBodies(options.project));
    session.setProject(std::move(project));
    if (auto prepared = session.prepare(); !prepared.ok()) {
        const Error& e = prepared.error();
        std::cerr << "error: " << (e.file.empty() ? options.project + ": " : "") << e.toString()
                  << "\n";
        return EXIT_BAD_INPUT;
    }
    for (const std::string& w : session.warnings()) {
        std::cerr << "warning: " << options.project << ": " << w << "\n";
    }
    const patterns::GarmentMesh& mesh = session.mesh();
    std::fprintf(stderr, "drape: %zu panels, %ld triangles (min angle %.1f deg) in %.2f s\n",
                 mesh.panels.size(), mesh.triangleCount, mesh.minAngleDeg, mesh.seconds);
    if (session.figures().startPenetration > 0) {
        std::fprintf(stderr, "warning: the placed garment starts %.4f m inside the body\n",
                     session.figures().startPenetration);
    }

    const patterns::Garment& garment = session.project().garment;
    const GarmentObj frameObj = garmentObj(garment, mesh, session.assembled());
    session.onFrame([&](long frame, double t, double ke) {
        const sim::RunStats& stats = session.simulation()->stats();
        char figures[160];
        std::snprintf(figures, sizeof figures,
                      "kinetic energy/vertex %.2e J  steps %ld  contacts %ld  wall %.1f s", ke,
                      stats.steps, stats.contacts, stats.wallTime);
        loop.frame(frame, t, figures, [&](const std::filesystem::path& stem) {
            return io::writeObj(stem.string() + ".obj", session.positions(), frameObj.triangles,
                                frameObj.options);
        });
    });
    const auto driveStart = std::chrono::steady_clock::now();
    const RunEnd end = loop.run([&] {
        switch (session.step()) {
        case patterns::DrapeStatus::Running:
            return StepState::Continue;
        case patterns::DrapeStatus::Failed:
            return StepState::Failed;
        default:
            return StepState::Done;
        }
    });
    const double wallSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - driveStart).count();

    const sim::Simulation& simulation = *session.simulation();
    const sim::MatX3& x = simulation.positions();
    const bool finite = simulation.stats().finite && x.allFinite();
    const patterns::DrapeFigures f = session.figures();
    int code = loop.exitCode(end == RunEnd::Done && !finite ? RunEnd::Failed : end);
    if (end == RunEnd::Cancelled) {
        std::fprintf(stderr, "drape: cancelled at t = %.2f s; writing the drape so far\n", f.time);
    } else if (end == RunEnd::Failed || !finite) {
        std::cerr << "error: " << options.project << ": drape failed at t = " << f.time << " s"
                  << (f.error.empty() ? "" : ": " + f.error) << "\n";
    } else if (!f.rested) {
        std::fprintf(stderr, "drape: not at rest after the time limit (%.2f s simulated)\n",
                     f.time);
    }
    std::string seams; // the seams welded more than 5 mm apart when sewing ended
    for (const patterns::ForcedWeld& w : f.forcedWelds) {
        if (w.widest > 0.005) {
            char part[160];
            std::snprintf(part, sizeof part, "%s%s %.1f mm (%d pairs)", seams.empty() ? "" : ", ",
                          w.seam.c_str(), 1000 * w.widest, w.pairs);
            seams += part;
        }
    }
    if (!seams.empty()) {
        std::fprintf(stderr,
                     "warning: sewing did not close every seam in %.2f s; welded at its end, "
                     "widest pair per seam: %s (a longer sewing_time_s, panels placed closer, "
                     "or more ease where the garment is tight)\n",
                     session.project().drape.sewingTime, seams.c_str());
    }
    std::fprintf(stderr,
                 "drape: %s at t = %.2f s in %.1f s wall; seam gap max %.2e m, area ratio "
                 "%.4f\n",
                 f.rested ? "at rest" : "stopped", f.time, wallSeconds, f.seamGapMax, f.areaRatio);

    if (!options.out.empty()) {
        if (finite) {
            GarmentObj obj = garmentObj(garment, mesh, session.assembled());
            obj.options.comment = "atelier-cli drape " + options.project +
                                  "\nt = " + std::to_string(simulation.time()) + " s";
            auto written = io::writeObj(options.out, x, obj.triangles, obj.options);
            if (written.ok()) {
                std::filesystem::path bodyPath = options.out;
                bodyPath.replace_extension(".body.obj");
                io::ObjWriteOptions bodyOptions;
                bodyOptions.comment = "body of atelier-cli drape " + options.project;
                bodyOptions.groups.push_back(
                    io::ObjGroup{"body", 0, static_cast<int>(session.body().triangles.rows())});
                written = io::writeObj(bodyPath, session.body().vertices, session.body().triangles,
                                       bodyOptions);
            }
            if (!written.ok()) {
                code = RunLoop::writeFailed(written.error(), code);
            }
        } else {
            std::cerr << "drape: the state is not finite; " << options.out << " is not written\n";
        }
    }
    if (!options.report.empty()) {
        const double totalSeconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        auto written = io::writeReport(
            options.report, simulation,
            drapeReportFields(options, session, f, end, code, wallSeconds, totalSeconds));
        if (!written.ok()) {
            code = RunLoop::writeFailed(written.error(), code);
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
                    "Write the garment at every output frame to DIR/frame_NNNNN.obj");
    cmd->callback([options] {
        const int code = runDrape(*options);
        if (code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

} // namespace atelier::app
