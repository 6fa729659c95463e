#pragma once
/// Signed distance of a point to a closed obstacle (negative inside), exact up to floating
/// point, and its cached lower bound for cloth vertices near a static obstacle.

#include "sim/collision/collision_obstacle.h"
#include "sim/core/types.h"

namespace atelier::sim {

/// Signed distance of p to closed obstacle o at positions xo (negative inside), searching up to
/// `maxDistance` (+inf: everywhere); +inf when farther. `closest` receives the obstacle's
/// closest point, `outward` the unit direction from it out of the obstacle. Exact up to
/// floating point (closest points, angle-weighted pseudo-normals).
double signedDistance(const CollisionObstacle& o, const MatX3& xo, const Vec3& p,
                      double maxDistance, Vec3* closest = nullptr, Vec3* outward = nullptr);

/// Signed distance of cloth vertex p at xp to closed obstacle o at its positions of the last
/// update (o.x1), exact, or a lower bound of it when that bound is at least `enough`. The
/// distance is 1-Lipschitz, so on a static obstacle it is at least its value last computed for
/// p minus how far p has moved since (o.distanceValue, o.distancePoint): the penetration figure
/// and the inside check skip the vertices clear of the body (they searched the whole body for
/// every vertex near it, 20% of a drape's time). Writes only p's slot of the cache, so it may
/// run for different vertices in parallel.
double vertexSignedDistance(CollisionObstacle& o, int p, const Vec3& xp, double enough);

} // namespace atelier::sim
