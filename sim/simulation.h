#pragma once
/// The step loop: kinematic corrections, integration with step control, reports.

#include "sim/forces/force_model.h"
#include "sim/scene.h"
#include "sim/snapshot.h"

#include <atomic>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace atelier::sim {

/// Counters and figures of a run so far.
struct RunStats {
    long steps = 0;         ///< accepted steps
    long rejectedSteps = 0; ///< steps rejected (error above tolerance or non-finite state)
    /// Accepted steps whose collision corrections stretched an edge beyond
    /// IntegratorOptions::collisionStrainLimit, and the last such stretch in words
    long stretchingSteps = 0;
    std::string stretching;
    long forceEvaluations = 0; ///< derivative evaluations (Runge–Kutta stages, implicit solves)
    long cgIterations = 0;     ///< implicit Euler: conjugate-gradient iterations in total
    long linearSolves = 0;     ///< implicit Euler: linear solves (one per attempted step)
    /// Implicit Euler: solves that ended above their tolerance: stopped at the iteration cap
    /// (`cappedSolves`) or broken down (the system not positive definite along a direction).
    long unconvergedSolves = 0;
    long cappedSolves = 0; ///< of which stopped at the iteration cap
    /// Implicit Euler: largest final relative residual |S(b − A x)| / |S b| of any solve [-]
    double worstRelativeResidual = 0;
    double simTime = 0;  ///< simulated time reached [s]
    double wallTime = 0; ///< wall time spent in steps [s]
    double minDt = 0;    ///< smallest accepted step [s]
    double maxDt = 0;    ///< largest accepted step [s]
    bool finite = true;  ///< the state is finite
    std::string error;   ///< why the run stopped early; empty when it did not
    /// Work done on the cloth by pins and drives, plus the energy the initial state held
    /// (kinetic + elastic + gravitational above the lowest point reached) [J]: an upper bound
    /// for the kinetic energy a dissipative simulation may show.
    double energyInput = 0;
    std::map<std::string, double> stageSeconds; ///< wall time per named stage [s]
    /// Deepest cloth vertex inside an obstacle beyond its thickness, over all output frames
    /// (and the start) [m]; 0 without obstacles.
    double maxPenetration = 0;
    long contacts = 0;        ///< active contacts after the last step
    long weldedSeamPairs = 0; ///< seam pairs welded so far (see SceneSpec::seamWeldDistance)
    /// Largest gap of a pair welded by force (Simulation::weldAllSeams), beyond the weld
    /// distance [m]
    double largestForcedWeld = 0;
    /// Welds put off because merging the pair would have carried cloth through cloth (the
    /// pair stays an elastic and is tried again at the next step), counted per pair and step:
    /// a pair blocked for 100 steps counts 100 [-].
    long deferredWelds = 0;
    /// Per seam pair (SceneSpec::seams): its gap when welded by force beyond the weld
    /// distance, 0 if it closed by itself or is still open [m].
    std::vector<double> forcedWeldGaps;
};

class CollisionStage;

/// Result of `run`, `advance` and `step`.
enum class RunStatus { Finished, Cancelled, Failed };

/// A point on the cloth: a triangle of all cloths' triangles in order (clothTriangles()) and
/// barycentric weights of its three corners (summing to 1).
struct ClothPoint {
    int triangle = 0;
    Vec3 barycentric = Vec3::Constant(1.0 / 3.0);
};

/// A running simulation of one scene. Not thread-safe: one thread steps it and touches it
/// between steps (grab, pin, obstacle poses); other threads read published snapshots
/// (publishTo()), which is all a window's viewport needs.
class Simulation {
  public:
    /// Checks a scene without building it: returns what is wrong, naming the cloth and
    /// vertex or triangle, or nullopt.
    static std::optional<std::string> validate(const SceneSpec& scene);

    /// Builds the step pipeline with only the stages the scene needs. The scene must pass
    /// `validate` (checked; on failure `error()` says why and `run` does nothing).
    explicit Simulation(SceneSpec scene);
    ~Simulation();
    Simulation(const Simulation&) = delete;
    Simulation& operator=(const Simulation&) = delete;

