#pragma once
/// The fail-safe after the corrections: cloth vertices of features that still cross each other
/// over the step are put back at their start (which was free of those crossings) and stopped,
/// repeatedly, until no crossing is left. A feature pair that a moving kinematic vertex (a
/// drive) carries through the other cannot be undone that way: its movable vertices are carried
/// along with the drive instead, the pair translated as one, so it does not cross. Exact swept
/// tests, no curvature culling.
///
/// The curvature culling of the contact detection (SelfQueryOptions) rests on the normal cone
/// alone, without Volino & Magnenat-Thalmann's contour test, so a patch whose normals fit in a
/// cone can still be folded or wound onto itself (a corner dragged round by a drive) and meet
/// itself unseen: every step the fail-safe would put the same vertices back, and the cloth
/// would stay frozen there. The triangle pairs the fail-safe finds crossing are therefore
/// watched: the detection tests them whatever the culling says (watchedPairs) until none of
/// them has crossed for WATCH_STEPS steps, so their contacts push them apart.

#include "sim/collision/bvh.h"
#include "sim/collision/collision_mesh.h"
#include "sim/collision/detection/detection_chunk.h"
#include "sim/core/types.h"

#include <utility>
#include <vector>

namespace atelier::sim {

class CrossingFailSafe {
  public:
    /// Puts back (xe = xs, ve = 0) the movable vertices of the cloth–cloth features that cross
    /// over xs → xe, round after round, until none is left (at most 32 rounds). Where a crossing
    /// feature pair holds a moving vertex of zero inverse mass, or one carried already, its
    /// other movable vertices are carried with it instead (xe = xs + that vertex's displacement,
    /// ve = its velocity). Refits `clothBvh` to the swept boxes. Returns the number of
    /// vertex-steps put back or carried.
    long rollBack(const CollisionMesh& mesh, SurfaceBvh& clothBvh, DetectionScratch& scratch,
                  const MatX3& xs, MatX3& xe, MatX3& ve, const VecX& invMass);

    /// Vertices of the cloth–cloth features that cross each other when the cloth moves in a
    /// straight line from xs to xe, testing only the triangles around `moved`.
    std::vector<int> crossingVertices(const CollisionMesh& mesh, SurfaceBvh& clothBvh,
                                      const MatX3& xs, const MatX3& xe,
                                      const std::vector<int>& moved);

    /// Triangle pairs seen crossing in one of the last WATCH_STEPS steps, sorted, each
    /// (smaller, larger) once: the contact detection tests them without curvature culling.
    const std::vector<std::pair<int, int>>& watchedPairs() const { return m_watchedPairs; }

    /// Steps a crossing triangle pair stays watched after it was last seen crossing.
    static constexpr int WATCH_STEPS = 64;

  private:
    /// One detection pass: appends to `hits` the four vertices of every feature pair crossing
    /// over xs → xe.
    void findCrossings(const CollisionMesh& mesh, SurfaceBvh& clothBvh, DetectionScratch& scratch,
                       const MatX3& xs, const MatX3& xe, std::vector<int>& hits);
    /// As findCrossings, over the feature pairs of the triangles with a corner in `moved` only
    /// (each against the triangles its swept box overlaps).
    void findCrossingsAround(const CollisionMesh& mesh, SurfaceBvh& clothBvh, const MatX3& xs,
                             const MatX3& xe, const std::vector<int>& moved,
                             std::vector<int>& hits);
    /// Undoes the crossings `hits` (four vertices each) as rollBack describes, appending the
    /// vertices it moved to `changed`.
    void undoCrossings(const std::vector<int>& hits, const MatX3& xs, MatX3& xe, MatX3& ve,
                       const VecX& invMass, std::vector<int>& changed);

    /// Adds `found` to the watched pairs (or renews them) and rebuilds watchedPairs().
    void watch(const std::vector<std::pair<int, int>>& found);

    /// What the fail-safe did to a vertex in the current step.
    enum class Undone : char { No, PutBack, Carried };
    std::vector<Undone> m_undone; ///< per vertex (all No between steps)
    std::vector<int> m_crossings; ///< four vertices per crossing feature pair
    struct Watched {
        std::pair<int, int> pair;
        int stepsLeft = 0;
    };
    std::vector<Watched> m_watched;                  ///< sorted by pair
    std::vector<std::pair<int, int>> m_watchedPairs; ///< the pairs of m_watched
    std::vector<std::pair<int, int>> m_found;        ///< crossing pairs found this step
};

} // namespace atelier::sim
