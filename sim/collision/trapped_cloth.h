#pragma once
/// Cloth trapped inside a closed obstacle: found by an inside check (signed distance below the
/// contact reach), carried out where the cloth around it enters the obstacle. Trapped vertices
/// get no ordinary contacts with that obstacle until they are out.

#include "sim/collision/collision_mesh.h"
#include "sim/collision/collision_obstacle.h"
#include "sim/core/types.h"
#include "sim/scene.h"

#include <cstddef>
#include <vector>

namespace atelier::sim {

class TrappedCloth {
  public:
    TrappedCloth() = default;
    explicit TrappedCloth(int vertexCount);

    /// Per cloth vertex: the obstacle it is inside, or -1 (|V|).
    const std::vector<int>& obstacleOf() const { return m_obstacleOf; }
    /// Number of cloth vertices inside an obstacle now.
    long count() const;

    /// Marks the cloth vertices at x deeper inside closed obstacle k (o) than the contact reach
    /// as trapped in it; vertices trapped already keep their obstacle.
    void find(std::size_t k, CollisionObstacle& o, const CollisionMesh& mesh,
              const CollisionOptions& options, const MatX3& x);

    /// Releases the vertices trapped in obstacle k that are outside it at xe, and moves the
    /// others toward where the cloth around them enters it, at most `extractionSpeed`·h each,
    /// stopping them (ve = 0).
    void extract(std::size_t k, const CollisionObstacle& o, const CollisionMesh& mesh,
                 double extractionSpeed, double h, MatX3& xe, MatX3& ve);

  private:
    /// Releases the vertices trapped in obstacle k that are out of it at xe; returns the others.
    std::vector<int> releaseOutside(std::size_t k, const CollisionObstacle& o, const MatX3& xe);
    /// Entry points of the trapped part (just outside the surface points nearest the free
    /// vertices bordering it), and per vertex the entry nearest along the cloth (m_source,
    /// Dijkstra over the current edge lengths).
    std::vector<Vec3> nearestEntries(std::size_t k, const CollisionObstacle& o,
                                     const CollisionMesh& mesh, const std::vector<int>& trapped,
                                     const MatX3& xe);
    /// Per trapped vertex: its target (its entry, or the nearest surface for a part with no
    /// free border) and its unit heading there, averaged over trapped neighbours.
    void headings(const CollisionObstacle& o, const CollisionMesh& mesh,
                  const std::vector<int>& trapped, const std::vector<Vec3>& entries,
                  const MatX3& xe, std::vector<Vec3>& target, std::vector<Vec3>& heading);

    std::vector<int> m_obstacleOf; ///< per vertex: obstacle it is inside, or -1
    /// extract scratch, per vertex: distance along the cloth to the nearest entry, that entry's
    /// index, the vertex's index among the trapped ones.
    std::vector<double> m_distance;
    std::vector<int> m_source, m_slot;
};

} // namespace atelier::sim
