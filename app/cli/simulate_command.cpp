/// `atelier-cli simulate`: load a scene file, run it to its duration, write the final mesh
/// (OBJ, one group per cloth, UVs = rest coordinates [m]), the obstacles at the end (OBJ, one
/// group per obstacle) and a JSON report.

#include "app/cli/commands.h"
#include "app/cli/limits_option.h"
#include "app/cli/preflight.h"
#include "app/cli/run_loop.h"

#include "io/obj.h"
#include "io/report.h"
#include "io/scene_file.h"

#include "sim/collision/obstacle.h"
#include "sim/core/parallel.h"
#include "sim/simulation.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace atelier::app {

namespace {

struct SimulateOptions {
    std::string scene;
    std::string out;
    std::string report;
    int threads = 0; ///< 0 = the engine's default (all cores)
    std::string framesDir;
    long maxVertices = DEFAULT_MAX_VERTICES; ///< refuse scenes with more cloth vertices
    std::vector<std::string> limits;         ///< --limit NAME=VALUE
};

/// The whole scene as one mesh: triangles offset per cloth, rest coordinates as UVs, one group
/// per cloth.
struct CombinedMesh {
    sim::MatX3i triangles;
    io::ObjWriteOptions options;
};

CombinedMesh combinedMesh(const sim::Simulation& simulation) {
    const sim::SceneSpec& scene = simulation.scene();
    const std::vector<int>& offsets = simulation.clothOffsets();
    int triangleCount = 0;
    for (const sim::ClothSpec& cloth : scene.cloths) {
        triangleCount += cloth.mesh.triangleCount();
    }
    CombinedMesh out;
    out.triangles.resize(triangleCount, 3);
    out.options.uvs.resize(offsets.back(), 2);
    int t = 0;
    for (std::size_t c = 0; c < scene.cloths.size(); ++c) {
        const sim::ClothMesh& mesh = scene.cloths[c].mesh;
        const int offset = offsets[c];
        out.triangles.middleRows(t, mesh.triangleCount()) = mesh.triangles.array() + offset;
        out.options.uvs.middleRows(offset, mesh.vertexCount()) = mesh.rest;
        out.options.groups.push_back(io::ObjGroup{scene.cloths[c].name, t, mesh.triangleCount()});
        t += mesh.triangleCount();
    }
    return out;
}

/// All obstacles as one mesh, one group per obstacle; positions are taken when written.
struct ObstacleMesh {
    sim::MatX3i triangles;
    io::ObjWriteOptions options;
    bool moves = false; ///< some obstacle moves (keys with different poses, or frames)
};

ObstacleMesh obstacleMesh(const sim::SceneSpec& scene) {
    ObstacleMesh out;
    int vertexCount = 0;
    int triangleCount = 0;
    for (const sim::ObstacleSpec& obstacle : scene.obstacles) {
        vertexCount += static_cast<int>(obstacle.vertices.rows());
        triangleCount += static_cast<int>(obstacle.triangles.rows());
        out.moves = out.moves || sim::obstacleMoves(obstacle);
    }
    out.triangles.resize(triangleCount, 3);
    int v = 0;
    int t = 0;
    for (const sim::ObstacleSpec& obstacle : scene.obstacles) {
        const int count = static_cast<int>(obstacle.triangles.rows());
        out.triangles.middleRows(t, count) = obstacle.triangles.array() + v;
        out.options.groups.push_back(io::ObjGroup{obstacle.name, t, count});
        v += static_cast<int>(obstacle.vertices.rows());
        t += count;
    }
    return out;
}

/// Writes the obstacles at the simulation's current time (world positions) to `path`.
io::Result<void> writeObstacles(const std::filesystem::path& path,
                                const sim::Simulation& simulation, const ObstacleMesh& mesh,
                                const std::string& comment) {
    const sim::SceneSpec& scene = simulation.scene();
    Eigen::Index vertexCount = 0;
    for (const sim::ObstacleSpec& obstacle : scene.obstacles) {
        vertexCount += obstacle.vertices.rows();
    }
    sim::MatX3 positions(vertexCount, 3);
    Eigen::Index v = 0;
    for (std::size_t k = 0; k < scene.obstacles.size(); ++k) {
        const sim::MatX3& x = simulation.obstaclePositions(static_cast<int>(k));
        positions.middleRows(v, x.rows()) = x;
        v += x.rows();
    }
    io::ObjWriteOptions options = mesh.options;
    options.comment = comment;
    return io::writeObj(path, positions, mesh.triangles, options);
}

/// `OUT.obj` → `OUT.obstacles.obj`.
std::filesystem::path obstaclesPath(const std::filesystem::path& out) {
    std::filesystem::path path = out;
    return path.replace_extension(".obstacles.obj");
}

/// The output paths against the scene and each other, before any work.
std::optional<std::string> checkSimulateOutputs(const SimulateOptions& options) {
    std::vector<NamedPath> files = {{"scene", options.scene}};
    const std::vector<NamedPath> outputs = {
        {"--out", options.out},
        {"--out (its obstacles)",
         options.out.empty() ? std::filesystem::path() : obstaclesPath(options.out)},
        {"--report", options.report}};
    if (auto problem = checkOutputs(files, outputs)) {
        return problem;
    }
    files.insert(files.end(), outputs.begin(), outputs.end());
    return checkOutputFolder({"--frames-dir", options.framesDir}, files);
}

/// Writes the final cloth mesh and the obstacles beside it; returns the exit code.
int writeFinalMeshes(const SimulateOptions& options, const sim::Simulation& simulation,
                     const CombinedMesh& mesh, const ObstacleMesh* obstacles, int code) {
    io::ObjWriteOptions objOptions = mesh.options;
    objOptions.comment = "atelier-cli simulate " + options.scene +
                         "\nt = " + std::to_string(simulation.time()) + " s";
    auto written = io::writeObj(options.out, simulation.positions(), mesh.triangles, objOptions);
    if (written.ok() && obstacles != nullptr) {
        written =
            writeObstacles(obstaclesPath(options.out), simulation, *obstacles, objOptions.comment);
    }
    return written.ok() ? code : RunLoop::writeFailed(written.error(), code);
}

int runSimulate(const SimulateOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    RunLoop loop("simulate", 0, options.framesDir); // from here on, a signal stops the run
    if (auto problem = checkSimulateOutputs(options)) {
        std::cerr << "error: " << *problem << "\n";
        return EXIT_BAD_INPUT;
    }
    std::optional<sim::SceneSpec> loaded = loadSceneOrReport(options.scene, options.limits);
    if (!loaded) {
        return EXIT_BAD_INPUT;
    }
    long vertices = 0;
    for (const sim::ClothSpec& cloth : loaded->cloths) {
        vertices += cloth.mesh.vertexCount();
    }
    if (auto problem = checkVertexLimit(options.scene + ": the scene's cloths", vertices,
                                        options.maxVertices)) {
        std::cerr << "error: " << *problem << "\n";
        return EXIT_BAD_INPUT;
    }
    if (options.threads > 0) {
        sim::setThreadCount(options.threads);
    }
    const double duration = loaded->duration;
    auto simulation = std::make_unique<sim::Simulation>(std::move(*loaded));
    const CombinedMesh mesh = combinedMesh(*simulation);
    // Obstacles are written only when the collision stage holds their positions (it exists
    // whenever the scene has obstacles and passed validation).
    const bool withObstacles =
        !simulation->scene().obstacles.empty() && simulation->collision() != nullptr;
    const ObstacleMesh obstacles = obstacleMesh(simulation->scene());

    loop.setEndTime(duration);
    if (!loop.prepare()) {
        return EXIT_BAD_INPUT;
    }
    int code = EXIT_OK;
    if (withObstacles && !obstacles.moves && !options.framesDir.empty()) {
        // Static obstacles: one file for every frame.
        auto written =
            writeObstacles(std::filesystem::path(options.framesDir) / "obstacles.obj", *simulation,
                           obstacles, "atelier-cli simulate " + options.scene + "\nstatic");
        if (!written.ok()) {
            code = RunLoop::writeFailed(written.error(), code);
        }
    }
    const bool collision = simulation->collision() != nullptr;
    const auto writeFrame = [&](const std::filesystem::path& stem) {
        auto written = io::writeObj(stem.string() + ".obj", simulation->positions(), mesh.triangles,
                                    mesh.options);
        if (written.ok() && withObstacles && obstacles.moves) {
            written = writeObstacles(stem.string() + ".obstacles.obj", *simulation, obstacles,
                                     "t = " + std::to_string(simulation->time()) + " s");
        }
        return written;
    };
    RunEnd end = RunEnd::Failed;
    if (simulation->error().empty()) {
        end = loop.run([&] {
            if (!(simulation->time() < duration - 1e-12)) {
                return StepState::Done;
            }
            if (simulation->step(duration) != sim::RunStatus::Finished) {
                return StepState::Failed;
            }
            if (simulation->atFrame()) {
                const sim::RunStats& stats = simulation->stats();
                char figures[200];
                const int n =
                    std::snprintf(figures, sizeof figures, "steps %ld (rejected %ld)  wall %.1f s",
                                  stats.steps, stats.rejectedSteps, stats.wallTime);
                if (collision && n > 0 && static_cast<std::size_t>(n) < sizeof figures) {
                    std::snprintf(figures + n, sizeof figures - static_cast<std::size_t>(n),
                                  "  contacts %ld  max penetration %.2g m", stats.contacts,
                                  stats.maxPenetration);
                }
                loop.frame(simulation->frameIndex(), simulation->time(), figures, writeFrame);
            }
            return StepState::Continue;
        });
    }
    const sim::RunStats& stats = simulation->stats();
    const bool finite = stats.finite && simulation->positions().allFinite();
    code = std::max(code, loop.exitCode(end == RunEnd::Done && !finite ? RunEnd::Failed : end));
    if (end == RunEnd::Cancelled) {
        std::cerr << "simulate: interrupted (" << InterruptGuard::signalName()
                  << ") at t = " << simulation->time() << " s; writing the state so far\n";
    } else if (end == RunEnd::Failed || !finite) {
        const std::string why = !simulation->error().empty() ? simulation->error() : stats.error;
        std::cerr << "error: " << options.scene
                  << ": simulation failed at t = " << simulation->time() << " s"
                  << (why.empty() ? "" : ": " + why) << "\n";
    }
    if (stats.stretchingSteps > 0) {
        std::cerr << "warning: " << options.scene << ": in " << stats.stretchingSteps
                  << " steps the collision corrections stretched the cloth; last: "
                  << stats.stretching << "\n";
    }
    if (stats.unconvergedSolves > 0) {
        std::cerr << "warning: " << options.scene << ": " << stats.unconvergedSolves << " of "
                  << stats.linearSolves << " linear solves ended above their tolerance ("
                  << stats.cappedSolves << " at the iteration cap), worst relative residual "
                  << stats.worstRelativeResidual << "\n";
    }

    if (!options.out.empty()) {
        if (finite) {
            code = writeFinalMeshes(options, *simulation, mesh,
                                    withObstacles ? &obstacles : nullptr, code);
        } else {
            std::cerr << "simulate: the state is not finite; " << options.out
                      << " is not written\n";
        }
    }

    if (!options.report.empty()) {
        const double totalSeconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const char* statusName = end == RunEnd::Done        ? "finished"
                                 : end == RunEnd::Cancelled ? "cancelled"
                                                            : "failed";
        const io::ReportFields extra = {
            {"scene", options.scene},
            {"status", std::string(statusName)},
            {"interrupted", end == RunEnd::Cancelled},
            {"signal", end == RunEnd::Cancelled
                           ? io::ReportValue(std::string(InterruptGuard::signalName()))
                           : io::ReportValue(nullptr)},
            {"exit_code", static_cast<std::int64_t>(code)},
            {"threads", static_cast<std::int64_t>(sim::threadCount())},
            {"frames_written", static_cast<std::int64_t>(loop.framesWritten())},
            {"total_wall_time_s", totalSeconds},
        };
        auto written = io::writeReport(options.report, *simulation, extra);
        if (!written.ok()) {
            code = RunLoop::writeFailed(written.error(), code);
        }
    }
    return code;
}

} // namespace

