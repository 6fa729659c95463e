#pragma once
/// The state of a Simulation (sim/simulation.h), shared by the files that implement it:
/// simulation.cpp (building, the step loop), simulation_interaction.cpp (grabs, pins, obstacle
/// poses and snapshots between steps). Not part of the engine's interface.

#include "sim/collision/collision_stage.h"
#include "sim/collision/contact_forces.h"
#include "sim/constraints/seam_elastics.h"
#include "sim/constraints/seam_welds.h"
#include "sim/core/block_sparse.h"
#include "sim/forces/seam_bending.h"
#include "sim/integrators/explicit_rk.h"
#include "sim/integrators/filtered_cg.h"
#include "sim/simulation.h"
#include "sim/snapshot.h"

#include <array>
#include <chrono>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace atelier::sim {

namespace detail {
using Clock = std::chrono::steady_clock;

inline double seconds(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double>(b - a).count();
}

/// Accumulates the wall time of a named stage while alive.
class StageTimer {
  public:
    StageTimer(double& slot) : m_slot(slot), m_start(Clock::now()) {}
    ~StageTimer() { m_slot += seconds(m_start, Clock::now()); }
    StageTimer(const StageTimer&) = delete;
    StageTimer& operator=(const StageTimer&) = delete;

  private:
    double& m_slot;
    Clock::time_point m_start;
};

constexpr double INF = std::numeric_limits<double>::infinity();
/// The seam hinges grow from nothing to their stiffness over this long once let act [s].
constexpr double SEAM_BENDING_RAMP = 0.1;

/// A grab (Simulation::grab): the grabbed triangle's vertices follow the target, each by a
/// tracker-following drive appended to the scene's drives.
struct Grab {
    int id = 0;
    std::array<int, 3> vertices{-1, -1, -1}; ///< held vertices (-1: already held otherwise)
    std::array<Vec3, 3> offsets;             ///< each vertex's offset from the grabbed point [m]
};
} // namespace detail

using detail::Clock;
using detail::INF;
using detail::seconds;
using detail::StageTimer;

struct Simulation::Impl {
    SceneSpec scene;
    std::string error;
    std::vector<int> offsets{0};
    int n = 0;
    MatX3 x, v;
    VecX mass, invMass;
    MatX3 pinPosition;                        ///< rows for pinned vertices: their hold position
    std::vector<char> pinned;                 ///< per vertex
    std::vector<int> driveOf;                 ///< per vertex: index of its drive or -1
    std::vector<std::array<int, 2>> allEdges; ///< global edges of all cloths (high damping)
    std::vector<double> allEdgeRest;          ///< their rest lengths [m]
    std::vector<int> edgeCloth;               ///< per edge of allEdges: its cloth
    MatX3 xPreCollision; ///< the step's end before the collision corrections (strain watch)
    std::vector<std::unique_ptr<ForceModel>> models;
    std::vector<std::string> stages;
    std::vector<double*> modelTimers;
    double t = 0;
    double dtNext = 0;               ///< next step to try [s]
    double dtNominal = 0;            ///< fixed-step integrators: the scene's step [s]
    std::string lastRejection;       ///< why the last step was rejected (for error messages)
    double previousErrorRatio = 1.0; ///< rk45: error / tolerance of the last accepted step
    RunStats stats;
    bool failed = false;
    double lowestY = INF;   ///< lowest vertex height reached, for the gravitational energy bound
    double massHeight0 = 0; ///< Σ m_i h_i at the start, h = height along −g [kg·m]
    double baseEnergyInput = 0; ///< initial kinetic + elastic energy + constraint work [J]

    std::unique_ptr<ExplicitRkStepper> rk;
    FilteredCg cg;
    BlockSparseMatrix jacobian;
    MatX3 xNew, vNew, acc, force, forceStart, accEnd, rhs, dv, scratch, xSave, vSave;
    MatX3 dampingForce;     // implicitStep's (∂f/∂v)·v
    std::vector<char> held; ///< implicit Euler: per vertex, whether CG keeps its Δv
    std::unique_ptr<CollisionStage> collision;
    ContactForces contactForces; ///< implicit Euler: the contacts inside the solve
    double hStep = 0;            ///< the step being taken [s]
    double collisionPower = 0;   ///< power of the contact corrections at the step's start [W]
    /// Energy in the solve's contact springs at the step's start, free to become motion [J];
    /// what it gained since the last accepted step counts as put in (the corrections place
    /// vertices at the contact distance, inside the springs' layer).
    double contactPotential = 0;
    double lastContactPotential = 0;
    double* timerCollision = nullptr;

    double* timerForces = nullptr;
    double* timerConstraints = nullptr;
    double* timerIntegrator = nullptr;
    double* timerSolve = nullptr;

    /// Seam welding (sim/constraints/seam_welds.h) and its figures, copied into stats.
    SeamWelds welds;
    /// A welded group whose members lie within this of each other [m] is merged at a step's
    /// start unchecked for crossings: half the thinnest self-colliding cloth's thickness.
    double mergeUnchecked = 0;
    WeldFigures weldFigures;
    MatX3 xPreMerge, vPreMerge; ///< the state before this step's merge

    /// Output frames completed: steps end on frame times (1/frameRate apart).
    long frameIndex = 0;
    double frameTarget = -1; ///< end of the frame being stepped [s]; < 0 between frames

