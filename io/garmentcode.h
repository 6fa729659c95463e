#pragma once
/// GarmentCode / pygarment pattern specifications (JSON) imported as an Atelier project:
/// panels with 2D vertices and edges (straight, quadratic and cubic Béziers with control points
/// in the edge's frame, circular arcs, and the older dataset's single relative control point),
/// `units_in_meter`, each panel's 3D translation and XYZ Euler rotation, and stitches between
/// panel edges. docs/garmentcode.md describes the mapping.
///
/// Their 3D placement is for their own body; ours is slot-based (patterns::Placement). Each
/// panel keeps its drawing; its slot, side, rotation and offset are chosen so that the panels
/// sit around our body as they sat around theirs: sleeves (panels far to the side) on the arm
/// slots, the rest on the torso or waist slots by the direction from the garment's axis,
/// heights anchored at the shoulder (torso), the waist (waist slots) or 3 cm below the shoulder
/// joint (arms).

#include "io/limits.h"
#include "io/result.h"

#include "patterns/body.h"
#include "patterns/project.h"

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace atelier::io {

struct GarmentCodeOptions {
    /// Fabric preset (assets/materials/fabrics.json) of every panel.
    std::string fabric = "cotton";
    /// Slots of the panels that are not sleeves: "torso", "waist", or "auto": torso slots when
    /// the garment has sleeves, is taller than 0.75 m or reaches above 1.25 m (a GarmentCode
    /// body stands on y = 0), waist slots otherwise (a skirt).
    std::string slots = "auto";
    double clearance = 0.03; ///< gap kept between each placed panel and the body [m]
};

struct GarmentCodeImport {
    patterns::Project project;
    /// What could not be mapped exactly, each naming the panel and edge or stitch
    /// (`panel "front": edge 3: curvature type "spline" is not supported; imported straight`).
    std::vector<std::string> warnings;
};

/// Reads a specification from JSON text (`//` and `/* */` comments allowed, as in their
/// annotated template); `file` names it in errors. `body` gives the slots the panels are placed
/// on (the project's body is the default mannequin, the one `body` should be). Bad input is an
/// Error naming the JSON pointer (`spec.json: /pattern/panels/front/edges/2/endpoints: vertex 9
/// does not exist (the panel has 6)`); coordinates beyond `limits.maxSceneCoordinate` and
/// panels beyond patterns::MAX_PANEL_EXTENT are refused.
Result<GarmentCodeImport> parseGarmentCode(std::string_view text, const std::string& file,
                                           const patterns::Body& body,
                                           const GarmentCodeOptions& options = {},
                                           const Limits& limits = {});

/// Reads a specification file (a regular file of at most `limits.maxJsonBytes`); the project is
/// named after the file (`shirt_mean_specification.json` → `shirt_mean_specification`).
Result<GarmentCodeImport> importGarmentCode(const std::filesystem::path& path,
                                            const patterns::Body& body,
                                            const GarmentCodeOptions& options = {},
                                            const Limits& limits = {});

} // namespace atelier::io