void addSimulateCommand(CLI::App& app) {
    auto options = std::make_shared<SimulateOptions>();
    CLI::App* cmd = app.add_subcommand(
        "simulate", "Run a scene file to its duration; write the final mesh and a report");
    cmd->add_option("scene", options->scene, "Scene file (JSON, see assets/scenes/README.md)")
        ->required();
    cmd->add_option("--out,-o", options->out,
                    "Final mesh (OBJ: one group per cloth, UV = rest); obstacles, if any, go "
                    "to OUT.obstacles.obj");
    cmd->add_option("--report,-r", options->report, "Run report (JSON)");
    cmd->add_option("--threads,-j", options->threads, "Engine threads (default: all cores)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--frames-dir", options->framesDir,
                    "Also write every output frame as DIR/frame_NNNNN.obj (moving obstacles: "
                    "DIR/frame_NNNNN.obstacles.obj; static ones: DIR/obstacles.obj)");
    cmd->add_option("--max-vertices", options->maxVertices,
                    "Refuse a scene whose cloths have more vertices than this")
        ->capture_default_str()
        ->check(CLI::PositiveNumber);
    addLimitOption(cmd, &options->limits);
    cmd->callback([options] {
        const int code = runSimulate(*options);
        if (code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

} // namespace atelier::app
