#pragma once
/// Constrained Delaunay meshing of a planar domain (CGAL behind a small interface, so that its
/// heavy headers stay in one file).

#include "sim/core/types.h"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace atelier::patterns {

struct TriangulationInput {
    std::vector<sim::Vec2> points; ///< boundary and internal-line points [m]
    /// Constrained edges (indices into points): the closed boundary loops and internal lines.
    /// They stay mesh edges and are never split, so boundary points keep their places.
    std::vector<std::array<int, 2>> constraints;
    /// A point inside each hole: the regions holding them are left empty.
    std::vector<sim::Vec2> holeSeeds;
    double maxEdge = 0.01;   ///< target longest edge of the inner triangles [m]
    double minAngleDeg = 25; ///< smallest angle asked of the refinement [deg]
    /// CGAL's Lloyd smoothing visits vertices in memory-address order, so its result moved
    /// with the heap layout (the same project meshed differently run to run): off by default.
    int lloydIterations = 0; ///< smoothing of the inner vertices after refinement
};

struct TriangulationOutput {
    /// The input points first, in order, then the points the refinement added [m].
    std::vector<sim::Vec2> points;
    sim::MatX3i triangles; ///< counter-clockwise, inside the domain only
};

/// Meshes the region bounded by the constraints (outside the holes). Returns what went wrong
/// or nullopt.
std::optional<std::string> triangulate(const TriangulationInput& input, TriangulationOutput& out);

} // namespace atelier::patterns
