#include "sim/collision/response/obstacle_velocity.h"

#include "sim/collision/indexing.h"
#include "sim/collision/obstacle.h"

#include <cstddef>

namespace atelier::sim {

void predictObstacleVelocities(std::vector<CollisionObstacle>& obstacles,
                               std::vector<Contact>& contacts, double t, double h) {
    if (!(h > 0)) {
        return;
    }
    bool any = false;
    for (CollisionObstacle& o : obstacles) {
        if (o.moves) {
            obstaclePositionsAt(*o.spec, t + h, o.xNext);
            any = true;
        }
    }
    if (!any) {
        return;
    }
    for (Contact& c : contacts) {
        if (c.obstacle < 0 || !obstacles[static_cast<std::size_t>(c.obstacle)].moves) {
            continue;
        }
        const CollisionObstacle& o = obstacles[static_cast<std::size_t>(c.obstacle)];
        Vec3 velocity = Vec3::Zero();
        for (int k = 0; k < 3; ++k) {
            const int q = c.obstacleVertex[k];
            if (q >= 0) {
                velocity += c.obstacleWeight[k] * (row(o.xNext, q) - row(o.x1, q)) / h;
            }
        }
        c.obstacleVelocity = velocity;
    }
}

} // namespace atelier::sim
