#include "sim/collision/seam_routing.h"

#include "sim/collision/distance/obstacle_distance.h"

#include <limits>

namespace atelier::sim {

bool routeChordAround(const std::vector<CollisionObstacle>& obstacles, const Vec3& p, const Vec3& q,
                      double clearance, Vec3& via) {
    // Only a chord that enters an obstacle is routed. One that merely passes within the
    // clearance is the normal case for a seam lying on the body (its ends rest a contact
    // distance off it, and on a convex part the chord dips below that); routing those pulled
    // both ends outwards instead of together, and the tshirt's armpit seams stayed 3-4 cm open.
    constexpr double INF = std::numeric_limits<double>::infinity();
    double deepest = 0;
    for (const CollisionObstacle& o : obstacles) {
        if (!o.spec->closed) {
            continue;
        }
        for (const double s : {0.5, 0.25, 0.75}) {
            const Vec3 point = (1 - s) * p + s * q;
            Vec3 closest, outward;
            const double d = signedDistance(o, o.x1, point, INF, &closest, &outward);
            if (d < deepest) {
                deepest = d;
                via = closest + clearance * outward;
            }
        }
    }
    return deepest < 0;
}

} // namespace atelier::sim
