/// `atelier-cli simulate`: load a scene file, run it to its duration, write the final mesh
/// (OBJ, one group per cloth, UVs = rest coordinates [m]), the obstacles at the end (OBJ, one
/// group per obstacle) and a JSON report.

#include "app/cli/commands.h"

#include "io/obj.h"
#include "io/report.h"
#include "io/scene_file.h"

#include "sim/collision/obstacle.h"
#include "sim/core/parallel.h"
#include "sim/simulation.h"

#include <CLI/CLI.hpp>

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <unistd.h>

namespace atelier::app {

namespace {

struct SimulateOptions {
    std::string scene;
    std::string out;
    std::string report;
    int threads = 0; ///< 0 = the engine's default (all cores)
    std::string framesDir;
};

std::atomic<bool> g_cancel{false};

extern "C" void onInterrupt(int /*signal*/) { g_cancel.store(true); }

/// Restores the previous SIGINT handler when it goes out of scope.
class InterruptGuard {
  public:
    InterruptGuard() : m_previous(std::signal(SIGINT, onInterrupt)) {}
    ~InterruptGuard() { std::signal(SIGINT, m_previous); }
    InterruptGuard(const InterruptGuard&) = delete;
    InterruptGuard& operator=(const InterruptGuard&) = delete;

  private:
    void (*m_previous)(int);
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
        out.triangles.middleRows(t, mesh.triangleCount()) =
            mesh.triangles.array() + offset;
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

/// A progress line on stderr: rewritten in place on a terminal, every 10% otherwise.
class Progress {
  public:
    /// `contacts`: also show the active contacts (the scene has a collision stage).
    Progress(int frames, bool contacts)
        : m_frames(frames), m_contacts(contacts), m_tty(::isatty(STDERR_FILENO) != 0) {}

    void update(int frame, double time, const sim::RunStats& stats) {
        const int decile = m_frames > 0 ? (10 * frame) / m_frames : 10;
        if (!m_tty && decile == m_lastDecile) {
            return;
        }
        m_lastDecile = decile;
        char line[240];
        const int n = std::snprintf(
            line, sizeof line,
            "simulate: frame %d/%d  t = %.3f s  steps %ld (rejected %ld)  wall %.1f s", frame,
            m_frames, time, stats.steps, stats.rejectedSteps, stats.wallTime);
        if (m_contacts && n > 0 && static_cast<std::size_t>(n) < sizeof line) {
            std::snprintf(line + n, sizeof line - static_cast<std::size_t>(n),
                          "  contacts %ld  max penetration %.2g m", stats.contacts,
                          stats.maxPenetration);
        }
        std::cerr << (m_tty ? "\r\033[K" : "") << line << (m_tty ? "" : "\n") << std::flush;
        m_dirty = m_tty;
    }

    void finish() {
        if (m_dirty) {
            std::cerr << "\n";
            m_dirty = false;
        }
    }

