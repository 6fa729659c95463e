#include "io/report.h"

#include "io/atomic_file.h"
#include "io/json_text.h"

#include "sim/simulation.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

namespace atelier::io {

namespace {

/// A number, or null when it is not finite (JSON has no NaN or infinity).
nlohmann::json finiteOrNull(double value) {
    return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

} // namespace

std::string formatReport(const sim::Simulation& simulation, const ReportFields& extra) {
    const sim::RunStats& stats = simulation.stats();
    const sim::SceneSpec& scene = simulation.scene();
    nlohmann::json j;
    j["format"] = "atelier-report";
    j["version"] = 1;
    j["steps"] = stats.steps;
    j["rejected_steps"] = stats.rejectedSteps;
    j["steps_stretched_by_collisions"] = stats.stretchingSteps;
    j["stretched_by_collisions"] =
        stats.stretching.empty() ? nlohmann::json(nullptr) : nlohmann::json(stats.stretching);
    j["force_evaluations"] = stats.forceEvaluations;
    j["cg_iterations"] = stats.cgIterations;
    j["linear_solver"] = std::string(sim::linearSolverName(scene.integrator.linearSolver));
    if (simulation.linearSolver() != scene.integrator.linearSolver) {
        // An interactive drape settles with another (patterns::DrapeSession::setSettlingSolver).
        j["settling_linear_solver"] = std::string(sim::linearSolverName(simulation.linearSolver()));
    }
    j["linear_solves"] = stats.linearSolves;
    j["linear_solves_unconverged"] = stats.unconvergedSolves;
    j["linear_solves_capped"] = stats.cappedSolves;
    j["linear_solve_worst_residual"] = finiteOrNull(stats.worstRelativeResidual);
    j["sim_time_s"] = finiteOrNull(stats.simTime);
    j["wall_time_s"] = finiteOrNull(stats.wallTime);
    j["min_dt_s"] = finiteOrNull(stats.minDt);
    j["max_dt_s"] = finiteOrNull(stats.maxDt);
    j["finite"] = stats.finite && simulation.positions().allFinite();
    j["max_edge_strain"] = finiteOrNull(simulation.maxEdgeStrain());
    j["kinetic_energy_j"] = finiteOrNull(simulation.kineticEnergy());
    j["potential_energy_j"] = finiteOrNull(simulation.potentialEnergy());
    j["energy_input_j"] = finiteOrNull(stats.energyInput);
    j["active_stages"] = simulation.activeStages();
    nlohmann::json stages = nlohmann::json::object();
    for (const auto& [name, seconds] : stats.stageSeconds) {
        stages[name] = finiteOrNull(seconds);
    }
    j["stage_seconds"] = std::move(stages);
    j["integrator"] = std::string(sim::integratorName(scene.integrator.kind));
    std::string error = simulation.error();
    if (error.empty()) {
        error = stats.error;
    }
    j["error"] = error.empty() ? nlohmann::json(nullptr) : nlohmann::json(error);
    long long triangles = 0;
    nlohmann::json cloths = nlohmann::json::array();
    for (const sim::ClothSpec& cloth : scene.cloths) {
        triangles += cloth.mesh.triangleCount();
        cloths.push_back(cloth.name);
    }
    j["vertices"] = simulation.positions().rows();
    j["triangles"] = triangles;
    j["cloths"] = std::move(cloths);
    // Collision figures (0 and [] without a collision stage).
    j["max_penetration_m"] = finiteOrNull(stats.maxPenetration);
    j["contact_layer_crush_m"] = finiteOrNull(simulation.contactLayerCrush());
    long withObstacles = 0;
    j["intersecting_triangle_pairs"] = simulation.intersectingTrianglePairs(&withObstacles);
    j["intersecting_pairs_with_obstacles"] = withObstacles; // of which cloth–obstacle
    double collisionFraction = 0;
    if (const auto it = stats.stageSeconds.find("collision");
        it != stats.stageSeconds.end() && stats.wallTime > 0) {
        collisionFraction = std::clamp(it->second / stats.wallTime, 0.0, 1.0);
    }
    j["collision_time_fraction"] = finiteOrNull(collisionFraction);
    j["contacts"] = stats.contacts;
    nlohmann::json obstacles = nlohmann::json::array();
    for (const sim::ObstacleSpec& obstacle : scene.obstacles) {
        obstacles.push_back(obstacle.name);
    }
    j["obstacles"] = std::move(obstacles);
    for (const auto& [key, value] : extra) {
        std::visit(
            [&](const auto& v) {
                using V = std::decay_t<decltype(v)>;
                if constexpr (std::is_same_v<V, double>) {
                    j[key] = finiteOrNull(v);
                } else {
                    j[key] = v;
                }
            },
            value);
    }
    return jsonText(j);
}

Result<void> writeReport(const std::filesystem::path& path, const sim::Simulation& simulation,
                         const ReportFields& extra) {
    return writeFileAtomically(path, formatReport(simulation, extra));
}

} // namespace atelier::io
