#pragma once
/// An obstacle as the collision stage sees it: its topology (unique edges, the features each
/// triangle tests), its hierarchy, its positions over the step, and what the stage keeps per
/// obstacle between detections.

#include "sim/collision/bvh.h"
#include "sim/collision/contact.h"
#include "sim/core/types.h"
#include "sim/scene.h"

#include <array>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

namespace atelier::sim {

/// One obstacle of the scene in the collision stage.
struct CollisionObstacle {
    /// Topology and hierarchy of `obstacle` at its pose at t = 0; per-vertex state for
    /// `clothVertexCount` cloth vertices.
    CollisionObstacle(const ObstacleSpec& obstacle, int clothVertexCount);

    const ObstacleSpec* spec = nullptr;
    SurfaceBvh bvh;
    MatX3 x0, x1;                 ///< positions at the step's start and end
    MatX3 xNext;                  ///< positions at the end of the coming step (moving ones)
    MatX2i edges;                 ///< unique edges
    std::vector<int> edgeOwner;   ///< per edge: the triangle that tests it
    std::vector<int> vertexOwner; ///< per vertex: the triangle that tests it
    std::vector<std::vector<int>> vertexTriangles;
    std::vector<std::array<int, 2>> edgeTriangles; ///< per edge: its two triangles
    std::unordered_map<std::uint64_t, int> edgeIndex;
    std::vector<std::vector<int>> ownedVertices, ownedEdges; ///< per triangle
    bool moves = false;
    double fittedMargin = -1; ///< margin of the last refit of a static obstacle (-1: none)
    /// Extent along TrappedCloth::find's 13 directions (a 26-sided hull), fitted once if static.
    std::array<double, 13> hullLo{}, hullHi{};
    bool hullFitted = false;
    /// The step's first detection, kept for the one after the corrections (ObstaclePass::Again):
    /// its candidate pairs, the cloth positions it saw, its proximity contacts in pair order
    /// and, per pair, where they start among them (one more entry: the end).
    std::vector<std::pair<int, int>> firstPairs;
    MatX3 firstPositions;
    std::vector<Contact> firstNear;
    std::vector<std::array<int, 2>> firstFeature; ///< per firstNear: (p | q | e, -1 | g)
    std::vector<int> firstNearStart;
    /// Per cloth vertex: the side of an open obstacle it started on (0: not known yet).
    std::vector<signed char> openSide;
    /// Per cloth vertex: the last signed distance computed exactly (NaN: none) and where the
    /// vertex was then (static closed obstacles; vertexSignedDistance).
    std::vector<double> distanceValue;
    MatX3 distancePoint;
};

} // namespace atelier::sim