    // Touched between steps (simulation_interaction.cpp).
    std::vector<detail::Grab> grabs;
    /// Obstacles moved by setObstacleFrame/Pose that have not arrived yet.
    std::vector<int> posedObstacles;
    /// Makes the posed obstacles that have arrived static again.
    void settlePosedObstacles();
    MatX3i clothTriangles; ///< (|F|×3) global triangles of all cloths, built on first use
    SnapshotBuffer* snapshots = nullptr; ///< where snapshots are published, if anywhere
    /// Per obstacle: the version of its positions (Snapshot::obstacleVersions) and its
    /// normals computed for that version.
    std::vector<std::uint64_t> obstacleVersion, normalVersion;
    std::vector<MatX3> obstacleNormals;
    long publishedStep = -1; ///< stats.steps at the last publication

    explicit Impl(SceneSpec s) : scene(std::move(s)) {}

    /// Takes the next step toward the next frame time (or `until`, if sooner); `frameDone`
    /// says whether the step reached it. Publishes a snapshot when publishing.
    RunStatus stepToFrame(double until, bool& frameDone);
    /// Fills a snapshot with the state now and publishes it.
    void publishSnapshot();
    const MatX3i& globalTriangles();

    /// Welds the seam pairs that have closed (all once forced: weldAllSeams or the sewing
    /// deadline reached); returns whether a weld group changed.
    bool weldClosedSeams();
    /// Switches the seam hinges to follow the welds, or off while held, counting the energy
    /// they hold when switched on as energy put in.
    void updateSeamHinges();
    /// Imposed seams (B): each open pair's relative acceleration becomes
    /// \f$ -r/\tau^2 - 2\dot r/\tau \f$, split by mass (momentum conserved). Returns the
    /// power of the corrections [W].
    double imposeSeamAccelerations(const MatX3& xs, const MatX3& vs, MatX3& a) const;
    /// Imposed seams in implicit Euler: the same law integrated implicitly on the end-of-step
    /// relative velocities.
    void imposeSeamVelocities(double h, MatX3& vEnd) const;
    bool pairOpen(std::size_t k) const { return !welds.welded(k); }
    SeamElastics* seamElastics = nullptr; ///< the seam model when seams are elastic
    /// The hinges across welded seams (SceneSpec::seamBending), or null.
    SeamBending* seamBending = nullptr;
    bool seamBendingHeld = false; ///< Simulation::setSeamBending(false)
    double seamBendingSince = 0;  ///< time at which the seam hinges were last let act [s]
    bool seamsRouted = false;     ///< some pair has a via point (routing ran this sewing phase)
    /// Seam routing: re-chooses the via points of the open pairs blocked by an obstacle (see
    /// SceneSpec::seamRouteClearance); energy the moved targets add counts as put in.
    void routeSeams();

    // Sewing, set by the caller between steps (Simulation::setGravity and the rest).
    bool gravityOn = true;      ///< gravity acts (with SceneSpec::gravity)
    bool seamRouting = true;    ///< routeSeams() chooses via points
    bool forceWelds = false;    ///< every open pair is welded at each step's end
    double sewingDeadline = -1; ///< steps end there, the one reaching it forcing welds [s]
    double seamPower = 0;       ///< power of the imposed seam corrections at the step's start [W]

    bool hasDrives() const { return !scene.drives.empty(); }
    /// Gravity acts in the step starting at t.
    bool gravityActive() const { return scene.gravity && gravityOn; }

    void build(); // simulation_build.cpp
    /// Positions, velocities, masses, the force models, pins, drives and welds.
    void buildStateAndModels();
    /// The names of the pipeline's stages (only what the scene needs).
    void listStages();
    /// Stage timers, the Jacobian's pattern, the integrator, the collision stage and the
    /// energy the start holds.
    void buildSolver();
    void accelerations(double time, const MatX3& xs, const MatX3& vs, MatX3& a);
    void applyCorrectionsA(double h);
    bool explicitStep(double h, double& errorRatio);
    bool implicitStep(double h);
    bool step(double maxH);
    /// The step to try, at most maxH: cut at drive, obstacle and gravity events; sets the
    /// sewing phase's seam reach, routes and friction for it [s].
    double beginStep(double maxH);
    /// One try of a step of h: integrates, checks divergence, detects and corrects
    /// collisions. Returns whether it is accepted; `errorRatio` is the error estimate over
    /// the tolerance (+inf when the state was not finite or diverged), `work` the energy put
    /// in [J].
    bool attemptStep(double h, double& errorRatio, double& work);
    /// What to report when the collision corrections (xPreCollision → xNew) left an edge
    /// stretched beyond IntegratorOptions::collisionStrainLimit and longer than both before
    /// the corrections and at the step's start (x); empty otherwise.
    std::string collisionStretch() const;
    /// After an accepted step: welds closed seams and merges weld groups.
    void weldAfterStep();
    /// Whether moving the welded vertices from `before` to `after` carries cloth through cloth.
    SeamWelds::CrossingTest weldCrossingTest();
    /// Counters, the lowest point and the next step size after an accepted step.
    void endStep(double h, double errorRatio);
    double constraintPower(const MatX3& f, const MatX3& a, const MatX3& vel) const;
    /// Whether some vertex held by a drive moves (then the constraint does work).
    bool heldVerticesMove() const;
    /// Sets invMass: 0 for vertices held at time t (pins, exact drives not yet released).
    void updateHeld();
    /// Energy put in so far (see RunStats::energyInput), with `xs` counted for the lowest point.
    double energyBound(const MatX3& xs) const;
};

} // namespace atelier::sim
