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
/// the last update: cloth–cloth and cloth–obstacle. A cloth pair sharing a vertex is not
/// counted; vertices welded together (`welded`: groups of vertex indices, SeamWelds::groups())
/// are one vertex, but seam partners not welded are two: their triangles count when they
/// cross, as an open seam's do. Refits the hierarchies to x (and the obstacles' x1) without
/// margins. `clothObstacle`, if given, receives the cloth–obstacle part of the count; `pairs`
/// is scratch.
long countIntersectingTrianglePairs(const CollisionMesh& mesh, SurfaceBvh& clothBvh,
                                    std::vector<CollisionObstacle>& obstacles, const MatX3& x,
                                    const std::vector<std::vector<int>>& welded,
                                    std::vector<std::pair<int, int>>& pairs, long* clothObstacle);

} // namespace atelier::sim
