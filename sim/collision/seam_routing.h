#pragma once
/// Seam routing: a seam's chord that passes through a closed obstacle is pulled around it.

#include "sim/collision/collision_obstacle.h"
#include "sim/core/types.h"

#include <vector>

namespace atelier::sim {

/// Whether the chord p→q passes through a closed obstacle (at its positions of the last
/// update), judged at its quarter points; if so, `via` is the deepest of them moved along the
/// obstacle's outward direction to `clearance` outside it, a point the chord's two ends can be
/// pulled to around the obstacle instead of into it.
bool routeChordAround(const std::vector<CollisionObstacle>& obstacles, const Vec3& p, const Vec3& q,
                      double clearance, Vec3& via);

} // namespace atelier::sim
