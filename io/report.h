#pragma once
/// Run reports: a JSON summary of a simulation run (counters, timings, final-state figures),
/// for the CLI, CI and benchmarks.

#include "io/result.h"

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <variant>
#include <vector>

namespace atelier::sim {
class Simulation;
}

namespace atelier::io {

/// A value of an extra report field.
using ReportValue =
    std::variant<std::nullptr_t, bool, std::int64_t, double, std::string, std::vector<std::string>>;
/// Extra fields added at the top level of a report (they override built-in ones).
using ReportFields = std::map<std::string, ReportValue>;

/// The report of a run as JSON text (2-space indented). Keys:
/// `format` ("atelier-report"), `version` (1), `steps`, `rejected_steps`,
/// `steps_stretched_by_collisions` and `stretched_by_collisions` (RunStats::stretchingSteps,
/// stretching: string or null), `force_evaluations`,
/// `cg_iterations`, `linear_solver` (name), `linear_solves`, `linear_solves_unconverged`
/// (ended above the tolerance), `linear_solves_capped` (of which at the iteration cap),
/// `linear_solve_worst_residual` (largest final relative residual [-]),
/// `sim_time_s`, `wall_time_s`, `min_dt_s`, `max_dt_s`, `finite` (bool),
/// `max_edge_strain` [-], `kinetic_energy_j`, `potential_energy_j`, `energy_input_j`,
/// `active_stages` (list), `stage_seconds` (object: stage → [s]), `integrator`, `error` (string
/// or null), `vertices`, `triangles`, `cloths` (list of names); collision figures, always
/// present (0 or [] without a collision stage): `max_penetration_m` (RunStats::maxPenetration:
/// deepest cloth vertex inside an obstacle beyond the obstacle's own thickness over the output
/// frames [m]), `contact_layer_crush_m` (Simulation::contactLayerCrush() at the final state:
/// deepest cloth vertex inside the obstacle's plus the cloth's thickness, where a resting
/// cloth sits [m]), `intersecting_triangle_pairs` (Simulation::intersectingTrianglePairs() at
/// the final state, computed here), `collision_time_fraction` (stage_seconds["collision"] /
/// wall_time_s, clamped to [0, 1]; 0 when the wall time is 0), `contacts` (active contacts
/// after the last step), `obstacles` (list of names); then `extra`. Non-finite numbers are
/// written as null; bytes that are not UTF-8 in strings (a file name) as U+FFFD.
std::string formatReport(const sim::Simulation& simulation, const ReportFields& extra = {});

/// Writes `formatReport` to `path` atomically.
Result<void> writeReport(const std::filesystem::path& path, const sim::Simulation& simulation,
                         const ReportFields& extra = {});

} // namespace atelier::io