    /// Advances to simulated time `until` [s]. `onFrame(frameIndex, time)` is called at each
    /// output frame (every 1/frameRate s). `cancel`, if given, stops between steps.
    RunStatus run(double until, const std::function<void(int, double)>& onFrame = {},
                  const std::atomic<bool>* cancel = nullptr);
    /// Advances by exactly `dt` [s] of simulated time (one or more internal steps).
    RunStatus advance(double dt);
    /// Takes one step, never past `until` [s]: the steps run(until) takes (they end on output
    /// frames, path keys and obstacle keys), so a run taken step by step, paused and resumed at
    /// any step, gives the same bits as an uninterrupted one. Does nothing at `until`.
    RunStatus step(double until = std::numeric_limits<double>::infinity());
    /// Whether the last step ended on an output frame (also true before the first step).
    bool atFrame() const;
    /// Output frames completed so far (the frame number run() passes to onFrame).
    long frameIndex() const;

    // ---- Touching the cloth between steps (from the thread that steps) ----

    /// Grabs the cloth at `point`: from the next step on, the point's triangle moves with
    /// `target` [m] (each corner keeping its offset from the point), each corner following by
    /// the critically damped law of a tracker-following drive (Drive::followTimeConstant) with
    /// time constant `timeConstant` [s], so a jerky mouse is smoothed and the cloth is never
    /// yanked faster than it can follow. Returns the grab's handle (> 0), or 0 when the
    /// triangle is out of range or all its corners are already held.
    int grab(const ClothPoint& point, const Vec3& target, double timeConstant = 0.02);
    /// Moves a grab's target [m]; false for an unknown handle.
    bool moveGrab(int handle, const Vec3& target);
    /// Lets go; the corners are free from the next step on. False for an unknown handle.
    bool release(int handle);
    /// Grabs held now.
    int grabCount() const;
    /// Holds a vertex (global index) where it is now; false if out of range or already pinned.
    bool pin(int vertex);
    /// Frees a pinned vertex; false if it was not pinned.
    bool unpin(int vertex);
    bool pinned(int vertex) const;
    /// Moves obstacle k to the rigid pose world = R(rotation)·local + translation (rotation
    /// vector [rad], translation [m]), reached `duration` [s] of simulated time from now
    /// (≤ 0: one nominal step, dtNext, from now) along a straight path that the continuous
    /// collision detection sweeps, so the cloth is pushed, not passed through; steps end on
    /// its arrival, after which it is static again. Replaces the obstacle's keys or frames.
    /// False for an unknown obstacle.
    bool setObstaclePose(int k, const Vec3& translation, const Vec3& rotation, double duration = 0);
    /// The same with every vertex's world position given (|V_k|×3) [m] (a body in another pose).
    bool setObstacleFrame(int k, const MatX3& world, double duration = 0);
    /// Global triangles of all cloths, in cloth order (|F|×3): the index space of ClothPoint.
    const MatX3i& clothTriangles() const;

    // ---- Snapshots for other threads ----

    /// Publishes a snapshot (positions and normals of cloth and obstacles, figures) into
    /// `buffer` after every step from now on, and one now; any thread may read() from it at
    /// any moment. nullptr stops publishing (the default: a batch drape needs none). The
    /// buffer must outlive the publishing (a drape session keeps one across simulations).
    void publishTo(SnapshotBuffer* buffer);

    // ---- Sewing, driven by the caller between steps ----
    // A garment is sewn before it is draped: seams close around the body with gravity held
    // and friction lowered, then every pair still open is welded where it is and gravity
    // acts. The caller (patterns::DrapeSession) decides when, raises the events, and calls:

