#pragma once
/// The cloths as the collision stage sees them: one mesh over all cloths in global vertex
/// indices, with the features each triangle tests, adjacency, thicknesses, and sewn vertices
/// taken as one.

#include "sim/core/types.h"
#include "sim/scene.h"

#include <cstddef>
#include <vector>

namespace atelier::sim {

/// Topology and thickness of the scene's cloths for collisions (ipc-toolkit's CollisionMesh).
/// Each vertex and each edge is owned by one of its triangles, so a pair of triangles tests
/// each of its feature pairs once.
struct CollisionMesh {
    CollisionMesh() = default;
    /// `offsets`: first global vertex of each cloth plus the total.
    CollisionMesh(const SceneSpec& scene, const std::vector<int>& offsets);

    std::vector<int> clothOf;       ///< per global vertex: its cloth
    VecX thickness;                 ///< per global vertex [m]
    MatX3i triangles;               ///< all cloth triangles, global vertex indices (|F|×3)
    std::vector<int> triangleCloth; ///< per triangle: its cloth
    MatX2i edges;                   ///< all cloth edges, global (|E|×2)
    std::vector<std::vector<int>> ownedVertices, ownedEdges; ///< per triangle
    std::vector<std::vector<int>> neighbours;                ///< per vertex: adjacent vertices
    std::vector<int> vertexTriangle;               ///< per vertex: one triangle holding it
    std::vector<std::vector<int>> vertexTriangles; ///< per vertex: every triangle holding it
    std::vector<char> selfCloth;                   ///< per cloth: self-collision on
    bool anySelf = false;                          ///< some cloth has self-collision on
    double maxThickness = 0;                       ///< largest cloth thickness [m]
    std::vector<int> alias; ///< (|V|) representative of each vertex's sewn group

    /// Whether two cloth vertices are the same vertex or sewn together (scene seams, chained
    /// through corners): such vertices count as shared for adjacency, so the triangles on
    /// both sides of a seam are never taken as colliding or intersecting.
    bool same(int a, int b) const {
        return alias[static_cast<std::size_t>(a)] == alias[static_cast<std::size_t>(b)];
    }
    /// Whether both triangles belong to self-colliding cloths.
    bool selfPair(int ta, int tb) const {
        return selfCloth[static_cast<std::size_t>(triangleCloth[static_cast<std::size_t>(ta)])] &&
               selfCloth[static_cast<std::size_t>(triangleCloth[static_cast<std::size_t>(tb)])];
    }

    /// The triangles holding any of `vertices`, sorted, each once.
    std::vector<int> trianglesAround(const std::vector<int>& vertices) const;
};

} // namespace atelier::sim
