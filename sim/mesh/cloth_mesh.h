#pragma once
/// Triangle-mesh topology of a cloth and its flat rest (pattern) shape.

#include "sim/core/types.h"

#include <optional>
#include <string>

namespace atelier::sim {

/// Topology and rest shape of one cloth piece. Vertex indices are local (0..|V|-1).
struct ClothMesh {
    MatX3i triangles;     ///< (|F|×3), counter-clockwise in the pattern plane
    MatX2 rest;           ///< (|V|×2) pattern coordinates [m]; x = weft, y = warp
    MatX2i edges;         ///< (|E|×2) unique edges, first index < second
    MatX2i edgeTriangles; ///< (|E|×2) the triangles on each side of an edge, -1 on a border
    /// (|H|×4) interior edges as hinges: (edge v0, edge v1, opposite in tri 0, opposite in tri 1).
    /// Triangle 0 is the one in which v0→v1 runs counter-clockwise.
    Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor> hinges;
    VecX restArea; ///< (|F|) rest areas [m²]

    int vertexCount() const { return static_cast<int>(rest.rows()); }
    int triangleCount() const { return static_cast<int>(triangles.rows()); }
};

/// Builds edges, hinges and rest areas. Refuses (returns the message) indices out of range,
/// zero-area or inverted (clockwise) rest triangles, naming the triangle, and non-manifold
/// edges (more than two triangles on one edge), naming the edge's vertices.
/// `minArea` [m²] is the area below which a rest triangle counts as degenerate.
std::optional<std::string> buildClothMesh(const MatX2& rest, const MatX3i& triangles,
                                          ClothMesh& out, double minArea = 1e-12);

/// Lumped vertex masses [kg]: each triangle gives a third of area × density to each vertex.
/// `density` is the areal density [kg/m²]. Returns (|V|).
VecX lumpedMasses(const ClothMesh& mesh, double density);

/// How a generated rectangle is split into triangles.
enum class Triangulation {
    Regular,   ///< grid, diagonals alternating (criss-cross), near-isotropic
    Irregular, ///< interior vertices jittered by up to 40% of the spacing, random diagonals
};

/// Options of a generated rectangle of cloth in the pattern plane.
struct RectangleOptions {
    double width = 1.0;  ///< extent along weft (x) [m]
    double height = 1.0; ///< extent along warp (y) [m]
    int cellsX = 20;     ///< cells along x (vertices = cellsX + 1)
    int cellsY = 20;     ///< cells along y
    Triangulation triangulation = Triangulation::Regular;
    std::uint32_t seed = 1; ///< random seed of the irregular triangulation
};

/// Generates a rectangle [0,width]×[0,height] in the pattern plane. Vertex (i, j) of the grid,
/// i along x, has index j·(cellsX+1) + i, also for the irregular triangulation (whose interior
/// vertices are jittered but keep their indices, so boundary vertices stay on the border).
void makeRectangle(const RectangleOptions& options, MatX2& rest, MatX3i& triangles);

/// Triangle area in 2D, signed (positive when counter-clockwise).
inline double signedArea(const Vec2& a, const Vec2& b, const Vec2& c) {
    return 0.5 * ((b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y()));
}

} // namespace atelier::sim