    /// Gravity acts from the next step on, or stops acting; no effect without
    /// SceneSpec::gravity. On by default.
    void setGravity(bool on);
    /// The hinges across welded seams (SceneSpec::seamBending) act from the next step on,
    /// growing from nothing to their stiffness over 0.1 s, or are held off, every seam a free
    /// hinge (a sewing phase holds them until the garment is closed, so that closed parts of a
    /// seam do not hold the rest open); on by default. Energy they hold when switched on counts
    /// as energy put in. No effect without them.
    void setSeamBending(bool on);
    /// Multiplies the friction of every contact (cloth–obstacle and cloth–cloth) from the next
    /// step on, so panels slide around the body to close their seams [-]; 1 by default.
    void setFrictionScale(double scale);
    /// Elastic seams: the reach beyond which a seam pulls with a constant force (see
    /// SceneSpec::seamReach) from the next step on [m]; a longer reach pulls wide gaps harder
    /// (the energy that adds counts as put in). No effect without elastic seams.
    void setSeamReach(double reach);
    /// Seam routing (SceneSpec::seamRouteClearance) on or off from the next step on; on by
    /// default. Off clears the via points.
    void setSeamRouting(bool on);
    /// From the end of the next step on, every seam pair is welded whatever its gap
    /// (RunStats::largestForcedWeld, forcedWeldGaps), except a pair whose merge would carry
    /// cloth through cloth (with self-collision): that one is tried again at every step
    /// (RunStats::deferredWelds).
    void weldAllSeams();
    /// Steps end at `time` [s] (so that the caller can act there), and the step that reaches
    /// it ends with weldAllSeams(): a sewing phase's deadline. < 0 = none (the default).
    void setSewingDeadline(double time);
    /// Every seam pair is welded (false without seams).
    bool seamsWelded() const;
    /// The implicit solve's preconditioner from the next step on (at first the scene's
    /// IntegratorOptions::linearSolver); no effect with other integrators. A drape may sew with
    /// one and settle with another (patterns::DrapeSession::setSettlingSolver).
    void setLinearSolver(LinearSolver solver);
    LinearSolver linearSolver() const;
    /// The step of fixed-step integrators from the next step on [s] (at first the scene's
    /// IntegratorOptions::dt; ignored unless > 0); a rejected step still shrinks it and it
    /// grows back to this. Steps still end on output frames. A drape may settle with a larger
    /// step than it sews with (patterns::DrapeSession::setSettlingStep).
    void setStep(double dt);
    /// The step of fixed-step integrators [s] (setStep(), at first IntegratorOptions::dt).
    double nominalStep() const;

    double time() const;
    const MatX3& positions() const;  ///< (|V|×3) over all cloths [m]
    const MatX3& velocities() const; ///< (|V|×3) [m/s]
    const VecX& masses() const;      ///< (|V|) [kg]
    const RunStats& stats() const;
    const SceneSpec& scene() const;
    /// First global vertex index of each cloth, plus the total at the end: (|cloths|+1).
    const std::vector<int>& clothOffsets() const;
    /// Names of the stages in the step pipeline, in order.
    std::vector<std::string> activeStages() const;
    const std::string& error() const;

    /// Kinetic energy [J].
    double kineticEnergy() const;
    /// Max over all cloth edges of current length / rest length − 1.
    double maxEdgeStrain() const;
    /// Potential energy of the conservative forces and gravity [J] (models without an
    /// energy, such as volino, count as zero).
    double potentialEnergy() const;

    /// Computes the total force (internal + external, without constraint corrections) at the
    /// given state (for benchmarks and tests) [N].
    void evaluateForces(const MatX3& x, const MatX3& v, MatX3& f) const;
    /// The collision stage, or null when the scene has no obstacles and no self-collision.
    const CollisionStage* collision() const;
    /// Exact count of intersecting triangle pairs now (cloth–cloth and cloth–obstacle;
    /// triangles sharing a vertex excluded, welded seam vertices being one vertex, seam
    /// partners not yet welded two); 0 without a collision stage.
    /// `withObstacles`, if given, receives how many of them are cloth–obstacle pairs.
    long intersectingTrianglePairs(long* withObstacles = nullptr) const;
    /// Deepest penetration now (see RunStats::maxPenetration) [m].
    double penetration() const;
    /// Deepest cloth vertex inside the contact layer now: as penetration() but counted from
    /// the obstacle's thickness plus the cloth's, where a resting cloth sits [m]; 0 without
    /// obstacles.
    double contactLayerCrush() const;
    /// Whether seam pair k (SceneSpec::seams) is welded now.
    bool seamPairWelded(std::size_t k) const;
    /// World positions of obstacle k now (|V_k|×3).
    const MatX3& obstaclePositions(int k) const;
    /// The force models in the pipeline (for benchmarks and tests).
    const std::vector<std::unique_ptr<ForceModel>>& forceModels() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

/// Max over edges of |x_i − x_j| / restLength − 1 for a cloth mesh whose vertices start at
/// `offset` in x.
double maxEdgeStrain(const ClothMesh& mesh, const MatX3& x, int offset = 0);

std::string_view integratorName(IntegratorKind kind);
std::optional<IntegratorKind> integratorFromName(std::string_view name);
std::string_view stretchModelName(StretchModel model);
std::optional<StretchModel> stretchModelFromName(std::string_view name);
std::string_view bendingModelName(BendingModel model);
std::optional<BendingModel> bendingModelFromName(std::string_view name);

} // namespace atelier::sim
