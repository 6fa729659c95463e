#pragma once
/// How deep the cloth is inside the obstacles: the penetration figure of a drape.

#include "sim/collision/collision_obstacle.h"
#include "sim/core/types.h"

#include <vector>

namespace atelier::sim {

/// Deepest cloth vertex inside an obstacle beyond the obstacle's thickness at positions x and
/// the obstacles' positions of the last update: max over vertices and obstacles of
/// max(0, thickness − signed distance) [m]. Exact up to floating point (closest points,
/// angle-weighted pseudo-normals); open obstacles count the side each vertex started on as
/// outside. `depth`: per-vertex scratch. With `clothThickness` (per vertex [m]) the depth is
/// counted from the contact layer instead, max(0, thickness + cloth thickness − signed
/// distance): how far the cloth is pressed into the layer it rests on.
double penetrationDepth(std::vector<CollisionObstacle>& obstacles, const MatX3& x,
                        std::vector<double>& depth, const VecX* clothThickness = nullptr);

} // namespace atelier::sim
