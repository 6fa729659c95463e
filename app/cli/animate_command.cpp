/// `atelier-cli animate PROJECT --body-frames FRAMES... | --body-animation FILE --out
/// SEQUENCE.glb`: drapes the project on the first frame of an animated body until rest, then
/// runs the drape along the body's motion, one body frame after the other, and writes the
/// sequence (docs/animation.md).

#include "app/cli/commands.h"
#include "app/cli/drape.h"
#include "app/cli/interrupt.h"
#include "app/cli/limits_option.h"

#include "io/atomic_file.h"
#include "io/body_animation.h"
#include "io/body_file.h"
#include "io/gltf_animation.h"
#include "io/mesh_import.h"
#include "io/obj.h"
#include "io/project_file.h"

#include "patterns/mannequin.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

namespace atelier::app {

namespace {

struct AnimateOptions {
    DrapeOptions drape; ///< the drape to rest on the first frame (its --out, --report, ...)
    std::vector<std::string> bodyFrames;
    std::string bodyAnimation; ///< a skinned, animated body file, or empty
    std::string animation;     ///< its animation's name or index; empty = the first
    double start = 0;          ///< start of the window sampled [s]
    double duration = -1;      ///< length of the window sampled [s]; < 0 = to the end
    double fps = 30;
    std::string sequence;     ///< the .glb written
    std::string motionDir;    ///< garment and body OBJ per frame, or empty
    std::string motionReport; ///< JSON figures of the motion, or empty
    bool withBody = true;
};

/// The frame files: each argument a file, or a folder whose body meshes are taken in name
/// order.
Result<std::vector<std::filesystem::path>> frameFiles(const std::vector<std::string>& arguments) {
    std::vector<std::filesystem::path> files;
    for (const std::string& argument : arguments) {
        std::error_code ec;
        if (!std::filesystem::is_directory(argument, ec)) {
            files.emplace_back(argument);
            continue;
        }
        std::vector<std::filesystem::path> found;
        for (const auto& entry : std::filesystem::directory_iterator(argument, ec)) {
            if (entry.is_regular_file() && io::hasBodyMeshExtension(entry.path())) {
                found.push_back(entry.path());
            }
        }
        if (ec) {
            return Error{argument, "", "cannot list the folder: " + ec.message()};
        }
        if (found.empty()) {
            return Error{argument, "", "the folder holds no body mesh file"};
        }
        std::sort(found.begin(), found.end());
        files.insert(files.end(), found.begin(), found.end());
    }
    return files;
}

/// Reads the motion in the unit and up axis of the project's body, which must be a mesh (with
/// --body-animation, the animated file itself).
Result<io::BodyMotion> readMotion(const AnimateOptions& options, const io::Limits& limits) {
    auto project = io::loadProject(options.drape.project, limits);
    if (!project.ok()) {
        return project.error();
    }
    const patterns::BodySource& body = project.value().body;
    if (body.meshPath.empty()) {
        return Error{options.drape.project, "/body",
                     "the body is the mannequin; to drape along a motion, make the motion's "
                     "first frame the project's body (\"body\": {\"mesh\": FILE})"};
    }
    if (!options.bodyAnimation.empty()) {
        const std::filesystem::path mesh =
            std::filesystem::absolute(options.drape.project).parent_path() / body.meshPath;
        std::error_code ec;
        if (!std::filesystem::exists(options.bodyAnimation, ec)) {
            return Error{options.bodyAnimation, "", "the body animation file is not found"};
        }
        if (!std::filesystem::equivalent(mesh, options.bodyAnimation, ec)) {
            return Error{options.drape.project, "/body/mesh",
                         "the body is " + body.meshPath + ", not --body-animation " +
                             options.bodyAnimation +
                             "; make the animated file the project's body (\"body\": "
                             "{\"mesh\": FILE}), so that its unit and up axis apply"};
        }
        io::BodyAnimationOptions sampling;
        sampling.import = io::bodyImportOptions(body);
        sampling.animation = options.animation;
        sampling.fps = options.fps;
        sampling.start = options.start;
        sampling.duration = options.duration;
        return io::importBodyAnimation(options.bodyAnimation, sampling, limits);
    }
    auto files = frameFiles(options.bodyFrames);
    if (!files.ok()) {
        return files.error();
    }
    return io::importBodyMotion(files.value(), io::bodyImportOptions(body), limits);
}

/// Figures of the motion, for the report and the last line.
struct MotionFigures {
    int frames = 0;
    double maxPenetration = 0;     ///< deepest cloth vertex in the body over the frames [m]
    long maxIntersectingPairs = 0; ///< most intersecting triangle pairs at a frame
    double maxKineticEnergy = 0;   ///< per vertex, largest at a frame [J]
    double wallSeconds = 0;
    bool interrupted = false;
};

int writeMotionReport(const AnimateOptions& options, const MotionFigures& f, int code) {
    if (options.motionReport.empty()) {
        return code;
    }
    const nlohmann::json report = {{"format", "atelier-motion-report"},
                                   {"version", 1},
                                   {"project", options.drape.project},
                                   {"frames", f.frames},
                                   {"fps", options.fps},
                                   {"max_penetration_m", f.maxPenetration},
                                   {"max_intersecting_pairs", f.maxIntersectingPairs},
                                   {"max_kinetic_energy_per_vertex_j", f.maxKineticEnergy},
                                   {"wall_time_s", f.wallSeconds},
                                   {"interrupted", f.interrupted}};
    const auto written = io::writeFileAtomically(options.motionReport, report.dump(2) + "\n");
    if (!written.ok()) {
        std::cerr << "error: " << written.error().toString() << "\n";
        return code == EXIT_OK ? EXIT_RUN_FAILED : code;
    }
    return code;
}

/// Runs the drape along the motion from where it rests, frame by frame; writes the outputs.
int runMotion(const AnimateOptions& options, const io::BodyMotion& motion,
              patterns::DrapeSession& session, int code) {
    sim::Simulation* simulation = session.simulation();
    const sim::SceneSpec& scene = simulation->scene();
    int bodyIndex = -1;
    for (std::size_t k = 0; k < scene.obstacles.size(); ++k) {
        if (scene.obstacles[k].name == "body") {
            bodyIndex = static_cast<int>(k);
        }
    }
    if (bodyIndex < 0 || scene.obstacles[static_cast<std::size_t>(bodyIndex)].vertices.rows() !=
                             motion.frames.front().rows()) {
        std::cerr << "error: " << motion.files.front()
                  << ": the motion's body is not the project's body (its first frame must be "
                     "the project's body mesh)\n";
        return EXIT_BAD_INPUT;
    }
    const double startGap = (simulation->obstaclePositions(bodyIndex) - motion.frames.front())
                                .rowwise()
                                .norm()
                                .maxCoeff();
    if (startGap > 1e-3) {
        std::fprintf(stderr,
                     "warning: the motion's first frame is up to %.1f mm from the project's "
                     "body: the drape moves the body there over the first frame\n",
                     startGap * 1e3);
    }
    const GarmentObj obj =
        garmentObj(session.project().garment, session.mesh(), session.assembled());
    const double frameTime = 1.0 / options.fps;
    std::vector<double> times;
    std::vector<sim::MatX3> garment, body;
    MotionFigures f;
    const auto start = std::chrono::steady_clock::now();
    const auto record = [&](std::size_t k) -> Result<void> {
        times.push_back(static_cast<double>(k) * frameTime);
        garment.push_back(session.positions());
        body.push_back(simulation->obstaclePositions(bodyIndex));
        f.maxPenetration = std::max(f.maxPenetration, simulation->penetration());
        f.maxIntersectingPairs =
            std::max(f.maxIntersectingPairs, simulation->intersectingTrianglePairs());
        f.maxKineticEnergy = std::max(f.maxKineticEnergy, session.figures().kineticEnergyPerVertex);
        f.frames = static_cast<int>(times.size());
        if (options.motionDir.empty()) {
            return {};
        }
        char stem[32];
        std::snprintf(stem, sizeof stem, "%05zu", k);
        const std::filesystem::path dir(options.motionDir);
        auto written = io::writeObj(dir / ("frame_" + std::string(stem) + ".obj"), garment.back(),
                                    obj.triangles, obj.options);
        if (!written.ok()) {
            return written;
        }
        io::ObjWriteOptions bodyOptions;
        bodyOptions.comment = "body of atelier-cli animate, frame " + std::string(stem);
        return io::writeObj(dir / ("body_" + std::string(stem) + ".obj"), body.back(),
                            scene.obstacles[static_cast<std::size_t>(bodyIndex)].triangles,
                            bodyOptions);
    };
    if (auto written = record(0); !written.ok()) {
        std::cerr << "error: " << written.error().toString() << "\n";
        return EXIT_RUN_FAILED;
    }
    for (std::size_t k = 1; k < motion.frames.size(); ++k) {
        if (InterruptGuard::interrupted()) {
            f.interrupted = true;
            code = EXIT_CANCELLED;
            break;
        }
        simulation->setObstacleFrame(bodyIndex, motion.frames[k], frameTime);
        const double target = session.time() + frameTime;
        session.wake();
        while (session.time() < target - 1e-9) {
            const patterns::DrapeStatus status = session.advance(target - session.time());
            if (status == patterns::DrapeStatus::Failed) {
                std::cerr << "error: " << options.drape.project << ": the drape failed at frame "
                          << k << " of the motion: " << session.figures().error << "\n";
                return EXIT_RUN_FAILED;
            }
            if (status == patterns::DrapeStatus::Cancelled) {
                break;
            }
            if (status != patterns::DrapeStatus::Running) {
                session.wake(); // at rest again or at its time limit: the motion goes on
            }
        }
        if (auto written = record(k); !written.ok()) {
            std::cerr << "error: " << written.error().toString() << "\n";
            return EXIT_RUN_FAILED;
        }
        std::fprintf(stderr, "animate: frame %zu of %zu  t = %.3f s  penetration %.2f mm\n", k,
                     motion.frames.size() - 1, times.back(), simulation->penetration() * 1e3);
    }
    f.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::vector<io::SequenceMesh> meshes;
    meshes.push_back({"garment", obj.triangles, std::move(garment), {0.55, 0.62, 0.78}});
    if (options.withBody) {
        meshes.push_back({"body",
                          scene.obstacles[static_cast<std::size_t>(bodyIndex)].triangles,
                          std::move(body),
                          {0.85, 0.75, 0.68}});
    }
    if (auto written = io::writeSequenceGlb(options.sequence, meshes, times); !written.ok()) {
        std::cerr << "error: " << written.error().toString() << "\n";
        return writeMotionReport(options, f, EXIT_RUN_FAILED);
    }
    std::fprintf(stderr,
                 "animate: %d frames in %.1f s wall; deepest penetration %.2f mm, at most %ld "
                 "intersecting triangle pairs; wrote %s\n",
                 f.frames, f.wallSeconds, f.maxPenetration * 1e3, f.maxIntersectingPairs,
                 options.sequence.c_str());
    return writeMotionReport(options, f, code);
}

int runAnimate(const AnimateOptions& options) {
    const std::optional<io::Limits> limits = limitsOrReport(options.drape.limits);
    if (!limits) {
        return EXIT_BAD_INPUT;
    }
    if (!(options.fps > 0 && options.fps <= 1000)) {
        std::cerr << "error: --fps must be above 0 and at most 1000\n";
        return EXIT_BAD_INPUT;
    }
    if (options.bodyFrames.empty() == options.bodyAnimation.empty()) {
        std::cerr << "error: give the motion as --body-frames or as --body-animation\n";
        return EXIT_BAD_INPUT;
    }
    auto motion = readMotion(options, *limits);
    if (!motion.ok()) {
        std::cerr << "error: " << motion.error().toString() << "\n";
        return EXIT_BAD_INPUT;
    }
    DrapeOptions drape = options.drape;
    if (!motion.value().animation.empty()) {
        // The drape rests on the animation's first frame, not on the file's bind pose.
        const io::ImportedBody& first = motion.value().first;
        for (const std::string& w : first.report.warnings) {
            std::cerr << "warning: " << options.bodyAnimation << ": " << w << "\n";
        }
        patterns::Body body;
        body.vertices = first.vertices;
        body.triangles = first.triangles;
        if (auto problem = patterns::estimateSlots(body)) {
            std::cerr << "error: " << options.bodyAnimation << ": " << *problem << "\n";
            return EXIT_BAD_INPUT;
        }
        drape.body = std::move(body);
    }
    if (std::error_code ec; !options.motionDir.empty() &&
                            !std::filesystem::create_directories(options.motionDir, ec) && ec) {
        std::cerr << "error: " << options.motionDir
                  << ": cannot create the folder: " << ec.message() << "\n";
        return EXIT_BAD_INPUT;
    }
    std::fprintf(stderr, "animate: %zu body frames at %g frames per second (%.2f s)%s%s\n",
                 motion.value().frames.size(), options.fps,
                 static_cast<double>(motion.value().frames.size() - 1) / options.fps,
                 motion.value().animation.empty() ? "" : " of animation ",
                 motion.value().animation.c_str());
    return runDrape(drape, [&](patterns::DrapeSession& session, int code) {
        if (code != EXIT_OK) {
            return code;
        }
        return runMotion(options, motion.value(), session, code);
    });
}

} // namespace

void addAnimateCommand(CLI::App& app) {
    auto options = std::make_shared<AnimateOptions>();
    CLI::App* cmd = app.add_subcommand(
        "animate", "Drape a project on the first frame of an animated body until rest, then "
                   "along the body's motion; write the sequence as glTF (morph targets)");
    cmd->add_option("project", options->drape.project,
                    "Garment project (.atelier) whose body "
                    "is the motion's first frame")
        ->required();
    CLI::Option* frames =
        cmd->add_option("--body-frames", options->bodyFrames,
                        "The body at each frame: mesh files (same mesh, moved), or a folder of "
                        "them taken in name order");
    CLI::Option* animated = cmd->add_option(
        "--body-animation", options->bodyAnimation,
        "Or a skinned, animated body (glTF, FBX, COLLADA) sampled at --fps; the project's body "
        "must be this file");
    frames->excludes(animated);
    cmd->add_option("--animation", options->animation,
                    "The animation of --body-animation: its name or index (default: the first)")
        ->needs(animated);
    cmd->add_option("--start", options->start,
                    "Start of the window of the animation sampled [s] (default 0)")
        ->needs(animated)
        ->check(CLI::NonNegativeNumber);
    cmd->add_option("--duration", options->duration,
                    "Length of the window of the animation sampled [s] (default: to its end)")
        ->needs(animated)
        ->check(CLI::PositiveNumber);
    cmd->add_option("--fps", options->fps,
                    "Body frames per second (default 30); with --body-animation, the frames "
                    "sampled per second");
    cmd->add_option("--out", options->sequence,
                    "The sequence as one glTF binary (.glb): garment and body, a morph target "
                    "per frame and an animation that plays them")
        ->required();
    cmd->add_option("--frames-dir", options->motionDir,
                    "Also write DIR/frame_NNNNN.obj (garment) and DIR/body_NNNNN.obj per frame");
    cmd->add_option("--report", options->motionReport, "Figures of the motion (JSON)");
    cmd->add_option("--rest-out", options->drape.out, "The drape at rest on the first frame");
    cmd->add_option("--rest-report", options->drape.report,
                    "Report of the drape to rest (as atelier-cli drape --report)");
    cmd->add_flag("!--no-body", options->withBody, "Leave the body out of the .glb");
    cmd->add_option("-j,--threads", options->drape.threads, "Engine threads (default: all cores)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--particle-distance", options->drape.particleDistanceMm,
                    "Mesh particle distance [mm] (default: the project's)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--time-limit", options->drape.timeLimit,
                    "Simulated time limit of the drape to rest [s] (default: the project's)")
        ->check(CLI::PositiveNumber);
    cmd->add_option("--limit", options->drape.limits,
                    "Raise or lower a bound on the input, NAME=VALUE (repeatable)");
    cmd->callback([options] {
        if (const int code = runAnimate(*options); code != EXIT_OK) {
            throw CLI::RuntimeError(code);
        }
    });
}

} // namespace atelier::app
