#include "sim/collision/measures/intersecting_pairs.h"

#include "sim/collision/indexing.h"
#include "sim/collision/intersection/triangle_triangle.h"

namespace atelier::sim {

long countIntersectingTrianglePairs(const CollisionMesh& mesh, SurfaceBvh& clothBvh,
                                    std::vector<CollisionObstacle>& obstacles, const MatX3& x,
                                    const std::vector<std::vector<int>>& welded,
                                    std::vector<std::pair<int, int>>& pairs, long* clothObstacle) {
    const MatX3i& t = mesh.triangles;
    std::vector<int> one(static_cast<std::size_t>(x.rows())); // per vertex: its welded group's
    for (std::size_t v = 0; v < one.size(); ++v) {
        one[v] = static_cast<int>(v);
    }
    for (const std::vector<int>& group : welded) {
        for (int v : group) {
            one[static_cast<std::size_t>(v)] = group.front();
        }
    }
    long count = 0;
    clothBvh.refit(x, nullptr, 0.0);
    pairs.clear();
    SelfQueryOptions all;
    all.cullingAngle = 4.0; // no culling: the count must be exact
    clothBvh.selfOverlaps(pairs, all);
    for (const auto& [a, b] : pairs) {
        bool shared = false;
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                shared = shared || one[static_cast<std::size_t>(t(a, i))] ==
                                       one[static_cast<std::size_t>(t(b, j))];
            }
        }
        if (!shared && trianglesIntersect(row(x, t(a, 0)), row(x, t(a, 1)), row(x, t(a, 2)),
                                          row(x, t(b, 0)), row(x, t(b, 1)), row(x, t(b, 2)))) {
            ++count;
        }
    }
    long obstacleCount = 0;
    for (CollisionObstacle& o : obstacles) {
        o.bvh.refit(o.x1, nullptr, 0.0);
        o.fittedMargin = o.moves ? -1.0 : 0.0;
        pairs.clear();
        clothBvh.overlaps(o.bvh, pairs);
        const MatX3i& f = o.spec->triangles;
        for (const auto& [a, b] : pairs) {
            if (trianglesIntersect(row(x, t(a, 0)), row(x, t(a, 1)), row(x, t(a, 2)),
                                   row(o.x1, f(b, 0)), row(o.x1, f(b, 1)), row(o.x1, f(b, 2)))) {
                ++count;
                ++obstacleCount;
            }
        }
    }
    if (clothObstacle != nullptr) {
        *clothObstacle = obstacleCount;
    }
    return count;
}

} // namespace atelier::sim
