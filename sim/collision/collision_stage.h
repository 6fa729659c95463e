#pragma once
/// The collision stage of the step loop (Volino & Magnenat-Thalmann 1997 §4–6): detection on
/// refitted hierarchies (cloth–obstacle, cloth–cloth with curvature culling), proximity and
/// continuous narrow phase, contact regions with a consistent orientation, and the response
/// as kinematic corrections: positions and velocities (A) after each step, accelerations (B)
/// during the next, with Coulomb friction.

#include "sim/collision/bvh.h"
#include "sim/scene.h"

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace atelier::sim {

/// One contact: the constraint n · r ≥ distance on the relative position
/// \f$ r = \sum_k w_k x_k - q \f$ of cloth vertices (up to four, weights w) and an obstacle
/// point q (zero for cloth–cloth).
struct Contact {
    enum class Kind : std::uint8_t { VertexFace, FaceVertex, EdgeEdge, SelfVertexFace, SelfEdgeEdge };
    Kind kind = Kind::VertexFace;
    int vertex[4] = {-1, -1, -1, -1}; ///< global cloth vertices (-1 unused)
    double weight[4] = {0, 0, 0, 0};
    Vec3 obstaclePoint = Vec3::Zero();    ///< q at the end of the step [m]
    Vec3 obstacleVelocity = Vec3::Zero(); ///< dq/dt over the step [m/s]
    Vec3 normal = Vec3::UnitY();          ///< unit direction in which r must stay
    double distance = 0;                  ///< contact distance (sum of thicknesses) [m]
    double staticFriction = 0;
    double kineticFriction = 0;
    /// Friction of a touching contact: Coulomb's law, or, for a vertex pinched between two
    /// obstacles (CollisionStage::markPinches), stuck to the one that grips harder and sliding
    /// freely on the other.
    enum class Grip : std::uint8_t { Coulomb, Stick, Slip };
    Grip grip = Grip::Coulomb;
    bool active = false; ///< touching after the position correction (B acts on it)
    bool swept = false;  ///< found by a swept test only (the pair ended apart)
    int obstacle = -1;   ///< obstacle index, or -1 for cloth–cloth
    /// q as a combination of the obstacle's vertices (up to three: a face point, an edge
    /// point or a vertex), so its velocity can be taken over another step.
    int obstacleVertex[3] = {-1, -1, -1};
    double obstacleWeight[3] = {0, 0, 0};

    void setObstaclePoint(const int* vertices, const double* weights, int count) {
        for (int k = 0; k < count; ++k) {
            obstacleVertex[k] = vertices[k];
            obstacleWeight[k] = weights[k];
        }
    }
};

/// Figures of the collision stage.
struct CollisionFigures {
    long contacts = 0;           ///< active contacts after the last step
    long candidatePairs = 0;     ///< triangle pairs from the hierarchies in the last step
    long continuousHits = 0;     ///< contacts found only by the swept test, in total
    long trappedVertices = 0;    ///< cloth vertices inside a closed obstacle now
    long regionFlips = 0;        ///< contacts whose side the region vote changed, in total
    long rolledBack = 0;         ///< vertex-steps sent back to their start by the fail-safe, in total
};

struct CollisionStageProbe; // test access to the detection passes (defined by the tests)

class CollisionStage {
    friend struct CollisionStageProbe;

  public:
    /// `offsets`: first global vertex of each cloth plus the total; `x` the initial positions.
    CollisionStage(const SceneSpec& scene, const std::vector<int>& offsets, const MatX3& x);

    /// Whether the scene needs the stage at all (obstacles, or a cloth with self-collision).
    static bool needed(const SceneSpec& scene);
    bool selfCollision() const { return m_anySelf; }
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
    /// and the obstacles' positions of the last update: max over vertices and obstacles of max(0, thickness − signed distance)
    /// [m]. Exact up to floating point (closest points, angle-weighted pseudo-normals).
    double penetration(const MatX3& x);
    /// Exact count of intersecting triangle pairs at positions x and the obstacles' positions of
    /// the last update: cloth–cloth
    /// (pairs sharing a vertex excluded) and cloth–obstacle.
    /// `clothObstacle`, if given, receives the cloth–obstacle part of the count.
    long intersectingTrianglePairs(const MatX3& x, long* clothObstacle = nullptr);

    /// Seam routing: whether the chord p→q passes through a closed obstacle, judged at its
    /// quarter points; if so, `via` is the deepest of them moved along the obstacle's outward
    /// direction to `clearance` outside it, a point the chord's two ends can be pulled to
    /// around the obstacle instead of into it.
    bool routeAround(const Vec3& p, const Vec3& q, double clearance, Vec3& via) const;

    /// Vertices of the cloth–cloth features (self-colliding cloths) that cross each other when
    /// the cloth moves in a straight line from xs to xe, exactly (swept tests, as the
    /// fail-safe's). Empty without self-collision. For motions outside a step: welding.
    /// Only the triangles around `moved` (the vertices whose position differs) are tested.
    std::vector<int> crossingVertices(const MatX3& xs, const MatX3& xe,
                                      const std::vector<int>& moved);

    const std::vector<Contact>& contacts() const { return m_contacts; }
    const CollisionFigures& figures() const { return m_figures; }
    /// The motion of obstacle k (its keys or frames in the scene) was changed between steps:
    /// from now on it is treated as moving (hierarchy, hull and distances taken anew).
    void obstacleMotionChanged(std::size_t k);
    /// Whether obstacle k moves (its positions may change at every step).
    bool obstacleMoving(std::size_t k) const { return m_obstacles[k].moves; }
    /// World positions of obstacle k at the last update (|V_k|×3).
    const MatX3& obstaclePositions(int k) const { return m_obstacles[static_cast<std::size_t>(k)].x1; }

  private:
    /// Whether two cloth vertices are the same vertex or sewn together (scene seams, chained
    /// through corners): such vertices count as shared for adjacency, so the triangles on
    /// both sides of a seam are never taken as colliding or intersecting.
    bool same(int a, int b) const {
        return m_alias[static_cast<std::size_t>(a)] == m_alias[static_cast<std::size_t>(b)];
    }
    /// Whether both triangles belong to self-colliding cloths.
    bool selfPair(int ta, int tb) const {
        return m_selfCloth[static_cast<std::size_t>(m_triangleCloth[static_cast<std::size_t>(ta)])] &&
               m_selfCloth[static_cast<std::size_t>(m_triangleCloth[static_cast<std::size_t>(tb)])];
    }

    struct ObstacleData {
        const ObstacleSpec* spec = nullptr;
        SurfaceBvh bvh;
        MatX3 x0, x1;              ///< positions at the step's start and end
        MatX3 xNext;               ///< positions at the end of the coming step (moving ones)
        MatX2i edges;              ///< unique edges
        std::vector<int> edgeOwner; ///< per edge: the triangle that tests it
        std::vector<int> vertexOwner; ///< per vertex: the triangle that tests it
        std::vector<std::vector<int>> vertexTriangles;
        std::vector<std::array<int, 2>> edgeTriangles; ///< per edge: its two triangles
        std::unordered_map<std::uint64_t, int> edgeIndex;
        std::vector<std::vector<int>> ownedVertices, ownedEdges; ///< per triangle
        bool moves = false;
        double fittedMargin = -1; ///< margin of the last refit of a static obstacle (-1: none)
        /// Extent along findTrapped's 13 directions (a 26-sided hull), fitted once if static.
        std::array<double, 13> hullLo{}, hullHi{};
        bool hullFitted = false;
        /// The step's first detection, kept for the one after project() (Detection::Again):
        /// its candidate pairs, the cloth positions it saw, its proximity contacts in pair order
        /// and, per pair, where they start among them (one more entry: the end).
        std::vector<std::pair<int, int>> firstPairs;
        MatX3 firstPositions;
        std::vector<Contact> firstNear;
        std::vector<std::array<int, 2>> firstFeature; ///< per firstNear: (p | q | e, -1 | g)
        std::vector<int> firstNearStart;
    };

    /// First: the step's detection against obstacle k, proximity at xe and swept tests over
    /// xs → xe; with self-collision on, remembered for Again.
    /// Again (after project(), xs == xe): proximity contacts where the cloth is now. Same
    /// contacts in the same order as testing every candidate pair at xe, but only the cloth
    /// triangles that moved since First are tested; the others' are First's proximity
    /// contacts, those whose normal depends on where the cloth started taken again at xe.
    enum class Detection { First, Again };
    void detectObstacle(std::size_t k, double h, const MatX3& xs, const MatX3& xe, Detection which);
    void detectSelf(const MatX3& xs, const MatX3& xe);
    void voteRegions(const MatX3& xe);
    void extractTrapped(std::size_t k, double h, MatX3& xe, MatX3& ve);
    void findTrapped(std::size_t k, const MatX3& x);
    void project(const MatX3& xs, MatX3& xe, MatX3& ve, const VecX& invMass, double h);
    /// Sets Contact::grip of the touching vertex–face obstacle contacts of pinched vertices and
    /// holds each such vertex where the gripping obstacle carried it over the step (xs → xe).
    void markPinches(const MatX3& xs, MatX3& xe, double h);
    /// Fail-safe after the corrections: vertices of cloth primitives that still cross each other
    /// over the step are put back at their start (which was free of those crossings) and
    /// stopped, repeatedly, until no crossing is left.
    void rollBackCrossings(const MatX3& xs, MatX3& xe, MatX3& ve, const VecX& invMass);
    /// One detection pass of the fail-safe: appends to `marked` the vertices (movable ones only
    /// if `invMass` is given) of features crossing over xs → xe that are not flagged in
    /// m_putBack yet, flagging them.
    void markCrossings(const MatX3& xs, const MatX3& xe, const VecX* invMass,
                       std::vector<int>& marked);
    /// As markCrossings, over the feature pairs of the triangles with a corner in `moved` only
    /// (each against the triangles its swept box overlaps).
    void markCrossingsAround(const MatX3& xs, const MatX3& xe, const std::vector<int>& moved,
                             const VecX* invMass, std::vector<int>& marked);
    /// Appends the four vertices of every feature pair of triangles ta, tb (vertex–triangle
    /// both ways, edge–edge; sewn or shared vertices excluded) that crosses over xs → xe.
    void pairCrossings(int ta, int tb, const MatX3& xs, const MatX3& xe,
                       std::vector<int>& hits) const;
    /// Signed distance of cloth vertex p at xp to closed obstacle k, exact, or a lower bound of
    /// it when that bound is at least `enough`. The distance is 1-Lipschitz, so on a static
    /// obstacle it is at least its value last computed for p minus how far p has moved since:
    /// the penetration figure and the inside check skip the vertices clear of the body (they
    /// searched the whole body for every vertex near it, 20% of a drape's time).
    double vertexSignedDistance(std::size_t k, int p, const Vec3& xp, double enough);
    /// Signed distance of p to closed obstacle k at its current positions (negative inside),
    /// searching up to `maxDistance` (+inf: everywhere); +inf when farther.
    double signedDistance(std::size_t k, const MatX3& xo, const Vec3& p, double maxDistance,
                          Vec3* closest = nullptr, Vec3* outward = nullptr) const;

    const SceneSpec& m_scene;
    std::vector<int> m_offsets;
    std::vector<int> m_clothOf;       ///< per global vertex
    VecX m_thickness;                 ///< per global vertex [m]
    MatX3i m_triangles;               ///< all cloth triangles, global vertex indices
    std::vector<int> m_triangleCloth; ///< per triangle
    MatX2i m_edges;                   ///< all cloth edges, global
    std::vector<std::vector<int>> m_ownedVertices, m_ownedEdges; ///< per cloth triangle
    std::vector<std::vector<int>> m_neighbours; ///< per vertex: adjacent vertices
    std::vector<int> m_vertexTriangle;          ///< per vertex: one triangle holding it
    SurfaceBvh m_clothBvh;
    std::vector<ObstacleData> m_obstacles;
    std::vector<char> m_selfCloth;   ///< per cloth: self-collision on
    bool m_anySelf = false;
    double m_maxThickness = 0;

    std::vector<Contact> m_contacts;
    std::vector<std::uint64_t> m_contactKey; ///< per contact: memory key (self contacts), else 0
    std::vector<signed char> m_contactSide;  ///< per self vertex–face contact: side of its face
    std::vector<signed char> m_flippedFrom;  ///< sides before the region vote
    std::vector<char> m_contactReliable;     ///< side remembered or seen arriving (swept)
    std::unordered_map<std::uint64_t, signed char> m_memory; ///< side of each self pair in contact
    std::vector<int> m_trapped;       ///< per vertex: obstacle it is inside, or -1
    std::vector<char> m_extracting;   ///< per cloth: has vertices trapped in the obstacle being detected
    std::vector<std::pair<int, std::size_t>> m_pinchScratch; ///< (vertex, contact) for markPinches
    /// extractTrapped scratch, per vertex: distance along the cloth to the nearest entry, that
    /// entry's index, the vertex's index among the trapped ones.
    std::vector<double> m_extractDistance;
    std::vector<int> m_extractSource, m_extractSlot;
    std::vector<signed char> m_openSide; ///< per (obstacle, vertex): side of an open obstacle
    /// Per (obstacle, vertex): the last signed distance computed exactly (NaN: none) and
    /// where the vertex was then (static closed obstacles; vertexSignedDistance).
    std::vector<double> m_distanceValue;
    MatX3 m_distancePoint;
    std::vector<std::pair<int, int>> m_pairs;
    std::vector<char> m_movedTriangle; ///< Detection::Again: per cloth triangle, moved since First
    std::vector<char> m_putBack;    ///< fail-safe: per vertex, put back this step (all 0 between steps)
    std::vector<int> m_putBackList; ///< fail-safe: the vertices put back in the current round
    double m_frictionScale = 1.0;   ///< multiplies the friction of contacts found (sewing phase)
    /// The friction coefficient of a contact between two materials' coefficients a and b
    /// (their geometric mean), times the current scale.
    double scaledFriction(double a, double b) const;
    double m_lastInsideCheck = -1e300;
    CollisionFigures m_figures;
    std::vector<int> m_alias; ///< (|V|) representative of each vertex's sewn group
    std::vector<std::vector<int>> m_clothVertexTriangles; ///< per cloth vertex, lazily
    std::vector<int> m_crossingHits; ///< scratch of pairCrossings
    std::vector<double> m_depthScratch; ///< penetration(): per vertex, depth beyond the thickness
    /// What one piece of a parallel detection loop found (parallelChunks): concatenated in
    /// piece order, the pieces give what a serial loop gives.
    struct DetectionChunk {
        std::vector<Contact> contacts;
        std::vector<std::uint64_t> keys;  ///< per contact, as m_contactKey
        std::vector<signed char> sides;   ///< per contact, as m_contactSide
        std::vector<char> reliable;       ///< per contact, as m_contactReliable
        std::vector<int> hits;            ///< fail-safe: vertices of crossing features
        std::vector<std::array<int, 2>> features; ///< per obstacle contact: its features (Detection::First)
        long continuousHits = 0;
        void clear() {
            contacts.clear();
            keys.clear();
            sides.clear();
            reliable.clear();
            hits.clear();
            features.clear();
            continuousHits = 0;
        }
    };
    std::vector<DetectionChunk> m_chunks;
    /// Runs body(chunk, pair) over m_pairs in parallel pieces, each piece into its own cleared
    /// DetectionChunk; returns the number of pieces used (the first ones of m_chunks).
    template <class Body>
    std::size_t detectInChunks(Body&& body);
    /// Appends the pieces' contacts (and self-contact keys, sides, reliability) to m_contacts,
    /// in piece order, and adds up their continuous hits.
    void gatherChunks(std::size_t used);
};

} // namespace atelier::sim
