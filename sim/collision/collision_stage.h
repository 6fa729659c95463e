#pragma once
/// The collision stage of the step loop (Volino & Magnenat-Thalmann 1997 §4–6): detection on
/// refitted hierarchies (cloth–obstacle, cloth–cloth with curvature culling), proximity and
/// continuous narrow phase, contact regions with a consistent orientation, and the response
/// as kinematic corrections: positions and velocities (A) after each step, accelerations (B)
/// during the next, with Coulomb friction.
///
/// CollisionStage is a façade over one file per concept:
///  - collision_mesh.h, collision_obstacle.h: the cloths and obstacles as collisions see them;
///  - bvh.h: the hierarchies (the broad phase);
///  - detection/: cloth–obstacle and cloth–cloth contacts, the contact-region vote;
///  - ccd/, distance/, intersection/, predicates/ (geometry.h): the narrow-phase geometry;
///  - response/: position, velocity and acceleration corrections, pinches, obstacle velocities;
///  - fail_safe.h: putting back vertices of features that still cross;
///  - trapped_cloth.h: cloth inside a closed obstacle, carried out;
///  - seam_routing.h: seam chords pulled around obstacles;
///  - measures/: penetration depth and intersecting triangle pairs.

#include "sim/collision/bvh.h"
#include "sim/collision/collision_mesh.h"
#include "sim/collision/collision_obstacle.h"
#include "sim/collision/contact.h"
#include "sim/collision/detection/contact_regions.h"
#include "sim/collision/detection/detection_chunk.h"
#include "sim/collision/detection/obstacle_detection.h"
#include "sim/collision/fail_safe.h"
#include "sim/collision/trapped_cloth.h"
#include "sim/scene.h"

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace atelier::sim {

/// Figures of the collision stage.
struct CollisionFigures {
    long contacts = 0;        ///< active contacts after the last step
    long candidatePairs = 0;  ///< triangle pairs from the hierarchies in the last step
    long continuousHits = 0;  ///< contacts found only by the swept test, in total
    long trappedVertices = 0; ///< cloth vertices inside a closed obstacle now
    long regionFlips = 0;     ///< contacts whose side the region vote changed, in total
    long rolledBack = 0;      ///< vertex-steps sent back to their start by the fail-safe, in total
};

struct CollisionStageProbe; // test access to the detection passes (defined by the tests)

class CollisionStage {
    friend struct CollisionStageProbe;

  public:
    /// `offsets`: first global vertex of each cloth plus the total; `x` the initial positions.
    CollisionStage(const SceneSpec& scene, const std::vector<int>& offsets, const MatX3& x);

    /// Whether the scene needs the stage at all (obstacles, or a cloth with self-collision).
    static bool needed(const SceneSpec& scene);
    bool selfCollision() const { return m_mesh.anySelf; }
    /// Multiplies the friction coefficients of the contacts found from now on (sewing phase).
    void setFrictionScale(double scale) { m_frictionScale = scale; }

    /// After a step from (xs at t0) to (xe, ve at t1): detects contacts (proximity at the end,
    /// swept over the step) and corrects xe and ve (A). Vertices with invMass 0 do not move.
    /// Also used at the start with t0 == t1 and xs == xe.
    void update(double t0, double t1, const MatX3& xs, MatX3& xe, MatX3& ve, const VecX& invMass);

    /// B: corrects the accelerations `a` at stage velocities `vs` so active contacts do not
    /// re-approach, with Coulomb friction (stick below the static threshold, kinetic above).
    /// `h` is the step. Returns the power of the corrections on the cloth Σ m Δa·v [W].
    double correctAccelerations(const MatX3& vs, MatX3& a, const VecX& mass, const VecX& invMass,
                                double h) const;
    /// Implicit integrators: the same constraint and friction on end-of-step velocities.
    void correctVelocities(MatX3& v, const VecX& invMass) const;

    /// Before a step [t, t + h] of an implicit integrator: the contacts with moving obstacles
    /// take the velocity their obstacle point has over this step. Detection gave them the
    /// last step's: on a spinning body that chord is turned by ωh from this step's, and cloth
    /// carried along it drifts outwards by rω²h² a step (measured: 10% strain in 2 s on the
    /// fast-rotating-sphere scene).
    void predictObstacleVelocities(double t, double h);

    /// Deepest cloth vertex inside an obstacle beyond the obstacle's thickness at positions x
    /// and the obstacles' positions of the last update: max over vertices and obstacles of
    /// max(0, thickness − signed distance) [m]. Exact up to floating point (closest points,
    /// angle-weighted pseudo-normals).
    double penetration(const MatX3& x);
    /// Deepest cloth vertex inside the contact layer of an obstacle: max over vertices and
    /// obstacles of max(0, obstacle thickness + cloth thickness − signed distance) [m], at
    /// positions x and the obstacles' positions of the last update. A cloth resting on the
    /// layer gives ≈ 0; penetration(x) is this figure without the cloth's thickness.
    double contactLayerCrush(const MatX3& x);
    /// Exact count of intersecting triangle pairs at positions x and the obstacles' positions of
    /// the last update, cloth–cloth (pairs sharing a vertex or a welded group excluded: see
    /// countIntersectingTrianglePairs) and cloth–obstacle. `clothObstacle`, if given, receives
    /// the cloth–obstacle part of the count.
    long intersectingTrianglePairs(const MatX3& x, const std::vector<std::vector<int>>& welded,
                                   long* clothObstacle = nullptr);

    /// Seam routing: whether the chord p→q passes through a closed obstacle, judged at its
    /// quarter points; if so, `via` is the deepest of them moved along the obstacle's outward
    /// direction to `clearance` outside it, a point the chord's two ends can be pulled to
    /// around the obstacle instead of into it.
    bool routeAround(const Vec3& p, const Vec3& q, double clearance, Vec3& via) const;

    /// Vertices of the cloth–cloth features (self-colliding cloths) that cross each other when
    /// the cloth moves in a straight line from xs to xe, exactly (swept tests, as the
    /// fail-safe's), and the moved vertices of triangles the move brings into an obstacle
    /// (intersecting it at xe and not at xs, against its positions of the last update). For
    /// motions outside a step: welding. Only the triangles around `moved` (the vertices whose
    /// position differs) are tested.
    std::vector<int> crossingVertices(const MatX3& xs, const MatX3& xe,
                                      const std::vector<int>& moved);

    const std::vector<Contact>& contacts() const { return m_contacts; }
    const CollisionFigures& figures() const { return m_figures; }
    /// The motion of obstacle k (its keys or frames in the scene) was changed between steps:
    /// whether it moves is taken anew, and its hierarchy, hull and distances are refitted.
    void obstacleMotionChanged(std::size_t k);
    /// Whether obstacle k moves (its positions may change at every step).
    bool obstacleMoving(std::size_t k) const { return m_obstacles[k].moves; }
    /// World positions of obstacle k at the last update (|V_k|×3).
    const MatX3& obstaclePositions(int k) const {
        return m_obstacles[static_cast<std::size_t>(k)].x1;
    }

  private:
    using ObstacleData = CollisionObstacle;
    using Detection = ObstaclePass;

    /// The detection against obstacle k (detectObstacleContacts), its contacts appended to
    /// m_contacts.
    void detectObstacle(std::size_t k, double h, const MatX3& xs, const MatX3& xe, Detection which);
    /// Appends what a detection pass found in the first `result.pieces` pieces of m_scratch
    /// (contacts, and self-contact keys, sides, reliability) to the contact arrays, in piece
    /// order, and adds up its figures.
    void gather(const DetectionResult& result);

    const SceneSpec& m_scene;
    CollisionMesh m_mesh;
    SurfaceBvh m_clothBvh;
    std::vector<ObstacleData> m_obstacles;

    /// The step's contacts and, per contact, the self-contact region vote's inputs (obstacle
    /// contacts: 0, 0, 1).
    std::vector<Contact> m_contacts;
    std::vector<std::uint64_t> m_contactKey; ///< per contact: memory key (self contacts), else 0
    std::vector<signed char> m_contactSide;  ///< per self vertex–face contact: side of its face
    std::vector<char> m_contactReliable;     ///< side remembered or seen arriving (swept)

    ContactRegions m_regions;
    TrappedCloth m_trapped;
    CrossingFailSafe m_failSafe;
    DetectionScratch m_scratch;
    std::vector<std::pair<int, std::size_t>> m_pinchScratch; ///< (vertex, contact) for markPinches
    std::vector<double> m_depthScratch; ///< penetration(): per vertex, depth beyond the thickness
    double m_frictionScale = 1.0; ///< multiplies the friction of contacts found (sewing phase)
    double m_lastInsideCheck = -1e300;
    CollisionFigures m_figures;
};

} // namespace atelier::sim
