#pragma once
/// Measuring a body mesh as a tailor does: tape girths from plane sections, and checks that a
/// mesh is closed and manifold.

#include "sim/core/types.h"

#include <optional>
#include <vector>

namespace atelier::patterns {

/// Edge and vertex topology of a triangle mesh.
struct MeshTopology {
    long vertices = 0; ///< vertices used by triangles
    long edges = 0;
    long boundaryEdges = 0;       ///< used by one triangle
    long nonManifoldEdges = 0;    ///< used by more than two
    long misorientedEdges = 0;    ///< used twice in the same direction
    long nonManifoldVertices = 0; ///< whose triangles do not form one fan
    long degenerateTriangles = 0; ///< repeating a vertex or of zero area
    int components = 0;           ///< connected by edges
    long eulerCharacteristic = 0; ///< V − E + F (2 for a closed genus-0 surface)

    /// Closed, oriented 2-manifold with no degenerate triangles.
    bool watertight() const {
        return boundaryEdges == 0 && nonManifoldEdges == 0 && misorientedEdges == 0 &&
               nonManifoldVertices == 0 && degenerateTriangles == 0;
    }
};

MeshTopology meshTopology(const sim::MatX3& vertices, const sim::MatX3i& triangles);

/// Volume enclosed by a closed, outward-oriented mesh [m³].
double enclosedVolume(const sim::MatX3& vertices, const sim::MatX3i& triangles);

/// The closed loops where the plane through `point` with normal `normal` cuts the mesh.
std::vector<std::vector<sim::Vec3>> planeSection(const sim::MatX3& vertices,
                                                 const sim::MatX3i& triangles,
                                                 const sim::Vec3& point, const sim::Vec3& normal);

/// Tape-measure girth [m]: the perimeter of the convex hull of the section loop that encloses
/// `point` (a tape spans hollows, like the one between the breasts). nullopt when no loop of
/// the section encloses the point.
std::optional<double> tapeGirth(const sim::MatX3& vertices, const sim::MatX3i& triangles,
                                const sim::Vec3& point, const sim::Vec3& normal);

} // namespace atelier::patterns
