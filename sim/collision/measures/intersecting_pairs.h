#pragma once
/// How tangled the cloth is: the exact count of intersecting triangle pairs, cloth–cloth and
/// cloth–obstacle.

#include "sim/collision/bvh.h"
#include "sim/collision/collision_mesh.h"
#include "sim/collision/collision_obstacle.h"
#include "sim/core/types.h"

#include <utility>
#include <vector>

namespace atelier::sim {

/// Exact count of intersecting triangle pairs at positions x and the obstacles' positions of
/// the last update: cloth–cloth (pairs sharing a vertex, or sewn ones, excluded) and
/// cloth–obstacle. Refits the hierarchies to x (and the obstacles' x1) without margins.
/// `clothObstacle`, if given, receives the cloth–obstacle part of the count; `pairs` is
/// scratch.
long countIntersectingTrianglePairs(const CollisionMesh& mesh, SurfaceBvh& clothBvh,
                                    std::vector<CollisionObstacle>& obstacles, const MatX3& x,
                                    std::vector<std::pair<int, int>>& pairs, long* clothObstacle);

} // namespace atelier::sim
