#include "sim/collision/trapped_cloth.h"

#include "sim/collision/distance/obstacle_distance.h"
#include "sim/collision/indexing.h"
#include "sim/collision/triangle_normal.h"
#include "sim/core/parallel.h"

#include <queue>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <utility>

namespace atelier::sim {

namespace {

constexpr double UNBOUNDED = std::numeric_limits<double>::infinity();

/// Fits o.hullLo/hullHi, the obstacle's extent along `directions` (a static obstacle's once).
void fitHull(CollisionObstacle& o, const std::array<Vec3, 13>& directions) {
    std::array<double, 13>& lo = o.hullLo;
    std::array<double, 13>& hi = o.hullHi;
    if (o.moves || !o.hullFitted) { // a static obstacle's once
        lo.fill(UNBOUNDED);
        hi.fill(-UNBOUNDED);
        for (Eigen::Index v = 0; v < o.x1.rows(); ++v) {
            const Vec3 q = row(o.x1, static_cast<int>(v));
            for (std::size_t d = 0; d < directions.size(); ++d) {
                const double s = directions[d].dot(q);
                lo[d] = std::min(lo[d], s);
                hi[d] = std::max(hi[d], s);
            }
        }
        o.hullFitted = true;
    }
}

} // namespace

TrappedCloth::TrappedCloth(int vertexCount)
    : m_obstacleOf(static_cast<std::size_t>(vertexCount), -1) {}

long TrappedCloth::count() const {
    long trapped = 0;
    for (int v : m_obstacleOf) {
        trapped += v >= 0 ? 1 : 0;
    }
    return trapped;
}

void TrappedCloth::find(std::size_t k, CollisionObstacle& o, const CollisionMesh& mesh,
                        const CollisionOptions& options, const MatX3& x) {
    if (!o.spec->closed || o.bvh.empty()) {
        return;
    }
    // A vertex outside the obstacle's 26-sided hull (its extent along 13 directions: the axes,
    // the face and the body diagonals) is outside the obstacle: no distance query. Without it,
    // the query from a point far above a smooth surface visits a cap of leaves that grows with
    // the distance (the first check of a large sheet cost more than N log N).
    static const std::array<Vec3, 13> directions = {
        Vec3(1, 0, 0),  Vec3(0, 1, 0),  Vec3(0, 0, 1), Vec3(1, 1, 0),  Vec3(1, -1, 0),
        Vec3(1, 0, 1),  Vec3(1, 0, -1), Vec3(0, 1, 1), Vec3(0, 1, -1), Vec3(1, 1, 1),
        Vec3(1, 1, -1), Vec3(1, -1, 1), Vec3(-1, 1, 1)};
    fitHull(o, directions);
    const std::array<double, 13>& lo = o.hullLo;
    const std::array<double, 13>& hi = o.hullHi;
    const auto outsideHull = [&](const Vec3& p) {
        for (std::size_t d = 0; d < directions.size(); ++d) {
            const double s = directions[d].dot(p);
            if (s < lo[d] || s > hi[d]) {
                return true;
            }
        }
        return false;
    };
    // Each vertex on its own (its own slots of m_obstacleOf and of the distance cache).
    const std::int64_t nv = x.rows();
    parallelFor(nv, [&](std::int64_t pp) {
        const int p = static_cast<int>(pp);
        if (m_obstacleOf[static_cast<std::size_t>(p)] >= 0 || outsideHull(row(x, p))) {
            return;
        }
        const double reach =
            (mesh.thickness[p] + o.spec->thickness) * (1.0 + options.proximityFactor);
        if (vertexSignedDistance(o, p, row(x, p), -reach) < -reach) {
            m_obstacleOf[static_cast<std::size_t>(p)] = static_cast<int>(k);
        }
    });
}

std::vector<int> TrappedCloth::releaseOutside(std::size_t k, const CollisionObstacle& o,
                                              const MatX3& xe) {
    const int ki = static_cast<int>(k);
    std::vector<int> trapped;
    for (int p = 0; p < xe.rows(); ++p) {
        if (m_obstacleOf[static_cast<std::size_t>(p)] != ki) {
            continue;
        }
        // Contacts take over once the vertex is out. Released within the contact reach but still
        // inside, it was pushed out along the surface's normal in one step while its trapped
        // neighbours headed for the entry, and the triangles across the surface got contacts
        // whose sides were taken where they crossed it: through-body ended with its sheet
        // stretched 4.5 times and 24 cloth–body pairs pierced.
        if (signedDistance(o, o.x1, row(xe, p), UNBOUNDED) >= 0) {
            m_obstacleOf[static_cast<std::size_t>(p)] = -1;
        } else {
            trapped.push_back(p);
        }
    }
    return trapped;
}

std::vector<Vec3> TrappedCloth::nearestEntries(std::size_t k, const CollisionObstacle& o,
                                               const CollisionMesh& mesh,
                                               const std::vector<int>& trapped, const MatX3& xe) {
    const int ki = static_cast<int>(k);
    const std::size_t n = static_cast<std::size_t>(xe.rows());
    auto isTrapped = [&](int v) { return m_obstacleOf[static_cast<std::size_t>(v)] == ki; };
    std::vector<Vec3> entries;
    std::vector<double>& dist = m_distance;
    std::vector<int>& source = m_source;
    dist.assign(n, UNBOUNDED);
    source.assign(n, -1);
    m_slot.assign(n, -1);
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
    for (int p : trapped) {
        for (int f : mesh.neighbours[static_cast<std::size_t>(p)]) {
            if (isTrapped(f) || source[static_cast<std::size_t>(f)] >= 0) {
                continue;
            }
            Vec3 closest, outward;
            if (std::isfinite(signedDistance(o, o.x1, row(xe, f), UNBOUNDED, &closest, &outward))) {
                const double d0 = mesh.thickness[f] + o.spec->thickness;
                source[static_cast<std::size_t>(f)] = static_cast<int>(entries.size());
                entries.push_back(closest + 1.5 * d0 * outward);
                dist[static_cast<std::size_t>(f)] = 0;
                queue.emplace(0.0, f);
            }
        }
    }
    while (!queue.empty()) {
        const auto [d, u] = queue.top();
        queue.pop();
        if (d > dist[static_cast<std::size_t>(u)]) {
            continue;
        }
        for (int q : mesh.neighbours[static_cast<std::size_t>(u)]) {
            const double dq = d + (row(xe, q) - row(xe, u)).norm();
            if (isTrapped(q) && dq < dist[static_cast<std::size_t>(q)]) {
                dist[static_cast<std::size_t>(q)] = dq;
                source[static_cast<std::size_t>(q)] = source[static_cast<std::size_t>(u)];
                queue.emplace(dq, q);
            }
        }
    }
    return entries;
}

void TrappedCloth::headings(const CollisionObstacle& o, const CollisionMesh& mesh,
                            const std::vector<int>& trapped, const std::vector<Vec3>& entries,
                            const MatX3& xe, std::vector<Vec3>& target,
                            std::vector<Vec3>& heading) {
    std::vector<int>& slot = m_slot;
    // Target and heading of each trapped vertex (a part with no free border, wholly inside,
    // heads for the nearest surface).
    target.resize(trapped.size());
    heading.resize(trapped.size());
    for (std::size_t i = 0; i < trapped.size(); ++i) {
        const int p = trapped[i];
        slot[static_cast<std::size_t>(p)] = static_cast<int>(i);
        const int s = m_source[static_cast<std::size_t>(p)];
        if (s >= 0) {
            target[i] = entries[static_cast<std::size_t>(s)];
        } else {
            Vec3 closest, outward;
            signedDistance(o, o.x1, row(xe, p), UNBOUNDED, &closest, &outward);
            target[i] = closest + 1.5 * (mesh.thickness[p] + o.spec->thickness) * outward;
        }
        const Vec3 to = target[i] - row(xe, p);
        heading[i] = to.norm() > TINY_LENGTH ? Vec3(to.normalized()) : Vec3::Zero();
    }
    constexpr int SMOOTHING_PASSES = 8;
    std::vector<Vec3> next(trapped.size());
    for (int pass = 0; pass < SMOOTHING_PASSES; ++pass) {
        for (std::size_t i = 0; i < trapped.size(); ++i) {
            Vec3 sum = heading[i];
            for (int q : mesh.neighbours[static_cast<std::size_t>(trapped[i])]) {
                const int j = slot[static_cast<std::size_t>(q)];
                if (j >= 0) {
                    sum += heading[static_cast<std::size_t>(j)];
                }
            }
            next[i] = sum.norm() > TINY_LENGTH ? Vec3(sum.normalized()) : heading[i];
        }
        heading.swap(next);
    }
}

void TrappedCloth::extract(std::size_t k, const CollisionObstacle& o, const CollisionMesh& mesh,
                           double extractionSpeed, double h, MatX3& xe, MatX3& ve) {
    const std::vector<int> trapped = releaseOutside(k, o, xe);
    if (trapped.empty() || !(h > 0)) {
        return;
    }
    // Each trapped vertex is carried out where the cloth around it enters the obstacle (the side
    // it came from), not to the nearest surface, which for a deep vertex may be the far side.
    // The entries are the surface points nearest the free vertices bordering the trapped part;
    // each trapped vertex heads for the one nearest it along the cloth (Dijkstra over the current
    // edge lengths). The headings are then averaged over trapped neighbours, so that the trapped
    // part slides out as one piece: sent each to its own nearest entry, neighbours were pulled
    // toward entries far apart (edges stretched 2.5 times) or onto one point, where they crossed.
    const std::vector<Vec3> entries = nearestEntries(k, o, mesh, trapped, xe);
    std::vector<Vec3> target, heading;
    headings(o, mesh, trapped, entries, xe, target, heading);
    const double maxMove = extractionSpeed * h;
    for (std::size_t i = 0; i < trapped.size(); ++i) {
        const int p = trapped[i];
        const Vec3 to = target[i] - row(xe, p);
        if (to.norm() <= TINY_LENGTH) {
            continue;
        }
        // Headings that the average turned away from the vertex's own entry go straight there.
        const Vec3 dir = heading[i].dot(to) > 0 ? heading[i] : Vec3(to.normalized());
        xe.row(p) += (std::min(maxMove, to.norm()) * dir).transpose();
        ve.row(p).setZero();
    }
}

} // namespace atelier::sim
