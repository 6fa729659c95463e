/// `atelier-cli drape PROJECT.atelier --out DRAPED.obj --report REPORT.json`: mesh the
/// garment's panels, place them around the body, sew and drape until rest; write the draped
/// garment (one surface, welded seam vertices once; one group and material per panel, UVs =
/// pattern coordinates [m], normals; OBJ + MTL, glTF binary, FBX or PLY), the body beside it
/// (`DRAPED.body.obj`), a report and, with `--thumbnail`, a picture of the drape.

#include "app/cli/commands.h"
#include "app/cli/drape.h"
#include "app/cli/limits_option.h"
#include "app/cli/picture.h"
#include "app/cli/run_loop.h"

#include "io/body_file.h"
#include "io/mesh_export.h"
#include "io/obj.h"
#include "io/project_file.h"
#include "io/report.h"

#include "patterns/assemble.h"
#include "patterns/drape_session.h"
#include "patterns/fit.h"

#include "sim/core/parallel.h"
#include "sim/simulation.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

namespace atelier::app {

std::filesystem::path drapedBodyPath(const std::filesystem::path& out) {
    std::filesystem::path path = out;
    return path.replace_extension(".body.obj");
}

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

namespace {

/// The format of --out: --format, else its extension; nullopt when neither names one.
std::optional<io::MeshFormat> outputFormat(const DrapeOptions& options) {
    return options.format.empty() ? io::meshFormatOfPath(options.out)
                                  : io::parseMeshFormat(options.format);
}

/// The checks before any work (exit 2 with the message): outputs against the inputs (the
/// project and its body mesh) and each other, and the estimated mesh size.
std::optional<std::string> checkBeforeWork(const DrapeOptions& options,
                                           const patterns::Project& project) {
    std::vector<NamedPath> inputs = {{"project", options.project}};
    if (!project.body.meshPath.empty()) {
        inputs.push_back(
            {"the project's body mesh",
             std::filesystem::absolute(options.project).parent_path() / project.body.meshPath});
    }
    std::vector<NamedPath> outputs = {
        {"--out", options.out}, {"--report", options.report}, {"--thumbnail", options.thumbnail}};
    outputs.insert(outputs.end(), options.laterOutputs.begin(), options.laterOutputs.end());
    std::optional<io::MeshFormat> format;
    if (!options.out.empty()) {
        outputs.push_back({"--out (its body)", drapedBodyPath(options.out)});
        format = outputFormat(options);
        if (format == io::MeshFormat::Obj) {
            outputs.push_back(
                {"--out (its materials)", io::exportedFiles(options.out, *format)[1]});
        }
    }
    if (!options.alsoOut.empty() && options.out.empty()) {
        return "--also-out needs --out";
    }
    for (const std::string& extra : options.alsoOut) {
        outputs.push_back({"--also-out", extra});
        const auto extraFormat = io::meshFormatOfPath(extra);
        if (!extraFormat) {
            return "--also-out " + extra +
                   ": unknown mesh format extension (formats: " + io::meshFormatList() + ")";
        }
        if (*extraFormat == io::MeshFormat::Obj) {
            outputs.push_back(
                {"--also-out (its materials)", io::exportedFiles(extra, *extraFormat)[1]});
        }
    }
    if (auto problem = checkOutputs(inputs, outputs)) {
        return problem;
    }
    if (!options.out.empty() && !format) {
        return "--out " + options.out + ": unknown mesh format " +
               (options.format.empty() ? "extension (.obj, .glb, .fbx, .ply; or --format)"
                                       : "\"" + options.format + "\"") +
               " (formats: " + io::meshFormatList() + ")";
    }
    inputs.insert(inputs.end(), outputs.begin(), outputs.end());
    if (auto problem = checkOutputFolder({"--frames-dir", options.framesDir}, inputs)) {
        return problem;
    }
    const double h = project.drape.particleDistance;
    char what[96];
    std::snprintf(what, sizeof what, "the garment meshed at a particle distance of %g mm",
                  1000 * h);
    return checkVertexLimit(what, patterns::estimateGarmentMesh(project.garment, h).vertices,
                            options.maxVertices);
}

/// The drape session's body provider: the project's mannequin or body mesh (io/), or the
/// caller's body.
patterns::BodyProvider projectBodies(const DrapeOptions& options, const io::Limits& limits) {
    if (options.body) {
        return [body = *options.body](const patterns::BodySource&) {
            return Result<patterns::Body>(body);
        };
    }
    const std::string& projectFile = options.project;
    const std::filesystem::path dir = std::filesystem::absolute(projectFile).parent_path();
    return [dir, projectFile, limits](const patterns::BodySource& source) {
        std::vector<std::string> warnings;
        auto body = io::loadBody(source, dir, projectFile, limits, &warnings);
        for (const std::string& w : warnings) {
            std::cerr << "warning: " << w << "\n";
        }
        return body;
    };
}

/// The figures behind the report's drape fields.
io::ReportFields drapeReportFields(const DrapeOptions& options,
                                   const patterns::DrapeSession& session,
                                   const patterns::DrapeFigures& f, const patterns::GarmentFit& fit,
                                   RunEnd end, int code, const std::vector<std::string>& warnings,
                                   double wallSeconds, double totalSeconds) {
    const sim::RunStats& stats = session.simulation()->stats();
    const patterns::FoldFigures folds =
        patterns::foldFigures(session.assembled(), session.simulation()->positions());
    const auto degrees = [](double radians) { return radians * 180.0 / std::numbers::pi; };
    const std::string status = end == RunEnd::Cancelled ? "cancelled"
                               : end == RunEnd::Failed  ? "failed"
                               : f.rested               ? "rested"
                                                        : "time-limit";
    const auto orNull = [](bool have, double value) {
        return have ? io::ReportValue(value) : io::ReportValue(nullptr);
    };
    std::vector<std::string> lifts;
    for (const patterns::PlacementLift& l : f.placementLifts) {
        lifts.push_back(patterns::liftText(l));
    }
    std::vector<std::string> panelLines;
    for (const patterns::PanelStrain& p : fit.panels) {
        char line[200];
        std::snprintf(line, sizeof line,
                      "%s: strain up to %.4f at %.3f m height; area beyond 5%%: %.4f, beyond "
                      "10%%: %.4f",
                      p.panel.c_str(), p.maxStrain, p.maxHeight, p.over5, p.over10);
        panelLines.emplace_back(line);
    }
    return {
        {"project", options.project},
        {"status", status},
        {"interrupted", end == RunEnd::Cancelled},
        {"signal", end == RunEnd::Cancelled
                       ? io::ReportValue(std::string(InterruptGuard::signalName()))
                       : io::ReportValue(nullptr)},
        {"phase", std::string(patterns::phaseName(f.phase))},
        {"exit_code", static_cast<std::int64_t>(code)},
        {"threads", static_cast<std::int64_t>(sim::threadCount())},
        {"seam_gap_max_m", f.seamGapMax},
        {"area_ratio", f.areaRatio},
        // Folds across the seams between panels and inside them (patterns::FoldFigures).
        {"seam_edges", static_cast<std::int64_t>(folds.seamEdges)},
        {"seam_fold_median_deg", degrees(folds.seamMedian)},
        {"seam_fold_max_deg", degrees(folds.seamMax)},
        {"cloth_fold_median_deg", degrees(folds.clothMedian)},
        // How far the panels are stretched and whether the garment fits (patterns/fit.h).
        {"fit", std::string(patterns::fitName(fit.verdict.fit))},
        {"fit_message", fit.verdict.message},
        {"strain_max", fit.largestStrain()},
        {"strain_beyond_10pct_share_max", fit.largestShareBeyond10()},
        {"panel_strain", panelLines},
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
        {"sim_time_to_rest_s", orNull(f.rested, f.restTime)},
        {"drape_time_s", f.time}, // simulated time reached, however the drape ended
        {"kinetic_energy_per_vertex_j", f.kineticEnergyPerVertex},
        {"start_penetration_m", f.startPenetration},
        {"start_intersecting_pairs", static_cast<std::int64_t>(f.startIntersectingPairs)},
        {"placed_crossings", static_cast<std::int64_t>(f.placedCrossings)},
        {"placement_lifts", lifts},
        {"pins", static_cast<std::int64_t>(f.pins)},
        // Largest distance of a pinned vertex from where its pin holds it: 0 when pins hold.
        {"pin_displacement_max_m", f.pinDisplacementMax},
        {"warnings", static_cast<std::int64_t>(warnings.size())},
        {"warning_messages", warnings},
        {"total_wall_time_s", totalSeconds},
    };
}

/// The warnings of a prepared drape: meshing (seam ease), a start inside the body and a start
/// crossing itself.
std::vector<std::string> preparedWarnings(const patterns::DrapeSession& session) {
    std::vector<std::string> out = session.warnings();
    const patterns::DrapeFigures f = session.figures();
    char text[200];
    if (f.startPenetration > 0) {
        std::snprintf(text, sizeof text, "the placed garment starts %.4f m inside the body",
                      f.startPenetration);
        out.emplace_back(text);
    }
    if (!f.placementLifts.empty()) {
        std::string lifted;
        for (const patterns::PlacementLift& l : f.placementLifts) {
            lifted += (lifted.empty() ? "" : "; ") + patterns::liftText(l);
        }
        std::snprintf(text, sizeof text,
                      "panels placed through each other (%ld intersecting triangle pairs) were "
                      "moved apart on their slots: ",
                      f.placedCrossings);
        out.push_back(text + lifted);
    }
    if (f.startIntersectingPairs > 0) {
        std::snprintf(text, sizeof text,
                      "the placed garment starts with %ld intersecting triangle pairs: panels "
                      "placed through each other stay crossed (place them apart: slot, offset, "
                      "clearance)",
                      f.startIntersectingPairs);
        out.emplace_back(text);
    }
    return out;
}

/// The warnings of sewing: seams welded by force more than 5 mm apart, and, once sewing is
/// over, seam pairs still not welded (each weld put off because it would carry cloth through
/// cloth).
std::vector<std::string> sewingWarnings(const patterns::DrapeSession& session,
                                        const patterns::DrapeFigures& f) {
    std::vector<std::string> out;
    char text[320];
    std::string seams; // the seams welded more than 5 mm apart when sewing ended
    for (const patterns::ForcedWeld& w : f.forcedWelds) {
        if (w.widest > 0.005) {
            std::snprintf(text, sizeof text, "%s%s %.1f mm (%d pairs)", seams.empty() ? "" : ", ",
                          w.seam.c_str(), 1000 * w.widest, w.pairs);
            seams += text;
        }
    }
    if (!seams.empty()) {
        std::snprintf(text, sizeof text, "%.2f s", session.project().drape.sewingTime);
        out.push_back("sewing did not close every seam in " + std::string(text) +
                      "; welded at its end, widest pair per seam: " + seams +
                      " (a longer sewing_time_s, panels placed closer, or more ease where the "
                      "garment is tight)");
    }
    std::string list;
    for (const patterns::ForcedWeld& w : session.openSeams()) {
        std::snprintf(text, sizeof text, "%s%s: %d pairs, widest %.1f mm", list.empty() ? "" : ", ",
                      w.seam.c_str(), w.pairs, 1000 * w.widest);
        list += text;
    }
    if (!list.empty()) {
        out.push_back("seam pairs not welded after sewing (each weld would have carried "
                      "cloth through cloth): " +
                      list);
    }
    return out;
}

/// Writes the draped garment and the body beside it; returns the exit code.
int writeDrapedMeshes(const DrapeOptions& options, const patterns::DrapeSession& session,
                      int code) {
    const sim::Simulation& simulation = *session.simulation();
    GarmentObj obj = garmentObj(session.project().garment, session.mesh(), session.assembled());
    // One surface: the vertices of each welded seam pair are one vertex (with a UV in each
    // panel); --split-panels keeps every panel's own.
    std::vector<std::pair<int, int>> welds;
    if (!options.splitPanels) {
        const auto& pairs = session.assembled().scene.seams;
        for (std::size_t k = 0; k < pairs.size(); ++k) {
            if (simulation.seamPairWelded(k)) {
                welds.emplace_back(pairs[k].a, pairs[k].b);
            }
        }
    }
    io::SurfaceMesh surface = io::weldedSurface(simulation.positions(), obj.triangles,
                                                obj.options.uvs, obj.options.groups, welds);
    surface.comment = "atelier-cli drape " + options.project +
                      "\nt = " + std::to_string(simulation.time()) + " s";
    auto written = io::exportMesh(options.out, surface, *outputFormat(options));
    for (const std::string& extra : options.alsoOut) {
        if (written.ok()) {
            written = io::exportMesh(extra, surface, *io::meshFormatOfPath(extra));
        }
    }
    if (written.ok()) {
        io::ObjWriteOptions bodyOptions;
        bodyOptions.comment = "body of atelier-cli drape " + options.project;
        bodyOptions.groups.push_back(
            io::ObjGroup{"body", 0, static_cast<int>(session.body().triangles.rows())});
        written = io::writeObj(drapedBodyPath(options.out), session.body().vertices,
                               session.body().triangles, bodyOptions);
    }
    return written.ok() ? code : RunLoop::writeFailed(written.error(), code);
}

/// Loads the project with the command line's overrides, and checks it before any work; exit
/// code 2 in `code` when it cannot go on.
std::optional<patterns::Project> loadDrapeProject(const DrapeOptions& options,
                                                  const io::Limits& limits, int& code) {
    code = EXIT_BAD_INPUT;
    auto loaded = io::loadProject(options.project, limits);
    if (!loaded.ok()) {
        std::cerr << inputErrorText(loaded.error());
        return std::nullopt;
    }
    patterns::Project project = std::move(loaded).value();
    if (options.timeLimit > 0) {
        project.drape.timeLimit = options.timeLimit;
    }
    if (options.particleDistanceMm > 0) {
        project.drape.particleDistance = options.particleDistanceMm / 1000.0;
    }
    if (const auto solver = sim::linearSolverFromName(options.linearSolver)) {
        project.drape.linearSolver = *solver;
    }
    if (auto problem = checkBeforeWork(options, project)) {
        std::cerr << "error: " << *problem << "\n";
        return std::nullopt;
    }
    code = EXIT_OK;
    return project;
}

} // namespace

int runDrape(const DrapeOptions& options, const DrapeFinished& finished) {
    const auto start = std::chrono::steady_clock::now();
    RunLoop loop("drape", 0, options.framesDir); // from here on, a signal stops the drape
    const std::optional<io::Limits> limits = limitsOrReport(options.limits);
    if (!limits) {
        return EXIT_BAD_INPUT;
    }
    int code = EXIT_OK;
    std::optional<patterns::Project> project = loadDrapeProject(options, *limits, code);
    if (!project) {
        return code;
    }
    if (options.threads > 0) {
        sim::setThreadCount(options.threads);
    }
    loop.setEndTime(project->drape.timeLimit);
    if (!loop.prepare()) {
        return EXIT_BAD_INPUT;
    }

    patterns::DrapeSession session(projectBodies(options, *limits));
    session.setInteractive(options.interactive);
    session.setSettlingStep(options.settlingStep);
    if (!options.linearSolver.empty()) {
        session.setSettlingSolver(std::nullopt); // the one given, throughout
    }
    session.setProject(std::move(*project));
    if (auto prepared = session.prepare(); !prepared.ok()) {
        const Error& e = prepared.error();
        std::cerr << "error: " << (e.file.empty() ? options.project + ": " : "") << e.toString()
                  << "\n";
        return EXIT_BAD_INPUT;
    }
    std::vector<std::string> warnings = preparedWarnings(session);
    for (const std::string& w : warnings) {
        std::cerr << "warning: " << options.project << ": " << w << "\n";
    }
    const patterns::GarmentMesh& mesh = session.mesh();
    std::fprintf(stderr, "drape: %zu panels, %ld triangles (min angle %.1f deg) in %.2f s\n",
                 mesh.panels.size(), mesh.triangleCount, mesh.minAngleDeg, mesh.seconds);

    const GarmentObj frameObj = garmentObj(session.project().garment, mesh, session.assembled());
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
    const bool finite = simulation.stats().finite && simulation.positions().allFinite();
    const patterns::DrapeFigures f = session.figures();
    code = loop.exitCode(end == RunEnd::Done && !finite ? RunEnd::Failed : end);
    if (end == RunEnd::Cancelled) {
        std::fprintf(stderr, "drape: interrupted (%s) at t = %.2f s; writing the drape so far\n",
                     InterruptGuard::signalName(), f.time);
    } else if (end == RunEnd::Failed || !finite) {
        std::cerr << "error: " << options.project << ": drape failed at t = " << f.time << " s"
                  << (f.error.empty() ? "" : ": " + f.error) << "\n";
    } else if (!f.rested) {
        std::fprintf(stderr, "drape: not at rest after the time limit (%.2f s simulated)\n",
                     f.time);
    }
    if (const sim::RunStats& stats = simulation.stats(); stats.unconvergedSolves > 0) {
        char text[200];
        std::snprintf(text, sizeof text,
                      "%ld of %ld linear solves ended above their tolerance (%ld at the iteration "
                      "cap), worst relative residual %.2e",
                      stats.unconvergedSolves, stats.linearSolves, stats.cappedSolves,
                      stats.worstRelativeResidual);
        std::cerr << "warning: " << options.project << ": " << text << "\n";
        warnings.emplace_back(text);
    }
    for (std::string& w : sewingWarnings(session, f)) {
        std::cerr << "warning: " << options.project << ": " << w << "\n";
        warnings.push_back(std::move(w));
    }
    std::fprintf(stderr,
                 "drape: %s at t = %.2f s in %.1f s wall; seam gap max %.2e m, area ratio "
                 "%.4f\n",
                 f.rested ? "at rest" : "stopped", f.time, wallSeconds, f.seamGapMax, f.areaRatio);
    const patterns::GarmentFit fit = session.fit();
    std::fprintf(stderr, "drape: %s%s%s\n", std::string(patterns::fitName(fit.verdict.fit)).c_str(),
                 fit.verdict.message.empty() ? "" : ": ", fit.verdict.message.c_str());

    if (!options.out.empty()) {
        if (finite) {
            code = writeDrapedMeshes(options, session, code);
        } else {
            std::cerr << "drape: the state is not finite; " << options.out << " is not written\n";
        }
    }
    if (finite && !options.thumbnail.empty()) {
        code = writeThumbnail(sessionGarment(session), options.thumbnail, code);
    }
    if (finite && finished) {
        code = finished(session, code);
    }
    if (!options.report.empty()) {
        const double totalSeconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        auto written = io::writeReport(options.report, simulation,
                                       drapeReportFields(options, session, f, fit, end, code,
                                                         warnings, wallSeconds, totalSeconds));
        if (!written.ok()) {
            code = RunLoop::writeFailed(written.error(), code);
        }
    }
    return code;
}

void addDrapeCommand(CLI::App& app) {
    auto options = std::make_shared<DrapeOptions>();
    CLI::App* cmd = app.add_subcommand(
        "drape", "Mesh, place, sew and drape a garment project until rest; write the mesh");
    cmd->add_option("project", options->project, "Garment project (.atelier)")->required();
    cmd->add_option("--out,-o", options->out,
                    "Draped garment, one surface (welded seam vertices once), the format by "
                    "extension: .obj (+ .mtl; one group and material per panel, UV = pattern "
                    "[m], normals), .glb, .fbx, .ply; the body goes to OUT.body.obj");
    cmd->add_option("--format", options->format,
                    "Format of --out whatever its extension: " + io::meshFormatList())
        ->check(CLI::IsMember({"obj", "glb", "fbx", "fbx-ascii", "ply"}));
    cmd->add_option("--also-out", options->alsoOut,
                    "The same draped garment in further files, each in the format of its "
                    "extension (repeatable)");
    cmd->add_flag("--split-panels", options->splitPanels,
                  "Keep each panel's own vertices along the seams in --out");
    cmd->add_option("--report,-r", options->report, "Drape report (JSON)");
    cmd->add_option("--thumbnail", options->thumbnail,
                    "A 256x256 three-quarter picture of the drape (PNG)");
    cmd->add_option("--threads,-j", options->threads, "Engine threads (default: all cores)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--time-limit", options->timeLimit,
                    "Simulated time limit [s] (default: the project's)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--particle-distance", options->particleDistanceMm,
                    "Mesh particle distance [mm] (default: the project's)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--linear-solver", options->linearSolver,
                    "Implicit solve's preconditioner, throughout (default: the project's; "
                    "--interactive settles with block-ic0 once sewn)")
        ->check(CLI::IsMember({"block-jacobi", "block-ic0"}));
    cmd->add_flag("--interactive", options->interactive,
                  "Step as the window does (the project's step, enlarged on coarse meshes; "
                  "block-ic0 once sewn; one step a frame once sewn and slow)");
    cmd->add_flag("--no-settling-step{false}", options->settlingStep,
                  "With --interactive: keep the sewing step once sewn");
    cmd->add_option("--frames-dir", options->framesDir,
                    "Write the garment at every output frame to DIR/frame_NNNNN.obj");
    cmd->add_option("--max-vertices", options->maxVertices,
                    "Refuse a garment whose mesh is estimated larger than this")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    addLimitOption(cmd, &options->limits);
    cmd->callback([options] {
        const int code = runDrape(*options);
        if (code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

} // namespace atelier::app
