#include "sim/collision/collision_obstacle.h"

#include "sim/collision/indexing.h"
#include "sim/collision/obstacle.h"

#include <algorithm>
#include <cstddef>
#include <limits>

namespace atelier::sim {

CollisionObstacle::CollisionObstacle(const ObstacleSpec& obstacle, int clothVertexCount)
    : spec(&obstacle), moves(obstacleMoves(obstacle)) {
    obstaclePositionsAt(obstacle, 0.0, x1);
    x0 = x1;
    const int nv = static_cast<int>(obstacle.vertices.rows());
    const int nt = static_cast<int>(obstacle.triangles.rows());
    vertexTriangles.assign(static_cast<std::size_t>(nv), {});
    vertexOwner.assign(static_cast<std::size_t>(nv), -1);
    ownedVertices.assign(static_cast<std::size_t>(nt), {});
    ownedEdges.assign(static_cast<std::size_t>(nt), {});
    std::vector<std::array<int, 2>> unique;
    for (int t = 0; t < nt; ++t) {
        for (int k = 0; k < 3; ++k) {
            const int a = obstacle.triangles(t, k), b = obstacle.triangles(t, (k + 1) % 3);
            vertexTriangles[static_cast<std::size_t>(a)].push_back(t);
            if (vertexOwner[static_cast<std::size_t>(a)] < 0) {
                vertexOwner[static_cast<std::size_t>(a)] = t;
                ownedVertices[static_cast<std::size_t>(t)].push_back(a);
            }
            const std::uint64_t key = pairKey(std::min(a, b), std::max(a, b));
            const auto [it, inserted] = edgeIndex.emplace(key, static_cast<int>(unique.size()));
            if (inserted) {
                unique.push_back({std::min(a, b), std::max(a, b)});
                edgeTriangles.push_back({t, -1});
                ownedEdges[static_cast<std::size_t>(t)].push_back(it->second);
            } else {
                edgeTriangles[static_cast<std::size_t>(it->second)][1] = t;
            }
        }
    }
    edges.resize(static_cast<Eigen::Index>(unique.size()), 2);
    for (std::size_t e = 0; e < unique.size(); ++e) {
        edges(static_cast<Eigen::Index>(e), 0) = unique[e][0];
        edges(static_cast<Eigen::Index>(e), 1) = unique[e][1];
    }
    bvh = SurfaceBvh(obstacle.triangles, x1);
    const auto n = static_cast<std::size_t>(clothVertexCount);
    openSide.assign(n, 0);
    distanceValue.assign(n, std::numeric_limits<double>::quiet_NaN());
    distancePoint.resize(static_cast<Eigen::Index>(n), 3);
}

} // namespace atelier::sim
