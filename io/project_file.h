#pragma once
/// `.atelier` project files: a patterns::Project (body, garment, drape settings) as versioned
/// JSON (`"format": "atelier-project"`, `"version": 1`).
///
/// Lengths in the file are millimetres and angles degrees (keys say so: `grain_deg`,
/// `offset_mm`, outline points); body measurements are metres, other values SI. Inside, all is
/// metres and radians. Saving writes the canonical form: every key in a fixed order, 2-space
/// indent, a trailing newline, millimetre and degree values rounded to 1e-6, so that
/// save → load → save gives the same bytes.
///
/// Layout, in the order written:
/// ```
/// { "format": "atelier-project", "version": 1, "name": "tshirt",
///   "body": {"base": "female", "measurements": {"bust": 0.92}}     // or {"mesh": "body.obj"}
///   "materials": [{"name": "main", "fabric": "jersey-knit"}],       // a built-in preset, or
///                 // {"name": ..., "density_kg_per_m2": ..., ...}: the keys of scene materials
///   "panels": [{"name": "front", "material": "main", "side": "front", "grain_deg": 90,
///       "outline": [{"line": {"from": [x, y]}}, {"cubic": {"from": [..], "c1": [..],
///                   "c2": [..]}}, {"quadratic": {"from": [..], "c1": [..]}},
///                   {"arc": {"from": [..], "bulge": 0.3}}],  // each ends at the next "from"
///       "holes": [[segments...]],
///       "internal_lines": [{"fold_deg": 0, "segments": [{"line": {"from": [..], "to": [..]}}]}],
///       "darts": [{"leg": 3}], "notches": [{"segment": 2, "t": 0.5}],
///       "placement": {"slot": "torso_front", "offset_mm": [0, 0], "rotation_deg": 0,
///                     "clearance_mm": 20}}],
///   "seams": [{"name": "side", "a": [{"panel": "front", "segment": 1, "t0": 0, "t1": 1}],
///              "b": [...]}],
///   "ease_tolerance_mm": 5,
///   "simulation": {"particle_distance_mm": 10, "model": "fem", "integrator": "implicit-euler",
///       "dt_s": 0.00333, "cloth_thickness_mm": 2, "self_collision": true,
///       "body_thickness_mm": 2, "body_static_friction": 0.5, "body_kinetic_friction": 0.4,
///       "seam_time_constant_s": 0.004, "seam_weld_distance_mm": 1,
///       "rest_kinetic_energy_j": 1e-8, "rest_duration_s": 0.2, "time_limit_s": 5} }
/// ```
/// Absent optional keys take the defaults of patterns::Panel, Placement and DrapeSettings.

#include "io/result.h"

#include "patterns/project.h"

#include <filesystem>
#include <string>
#include <string_view>

namespace atelier::io {

/// The project file version this build reads and writes.
inline constexpr int PROJECT_FORMAT_VERSION = 1;

/// Reads a project from JSON text; `file` names it in errors. Every key is checked: unknown
/// keys, wrong types, non-finite or out-of-range numbers, unknown names (fabric presets,
/// materials, sides, models, integrators) and duplicate names are errors naming the JSON
/// pointer (`shirt.atelier: /panels/3/outline/2/cubic/c1: must be an array of two finite
/// numbers`); then the garment goes through patterns::validateGarment, whose first issue
/// becomes the error. Invalid JSON gives the line and column. The body mesh is not looked
/// for (there is no directory to resolve it against): `loadProject` does that.
Result<patterns::Project> parseProject(std::string_view text, const std::string& file);

/// Reads a project file. As `parseProject`, and a body mesh path is resolved against the
/// project file's directory and must exist.
Result<patterns::Project> loadProject(const std::filesystem::path& path);

/// The canonical text of a project (see above). A material whose `material.name` is a
/// built-in preset and whose parameters equal that preset's is written as `"fabric": name`,
/// any other with its full parameters. Loop segments are written by their start: each ends
/// where the next starts. Non-finite values are written as `null` (which loading refuses).
std::string formatProject(const patterns::Project& project);

/// Writes `formatProject(project)` to `path` atomically.
Result<void> saveProject(const std::filesystem::path& path, const patterns::Project& project);

} // namespace atelier::io
