#pragma once
/// `.atelier` project files: a patterns::Project (body, garment document, drape settings) as
/// versioned JSON (`"format": "atelier-project"`, `"version": 2`); docs/project-format.md
/// describes both versions.
///
/// Lengths in the file are millimetres and angles degrees (keys say so: `grain_deg`,
/// `offset_mm`, points); body measurements are metres, other values SI. Inside, all is
/// metres and radians. Saving writes the canonical form of version 2: every key in a fixed
/// order, 2-space indent, a trailing newline, millimetre and degree values rounded to 1e-6, so
/// that save → load → save gives the same bytes.
///
/// Version 2, in the order written:
/// ```
/// { "format": "atelier-project", "version": 2, "name": "tshirt",
///   "body": {"base": "female", "measurements": {"bust": 0.92}}     // or {"mesh": "body.obj"}
///   "materials": [{"name": "main", "fabric": "jersey-knit"}],       // a built-in preset, or
///                 // {"name": ..., "density_kg_per_m2": ..., ...}: the keys of scene materials
///   "next_id": 15,                                                  // above every id
///   "panels": [{"id": 1, "name": "front", "material": "main", "side": "front", "grain_deg": 90,
///       "outline": [{"point": 2, "at": [x, y], "edge": 3, "curve": "line"},
///                   {"point": 4, "at": [..], "edge": 5, "curve": "cubic", "c1": [..],
///                    "c2": [..]},
///                   {"point": 6, "at": [..], "edge": 7, "curve": "arc", "bulge": 0.3}],
///                   // each corner once, with the edge from it to the next one
///       "holes": [{"id": 8, "contour": [corners...]}],
///       "internal_lines": [{"id": 9, "fold_deg": 0, "points": [{"point": 10, "at": [..],
///           "edge": 11, "curve": "line"}, {"point": 12, "at": [..]}]}],  // the last: no edge
///       "darts": [{"id": 13, "leg1": 3, "leg2": 5}],
///       "notches": [{"id": 14, "edge": 3, "t": 0.5}],
///       "placement": {"slot": "torso_front", "offset_mm": [0, 0], "rotation_deg": 0,
///                     "clearance_mm": 20}}],
///   "seams": [{"id": 15, "name": "side", "a": [{"panel": 1, "edge": 5, "t0": 0, "t1": 1}],
///              "b": [...]}],
///   "ease_tolerance_mm": 5,
///   "simulation": {"particle_distance_mm": 10, "model": "fem", ...} }
/// ```
/// Absent optional keys take the defaults of patterns::doc::Panel, Placement and DrapeSettings.
/// A version-1 file (segments by index, seams by panel name) is read into a patterns::Garment
/// and migrated with patterns::fromGarment, ids handed out in file order.

#include "io/limits.h"
#include "io/result.h"

#include "patterns/project.h"

#include <filesystem>
#include <string>
#include <string_view>

namespace atelier::io {

/// The project file version this build reads and writes.
inline constexpr int PROJECT_FORMAT_VERSION = 2;

/// Reads a project from JSON text; `file` names it in errors. Every key is checked: unknown
/// keys, wrong types, non-finite or out-of-range numbers, unknown names (fabric presets,
/// materials, sides, models, integrators) and duplicate names are errors naming the JSON
/// pointer (`shirt.atelier: /panels/3/outline/2/cubic/c1: must be an array of two finite
/// numbers`). In version 2, ids must be unique over the document and below `next_id`, and
/// every reference (dart legs, notch edges, seam panels and edges) must name an object of the
/// right kind (`/seams/0/a/0/edge: panel "front" has no outline edge with id 99`). Then the
/// garment goes through patterns::validateGarment, whose first issue becomes the error. Both
/// `document` and `garment` of the result are filled. Invalid JSON gives the line and column.
/// The body mesh is not looked for (there is no directory to resolve it against): `loadProject`
/// does that.
/// `limits` bounds the nesting of the JSON and what the drape settings ask for.
Result<patterns::Project> parseProject(std::string_view text, const std::string& file,
                                       const Limits& limits = {});

/// Reads a project file. As `parseProject`, and a body mesh path is resolved against the
/// project file's directory and must be a regular file. The project file itself must be a
/// regular file of at most `limits.maxJsonBytes`.
Result<patterns::Project> loadProject(const std::filesystem::path& path, const Limits& limits = {});

/// The canonical version-2 text of `project.document` with the project's name, body and drape
/// settings (`project.garment` is not read). A material whose `material.name` is a
/// built-in preset and whose parameters equal that preset's is written as `"fabric": name`,
/// any other with its full parameters. Non-finite values are written as `null` (which loading
/// refuses).
std::string formatProject(const patterns::Project& project);

/// Writes `formatProject(project)` to `path` atomically.
Result<void> saveProject(const std::filesystem::path& path, const patterns::Project& project);

} // namespace atelier::io