  private:
    int m_frames;
    bool m_contacts;
    bool m_tty;
    int m_lastDecile = -1;
    bool m_dirty = false;
};

int runSimulate(const SimulateOptions& options) {
    const auto start = std::chrono::steady_clock::now();
    auto loaded = io::loadScene(options.scene);
    if (!loaded.ok()) {
        std::cerr << "error: " << loaded.error().toString() << "\n";
        return EXIT_BAD_INPUT;
    }
    if (options.threads > 0) {
        sim::setThreadCount(options.threads);
    }
    if (!options.framesDir.empty()) {
        std::error_code ec;
        std::filesystem::create_directories(options.framesDir, ec);
        if (ec) {
            std::cerr << "error: " << options.framesDir << ": " << ec.message() << "\n";
            return EXIT_BAD_INPUT;
        }
    }

    const double duration = loaded.value().duration;
    const double frameRate = loaded.value().frameRate;
    auto simulation = std::make_unique<sim::Simulation>(std::move(loaded).value());
    const CombinedMesh mesh = combinedMesh(*simulation);
    // Obstacles are written only when the collision stage holds their positions (it exists
    // whenever the scene has obstacles and passed validation).
    const bool withObstacles =
        !simulation->scene().obstacles.empty() && simulation->collision() != nullptr;
    const ObstacleMesh obstacles = obstacleMesh(simulation->scene());

    sim::RunStatus status = sim::RunStatus::Failed;
    int framesWritten = 0;
    std::string frameError;
    if (withObstacles && !obstacles.moves && !options.framesDir.empty()) {
        // Static obstacles: one file for every frame.
        auto written =
            writeObstacles(std::filesystem::path(options.framesDir) / "obstacles.obj", *simulation,
                           obstacles, "atelier-cli simulate " + options.scene + "\nstatic");
        if (!written.ok()) {
            frameError = written.error().toString();
        }
    }
    if (simulation->error().empty()) {
        Progress progress(static_cast<int>(std::lround(duration * frameRate)),
                          simulation->collision() != nullptr);
        g_cancel.store(false);
        const InterruptGuard guard;
        status = simulation->run(
            duration,
            [&](int frame, double time) {
                progress.update(frame, time, simulation->stats());
                if (options.framesDir.empty() || !frameError.empty()) {
                    return;
                }
                char name[32];
                std::snprintf(name, sizeof name, "frame_%05d.obj", frame);
                auto written = io::writeObj(std::filesystem::path(options.framesDir) / name,
                                            simulation->positions(), mesh.triangles, mesh.options);
                if (written.ok() && withObstacles && obstacles.moves) {
                    std::snprintf(name, sizeof name, "frame_%05d.obstacles.obj", frame);
                    written =
                        writeObstacles(std::filesystem::path(options.framesDir) / name, *simulation,
                                       obstacles, "t = " + std::to_string(time) + " s");
                }
                if (written.ok()) {
                    ++framesWritten;
                } else {
                    frameError = written.error().toString();
                }
            },
            &g_cancel);
        progress.finish();
    }
    const sim::RunStats& stats = simulation->stats();
    const bool finite = stats.finite && simulation->positions().allFinite();

    int code = EXIT_OK;
    if (status == sim::RunStatus::Cancelled) {
        std::cerr << "simulate: cancelled at t = " << simulation->time() << " s\n";
        code = EXIT_CANCELLED;
    } else if (status == sim::RunStatus::Failed || !finite) {
        const std::string why = !simulation->error().empty() ? simulation->error() : stats.error;
        std::cerr << "error: " << options.scene << ": simulation failed at t = "
                  << simulation->time() << " s" << (why.empty() ? "" : ": " + why) << "\n";
        code = EXIT_RUN_FAILED;
    }
    if (!frameError.empty()) {
        std::cerr << "error: " << frameError << "\n";
        code = code == EXIT_OK ? EXIT_RUN_FAILED : code;
    }

    if (!options.out.empty()) {
        if (finite) {
            io::ObjWriteOptions objOptions = mesh.options;
            objOptions.comment = "atelier-cli simulate " + options.scene + "\nt = " +
                                 std::to_string(simulation->time()) + " s";
            auto written =
                io::writeObj(options.out, simulation->positions(), mesh.triangles, objOptions);
            if (written.ok() && withObstacles) {
                written = writeObstacles(obstaclesPath(options.out), *simulation, obstacles,
                                         objOptions.comment);
            }
            if (!written.ok()) {
                std::cerr << "error: " << written.error().toString() << "\n";
                code = code == EXIT_OK ? EXIT_RUN_FAILED : code;
            }
        } else {
            std::cerr << "simulate: the state is not finite; " << options.out
                      << " is not written\n";
        }
    }

    if (!options.report.empty()) {
        const double totalSeconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        const char* statusName = status == sim::RunStatus::Finished    ? "finished"
                                 : status == sim::RunStatus::Cancelled ? "cancelled"
                                                                       : "failed";
        const io::ReportFields extra = {
            {"scene", options.scene},
            {"status", std::string(statusName)},
            {"exit_code", static_cast<std::int64_t>(code)},
            {"threads", static_cast<std::int64_t>(sim::threadCount())},
            {"frames_written", static_cast<std::int64_t>(framesWritten)},
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
    cmd->callback([options] {
        const int code = runSimulate(*options);
        if (code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

} // namespace atelier::app
