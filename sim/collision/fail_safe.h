#pragma once
/// The fail-safe after the corrections: cloth vertices of features that still cross each other
/// over the step are put back at their start (which was free of those crossings) and stopped,
/// repeatedly, until no crossing is left. Exact swept tests, no curvature culling.

#include "sim/collision/bvh.h"
#include "sim/collision/collision_mesh.h"
#include "sim/collision/detection/detection_chunk.h"
#include "sim/core/types.h"

#include <vector>

namespace atelier::sim {

class CrossingFailSafe {
  public:
    /// Puts back (xe = xs, ve = 0) the movable vertices of the cloth–cloth features that cross
    /// over xs → xe, round after round, until none is left (at most 32 rounds). Refits
    /// `clothBvh` to the swept boxes. Returns the number of vertex-steps put back.
    long rollBack(const CollisionMesh& mesh, SurfaceBvh& clothBvh, DetectionScratch& scratch,
                  const MatX3& xs, MatX3& xe, MatX3& ve, const VecX& invMass);

    /// Vertices of the cloth–cloth features that cross each other when the cloth moves in a
    /// straight line from xs to xe, testing only the triangles around `moved`.
    std::vector<int> crossingVertices(const CollisionMesh& mesh, SurfaceBvh& clothBvh,
                                      const MatX3& xs, const MatX3& xe,
                                      const std::vector<int>& moved);

  private:
    /// One detection pass: appends to `marked` the vertices (movable ones only if `invMass` is
    /// given) of features crossing over xs → xe that are not flagged in m_putBack yet, flagging
    /// them.
    void markCrossings(const CollisionMesh& mesh, SurfaceBvh& clothBvh, DetectionScratch& scratch,
                       const MatX3& xs, const MatX3& xe, const VecX* invMass,
                       std::vector<int>& marked);
    /// As markCrossings, over the feature pairs of the triangles with a corner in `moved` only
    /// (each against the triangles its swept box overlaps).
    void markCrossingsAround(const CollisionMesh& mesh, SurfaceBvh& clothBvh, const MatX3& xs,
                             const MatX3& xe, const std::vector<int>& moved, const VecX* invMass,
                             std::vector<int>& marked);

    std::vector<char> m_putBack;    ///< per vertex, put back this step (all 0 between steps)
    std::vector<int> m_putBackList; ///< the vertices put back in the current round
    std::vector<std::vector<int>> m_vertexTriangles; ///< per cloth vertex, lazily
    std::vector<int> m_hits;                         ///< scratch of pairCrossings
};

} // namespace atelier::sim
