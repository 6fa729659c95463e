#include "sim/collision/measures/penetration.h"

#include "sim/collision/distance/obstacle_distance.h"
#include "sim/collision/indexing.h"
#include "sim/collision/triangle_normal.h"
#include "sim/core/parallel.h"

#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace atelier::sim {

double penetrationDepth(std::vector<CollisionObstacle>& obstacles, const MatX3& x,
                        std::vector<double>& depth, const VecX* clothThickness) {
    double worst = 0;
    const std::size_t n = static_cast<std::size_t>(x.rows());
    const double clothMax =
        clothThickness != nullptr && clothThickness->size() > 0 ? clothThickness->maxCoeff() : 0.0;
    for (CollisionObstacle& o : obstacles) {
        const double th = o.spec->thickness;
        if (o.fittedMargin < 0 && !o.moves) {
            o.bvh.refit(o.x1, nullptr, th); // the boxes of the last update hold x1 otherwise
            o.fittedMargin = th;
        }
        const Aabb& box = o.bvh.nodes()[static_cast<std::size_t>(o.bvh.root())].box;
        // Each vertex on its own (its own slot of the distance cache); the largest depth is
        // then taken serially (a maximum: the same for any order).
        depth.assign(n, 0.0);
        const std::int64_t nv = x.rows();
        parallelFor(nv, [&](std::int64_t pp) {
            const int p = static_cast<int>(pp);
            const Vec3 xp = row(x, p);
            // The box holds the obstacle grown by th: a vertex within th + c of it is within c.
            if (box.squaredDistance(xp) > clothMax * clothMax) {
                return;
            }
            const double layer = th + (clothThickness != nullptr ? (*clothThickness)(p) : 0.0);
            double sd;
            if (o.spec->closed) {
                sd = vertexSignedDistance(o, p, xp, layer);
            } else {
                const auto [tri, cp] = o.bvh.closestTriangle(o.x1, xp, layer);
                if (tri < 0) {
                    return;
                }
                const MatX3i& f = o.spec->triangles;
                const Vec3 nf = triangleNormal(row(o.x1, f(tri, 0)), row(o.x1, f(tri, 1)),
                                               row(o.x1, f(tri, 2)));
                const signed char side = o.openSide[static_cast<std::size_t>(p)];
                const double along = nf.dot(xp - cp.point);
                sd = side == 0 ? cp.distance : (along * side >= 0 ? cp.distance : -cp.distance);
            }
            depth[static_cast<std::size_t>(p)] = layer - sd;
        });
        for (double d : depth) {
            worst = std::max(worst, d);
        }
    }
    return worst;
}

} // namespace atelier::sim
