#include "case_runner.h"

#include "io/body_animation.h"
#include "io/body_file.h"
#include "io/dxf_aama.h"
#include "io/garmentcode.h"
#include "io/materials.h"
#include "io/project_file.h"
#include "io/scene_file.h"

#include "patterns/drape_session.h"

#include "sim/simulation.h"

#include <algorithm>
#include <cmath>
#include <exception>

namespace atelier::fuzz {

namespace fs = std::filesystem;

namespace {

int status(CaseEnd end) {
    return static_cast<int>(end);
}

/// A refusal passes when it says why.
int refused(const Error& error, std::string& message) {
    message = error.toString();
    return status(error.message.empty() ? CaseEnd::EmptyError : CaseEnd::Refused);
}

int runScene(const fs::path& file, const RunLimits& limits, std::string& message) {
    auto loaded = io::loadScene(file);
    if (!loaded.ok()) {
        return refused(loaded.error(), message);
    }
    sim::SceneSpec scene = std::move(loaded).value();
    long vertices = 0;
    for (const sim::ClothSpec& cloth : scene.cloths) {
        vertices += cloth.mesh.vertexCount();
    }
    long obstacleTriangles = 0;
    for (const sim::ObstacleSpec& obstacle : scene.obstacles) {
        obstacleTriangles += static_cast<long>(obstacle.triangles.rows());
    }
    if (vertices > limits.maxVertices || obstacleTriangles > limits.maxObstacleTriangles) {
        message = "loaded " + std::to_string(vertices) + " cloth vertices, " +
                  std::to_string(obstacleTriangles) + " obstacle triangles: not run";
        return status(CaseEnd::TooLarge);
    }
    const double duration = scene.duration;
    sim::Simulation simulation(std::move(scene));
    if (!simulation.error().empty()) {
        return refused(Error{file.string(), "", simulation.error()}, message);
    }
    // The command line's loop (app/cli/simulate_command.cpp), cut after a few steps.
    int steps = 0;
    while (steps < limits.steps && simulation.time() < duration - 1e-12) {
        if (simulation.step(duration) != sim::RunStatus::Finished) {
            break;
        }
        if (simulation.atFrame()) {
            (void)simulation.frameIndex();
        }
        ++steps;
    }
    message = "ran " + std::to_string(steps) +
              " steps to t = " + std::to_string(simulation.time()) + " s of " +
              std::to_string(duration) + " s";
    if (steps == limits.steps && !(simulation.time() > 0) && duration > 1e-12) {
        message += ": no simulated time passed, the command line would loop forever";
        return status(CaseEnd::Stalled);
    }
    return status(CaseEnd::Ran);
}

/// Triangles a garment meshes into at `particleDistance` [m], from its panels' bounding boxes
/// (an arc's bulge widens its box).
double triangleEstimate(const patterns::Garment& garment, double particleDistance) {
    double triangles = 0;
    for (const patterns::Panel& panel : garment.panels) {
        sim::Vec2 lo = sim::Vec2::Constant(INFINITY);
        sim::Vec2 hi = sim::Vec2::Constant(-INFINITY);
        double pad = 0;
        for (const patterns::Segment& s : panel.outline) {
            for (const sim::Vec2& p : {s.start, s.end, s.control1, s.control2}) {
                lo = lo.cwiseMin(p);
                hi = hi.cwiseMax(p);
            }
            pad = std::max(pad, std::abs(s.bulge) * (s.end - s.start).norm());
        }
        const sim::Vec2 size = (hi - lo).array() + 2 * pad + particleDistance;
        triangles += 2.31 * size.x() * size.y() / (particleDistance * particleDistance);
    }
    return triangles;
}

/// Drapes a loaded project a few steps.
int drapeProject(patterns::Project project, const fs::path& file, const BodyCache& bodies,
                 const RunLimits& limits, std::string& message) {
    project.drape.particleDistance =
        std::max(project.drape.particleDistance, limits.minParticleDistance);
    const double estimate = triangleEstimate(project.garment, project.drape.particleDistance);
    if (estimate > limits.maxTriangleEstimate && estimate <= limits.runawayTriangleEstimate) {
        message = "loaded, about " + std::to_string(static_cast<long>(estimate)) +
                  " triangles: not draped";
        return status(CaseEnd::TooLarge);
    }
    const fs::path dir = file.parent_path();
    patterns::DrapeSession session([&](const patterns::BodySource& source) {
        if (source.meshPath.empty()) {
            // Fitting a mannequin to measurements takes seconds: the measurements are checked
            // and the base's default body stands in.
            if (auto checked = io::bodyMeasurements(source, file.string()); !checked.ok()) {
                return Result<patterns::Body>(checked.error());
            }
            patterns::BodySource base;
            base.base = source.base;
            if (const patterns::Body* body = bodies.find(base)) {
                return Result<patterns::Body>(*body);
            }
        }
        if (!source.meshPath.empty()) {
            // The body file's animation, where it has one, sampled as `atelier-cli animate
            // --body-animation` samples it: a crash or hang there is a finding, an error not.
            io::BodyAnimationOptions sampling;
            sampling.fps = 10;
            (void)io::importBodyAnimation(dir / source.meshPath, sampling);
        }
        return io::loadBody(source, dir, file);
    });
    session.setProject(std::move(project));
    if (auto prepared = session.prepare(); !prepared.ok()) {
        return refused(prepared.error(), message);
    }
    int steps = 0;
    for (; steps < limits.steps && !session.finished(); ++steps) {
        session.step();
    }
    message = "draped " + std::to_string(steps) + " steps, phase " +
              std::string(patterns::phaseName(session.phase()));
    return status(CaseEnd::Ran);
}

int runProject(const fs::path& file, const BodyCache& bodies, const RunLimits& limits,
               std::string& message) {
    auto loaded = io::loadProject(file);
    if (!loaded.ok()) {
        return refused(loaded.error(), message);
    }
    return drapeProject(std::move(loaded).value(), file, bodies, limits, message);
}

/// Imports a GarmentCode specification onto the default body and drapes it a few steps.
int runGarmentCode(const fs::path& file, const BodyCache& bodies, const RunLimits& limits,
                   std::string& message) {
    const patterns::Body* body = bodies.find(patterns::BodySource{});
    if (body == nullptr) {
        message = "no default body to place the panels on";
        return status(CaseEnd::Exception);
    }
    auto imported = io::importGarmentCode(file, *body);
    if (!imported.ok()) {
        return refused(imported.error(), message);
    }
    return drapeProject(std::move(imported).value().project, file, bodies, limits, message);
}

/// Imports a DXF-AAMA pattern and drapes its (unsewn) pieces a few steps.
int runDxf(const fs::path& file, const BodyCache& bodies, const RunLimits& limits,
           std::string& message) {
    auto imported = io::importDxfAama(file);
    if (!imported.ok()) {
        return refused(imported.error(), message);
    }
    return drapeProject(std::move(imported).value().project, file, bodies, limits, message);
}

/// Reads the file and checks the measurements together (fitting the mannequin to them takes
/// seconds, beyond a case's time).
int runMeasurements(const fs::path& file, std::string& message) {
    auto source = io::readMeasurementsFile(file);
    if (!source.ok()) {
        return refused(source.error(), message);
    }
    auto measurements = io::bodyMeasurements(source.value(), file.string());
    if (!measurements.ok()) {
        return refused(measurements.error(), message);
    }
    message = "read " + std::to_string(source.value().measurements.size()) + " measurements";
    return status(CaseEnd::Ran);
}

int runFabrics(const fs::path& file, std::string& message) {
    auto presets = io::loadMaterialPresets(file);
    if (!presets.ok()) {
        return refused(presets.error(), message);
    }
    message = "loaded " + std::to_string(presets.value().size()) + " presets";
    return status(CaseEnd::Ran);
}

} // namespace

bool passed(int exitStatus) {
    return exitStatus == status(CaseEnd::Ran) || exitStatus == status(CaseEnd::Refused) ||
           exitStatus == status(CaseEnd::TooLarge);
}

void BodyCache::add(const patterns::BodySource& source) {
    if (!source.meshPath.empty() || find(source) != nullptr) {
        return;
    }
    auto body = io::makeBody(source, "");
    if (body.ok()) {
        m_bodies.emplace_back(source, std::move(body).value().body);
    }
}

const patterns::Body* BodyCache::find(const patterns::BodySource& source) const {
    for (const auto& [s, body] : m_bodies) {
        if (s == source) {
            return &body;
        }
    }
    return nullptr;
}

int runCase(InputKind kind, const fs::path& mainFile, const BodyCache& bodies,
            const RunLimits& limits, std::string& message) {
    try {
        switch (kind) {
        case InputKind::Scene:
            return runScene(mainFile, limits, message);
        case InputKind::Project:
            return runProject(mainFile, bodies, limits, message);
        case InputKind::Measurements:
            return runMeasurements(mainFile, message);
        case InputKind::Fabrics:
            return runFabrics(mainFile, message);
        case InputKind::GarmentCode:
            return runGarmentCode(mainFile, bodies, limits, message);
        case InputKind::Dxf:
            return runDxf(mainFile, bodies, limits, message);
        }
    } catch (const std::exception& e) {
        message = std::string("uncaught exception: ") + e.what();
        return status(CaseEnd::Exception);
    } catch (...) {
        message = "uncaught exception of unknown type";
        return status(CaseEnd::Exception);
    }
    return status(CaseEnd::Exception);
}

} // namespace atelier::fuzz
