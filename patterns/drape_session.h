#pragma once
/// The drape session: the one owner of a drape's pipeline (body → meshes → scene → simulation
/// → rest → figures). The command line, batch jobs, tests and the window all drive it; none
/// re-implements it. One thread drives it (prepare, advance, runUntil, edits); any thread may
/// pause or cancel it, read its phase and copy its latest snapshot.

#include "patterns/assemble.h"
#include "patterns/body.h"
#include "patterns/fit.h"
#include "patterns/mesh.h"
#include "patterns/project.h"
#include "patterns/sewing.h"
#include "patterns/triangulation_cache.h"

#include "sim/core/result.h"
#include "sim/simulation.h"
#include "sim/snapshot.h"

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace atelier::patterns {

/// Where a drape is. Sewing: seams close while gravity waits; settling: the garment falls and
/// comes to rest; at rest and failed are final until something changes.
enum class DrapePhase { Empty, Placing, Sewing, Settling, AtRest, Failed };
std::string_view phaseName(DrapePhase phase);

/// Something that happened during a drape, raised by the session as it steps.
struct DrapeEvent {
    enum class Kind {
        Placed,      ///< prepared: panels placed around the body, nothing stepped yet
        SeamsSewn,   ///< every seam pair closed by itself: sewing ends
        ForcedWelds, ///< sewing time is up: pairs still open were welded where they were
        GravityOn,   ///< gravity acts from now on
        AtRest,      ///< the garment has come to rest
        TimeLimit,   ///< the simulated time limit was reached before rest
        Failed,      ///< the simulation stopped with an error
        Restarted,   ///< an edit rebuilt the simulation (the message says which)
    };
    Kind kind = Kind::Placed;
    double time = 0;     ///< drape time when it happened [s]
    std::string message; ///< for a person: what happened, with figures
};
std::string_view eventName(DrapeEvent::Kind kind);

/// Why advance() or runUntil() returned.
enum class DrapeStatus {
    Running,   ///< advance(): the time asked for has passed, the drape goes on
    Stopped,   ///< runUntil(): the caller's predicate said stop
    Paused,    ///< pause() was called (from any thread); call again to resume
    Cancelled, ///< cancel() was called; the state so far is kept (it can be exported)
    AtRest,
    TimeLimit,
    Failed,
};

/// A drape's figures: what its report says.
struct DrapeFigures {
    DrapePhase phase = DrapePhase::Empty;
    bool rested = false;
    bool timeLimitReached = false;
    double time = 0;                   ///< drape time [s] (simulated, across restarts)
    double restTime = -1;              ///< drape time at which rest was reached, or −1 [s]
    double sewnAt = -1;                ///< drape time at which sewing ended, or −1 [s]
    double stepSeconds = 0;            ///< wall time spent stepping [s]
    double kineticEnergyPerVertex = 0; ///< mean, now [J]
    double seamGapMax = 0;             ///< largest distance between sewn pairs now [m]
    double areaRatio = 0;              ///< cloth area over rest area now [-]
    double startPenetration = 0;       ///< deepest cloth vertex inside the body as placed [m]
    /// Cloth triangle pairs intersecting each other as placed (panels placed through each
    /// other: the engine keeps cloth from crossing, it cannot undo a crossing it starts with).
    long startIntersectingPairs = 0;
    /// Triangle pairs of different panels intersecting as first placed (as the simulation
    /// starts), before `placementLifts` cleared them (all of them when
    /// startIntersectingPairs is 0).
    long placedCrossings = 0;
    std::vector<PlacementLift> placementLifts; ///< panels moved on their slots to clear others
    std::vector<ForcedWeld> forcedWelds;       ///< seams welded by force, widest first
    long triangles = 0;
    long seamPairs = 0;
    double meshSeconds = 0; ///< wall time of the last meshing [s]
    double minAngleDeg = 0; ///< smallest triangle angle of the meshes [deg]
    int panelsMeshed = 0;   ///< panels triangulated by the last prepare (the rest reused)
    std::string error;      ///< why the drape failed, if it did
    int pins = 0;           ///< garment pins holding now
    /// Largest distance of a pinned vertex from where its pin holds it now [m]: 0 unless the
    /// engine let a held vertex move.
    double pinDisplacementMax = 0;
};

/// A pin the window added or removed: garment panel index, its index in the panel's pins, and
/// the pin.
struct PinnedVertex {
    int panel = 0;
    int index = 0;
    Pin pin;
};

/// Supplies the body a project drapes on (the io layer loads mesh bodies and builds the
/// mannequin with its measurement checks). Called only when the project's body source changes.
using BodyProvider = std::function<Result<Body>(const BodySource& source)>;

/// The step a window drapes with, for `settings`: the project's step `dt`, enlarged where the
/// mesh is coarse enough for it. The step may reach the particle distance × 1 s/m (20 ms at
/// 20 mm, never above 20 ms); of the steps up to that, the largest that divides an output frame
/// (1/30 s) evenly, since steps end on frame times (a 10 ms step takes four per frame: 10, 10,
/// 10 and 3.3 ms). A project whose step is already at or above that keeps it. At 20 mm: 1/60 s,
/// two steps a frame instead of four; the four samples drape clean with it, and faster in wall
/// time per simulated second (docs/benchmarks.md, "Threads, a shared machine and interactive
/// speed"; docs/decisions/025-interactive-step.md) [s].
double interactiveStep(const DrapeSettings& settings);

/// The largest step interactiveStep() takes [s]: the 20 mm samples drape clean at 20 ms; at
/// 1/30 s the 20 mm tshirt keeps a 16 mm seam gap at rest.
inline constexpr double MAX_INTERACTIVE_STEP = 0.02;

/// The implicit solve's preconditioner of interactive drapes once sewing has ended: block
/// IC(0). Sewing keeps the project's (block-Jacobi: the seams' pull was tuned with its inexact
/// solves, and the 20 mm tshirt sewn with block IC(0) welds a 5.7 mm pair by force); settling,
/// where the 20 mm skirt spent 14,485 of its 17,242 block-Jacobi iterations and its four capped
/// solves, takes 2.4× fewer iterations in all with it (7,323, none capped), the tshirt 1.3×
/// fewer (4,343 against 5,548), both draping exactly as far as sewn
/// (docs/decisions/028-interactive-settling-solver.md).
inline constexpr sim::LinearSolver INTERACTIVE_SETTLING_SOLVER =
    sim::LinearSolver::BlockIncompleteCholesky;

/// Interactive drapes once sewn: while no garment vertex moves faster than this share of the
/// particle distance per output frame, the drape steps twice as long as interactiveStep() (or
/// less, to divide a frame evenly: one frame, 1/30 s, at 20 mm; 1/60 s at 15 mm); above twice
/// it, at interactiveStep() again (the gap keeps it from switching every frame). A grab held
/// keeps interactiveStep(). Three times as long (a frame at 15 mm) left the 15 mm dress 116%
/// strained at rest. At 20 mm the slow limit is 0.3 m/s, where the four
/// samples at rest still move single vertices at 0.1-0.28 m/s (contacts): settling takes
/// half the steps, the 20 mm tshirt and skirt drape faster than real time and the four rest
/// clean (docs/decisions/032-interactive-settling-step.md).
inline constexpr double INTERACTIVE_SETTLING_SPEED = 0.5;

class DrapeSession {
  public:
    explicit DrapeSession(BodyProvider bodies);
    ~DrapeSession();
    DrapeSession(const DrapeSession&) = delete;
    DrapeSession& operator=(const DrapeSession&) = delete;

    // ---- Inputs ----

    /// The project to drape. Nothing is computed until prepare(); what still applies (the
    /// body, panel meshes) is kept.
    void setProject(Project project);
    const Project& project() const { return m_project; }

    // ---- The pipeline ----

    /// Builds what changed (the body once per body source, the meshes of changed panels),
    /// places the panels and builds the simulation: phase Placing. Warnings (seam ease) go to
    /// warnings().
    Result<void> prepare();
    /// Takes one step (prepares first if needed).
    DrapeStatus step();
    /// Steps until `dt` [s] of drape time has passed, or the drape ends (rest, time limit,
    /// failure), or it is paused or cancelled. Prepares first if needed.
    DrapeStatus advance(double dt);
    /// Steps until the drape ends, it is paused or cancelled, or stop(*this) says so (asked
    /// after every step).
    DrapeStatus runUntil(const std::function<bool(const DrapeSession&)>& stop = {});
    /// Any thread: advance()/runUntil() return after the current step (Paused). Resuming is
    /// calling them again; the steps are those of a run that was never paused.
    void pause() { m_pause.store(true); }
    /// Any thread: advance()/runUntil() return after the current step (Cancelled).
    void cancel() { m_cancel.store(true); }
    /// Stepping thread, between steps: a touch (a grab, a pin) wakes a drape that stopped at
    /// rest or at its time limit. It settles again; its rest check starts over and its time
    /// limit counts from now. Does nothing before prepare() or after a failure.
    void wake();
    /// Any thread.
    DrapePhase phase() const { return m_phase.load(); }
    /// At rest, failed, or at the time limit.
    bool finished() const;
    /// Events since the last call, oldest first.
    std::vector<DrapeEvent> takeEvents();
    /// Called on the stepping thread after every step that ends an output frame (frame
    /// number, drape time [s], mean kinetic energy per vertex [J]).
    void onFrame(std::function<void(long, double, double)> callback) {
        m_onFrame = std::move(callback);
    }

    // ---- Touching the drape (between steps, from the stepping thread) ----

    /// Grab, pin, obstacle poses: the engine's own API (null before prepare()).
    sim::Simulation* simulation() { return m_simulation.get(); }
    const sim::Simulation* simulation() const { return m_simulation.get(); }
    /// Publishes a snapshot after every step into snapshots() (off by default).
    void setPublishing(bool on);
    /// Steps with interactiveStep() instead of the project's step (off by default): a window
    /// drapes so, and `atelier-cli bench drape` measures it. Applies from the next prepare()
    /// or rebuild; the project's settings are not changed.
    void setInteractive(bool on) { m_interactive = on; }
    bool interactive() const { return m_interactive; }
    /// Interactive drapes: the preconditioner once sewing has ended (by default
    /// INTERACTIVE_SETTLING_SOLVER); nullopt keeps the project's throughout. Applies from the
    /// next prepare() or rebuild, or the end of the sewing under way.
    void setSettlingSolver(std::optional<sim::LinearSolver> solver) { m_settlingSolver = solver; }
    std::optional<sim::LinearSolver> settlingSolver() const { return m_settlingSolver; }
    /// Interactive drapes: longer steps while the sewn garment is slow
    /// (INTERACTIVE_SETTLING_SPEED; on by default). Applies from the next frame.
    void setSettlingStep(bool on) { m_settlingStep = on; }
    bool settlingStep() const { return m_settlingStep; }
    /// Settling steps taken longer than interactiveStep() so far (settlingStep()), across
    /// restarts.
    long frameSteps() const { return m_frameSteps; }
    /// Any thread may read() the latest snapshot from here, across restarts.
    sim::SnapshotBuffer& snapshots() { return m_snapshots; }

    /// Pins garment vertex `vertex` (global) where it is now: the engine holds it from the next
    /// step, and the project's garment gains the pin (the vertex's pattern point, held at its
    /// present position) so that rebuilds keep it. Errors when nothing is draped, the vertex is
    /// not the garment's or is already pinned.
    Result<PinnedVertex> pinVertex(int vertex);
    /// Removes the garment pin holding `vertex`: an engine pin lets go from the next step; a
    /// pin that moves or lets go later (a drive) continues the drape without it. Returns the
    /// pin removed.
    Result<PinnedVertex> unpinVertex(int vertex);

    // ---- Edits that keep the drape (as commercial tools do) ----
    // Each builds a new simulation from the current positions: velocities, grabs, pins and
    // obstacle poses made through simulation() do not carry over (a window grabs again).
    // A failed edit leaves the project and the drape as they were.

    /// New drape settings. A new particle distance re-meshes and starts again; anything else
    /// continues from the current drape.
    Result<void> setDrapeSettings(const DrapeSettings& settings);
    /// A garment material's new values: continues from the current drape.
    Result<void> setMaterial(const std::string& name, const sim::Material& material);
    /// A new garment material (a name it has none of): no panel uses it yet, so the drape is
    /// unchanged; setPanel() then gives it to a panel.
    Result<void> addMaterial(const GarmentMaterial& material);
    /// Panel `index` edited: re-meshes what changed (that panel, and a partner whose seam
    /// points moved with it) and starts again with every panel whose mesh is unchanged kept
    /// where it is; changed ones are placed on their slots.
    Result<void> setPanel(std::size_t index, Panel panel);
    /// Places panel `index` on its slot again (its placement may have changed), the other
    /// panels kept where they are, and sews it anew. A panel that crosses the others where
    /// they are is moved on its slot until it clears them (as prepare() moves panels placed
    /// through each other, placementLifts() naming it), the others left where they are.
    Result<void> placePanel(std::size_t index, const Placement& placement);

    // ---- Results ----

    DrapeFigures figures() const;
    /// The seams with pairs still not welded once sewing is over (each weld put off because it
    /// would carry cloth through cloth), with their widest gap now, grouped by seam as
    /// forcedWelds() groups the forced ones; empty while sewing or before a drape.
    std::vector<ForcedWeld> openSeams() const;
    /// Whether the garment fits now (patterns/fit.h): its panels' strains and the verdict, with
    /// the open seams and the intersecting triangle pairs (counted only when the state is
    /// finite). An empty verdict (fits) before a drape.
    GarmentFit fit() const;
    const GarmentMesh& mesh() const { return m_mesh; }
    const AssembledGarment& assembled() const { return m_assembled; }
    /// Panels the last prepare moved apart on their slots to clear panels they were placed
    /// through (DrapeFigures::placementLifts), and the triangle pairs crossing before it.
    const std::vector<PlacementLift>& placementLifts() const { return m_placementLifts; }
    long placedCrossings() const { return m_placedCrossings; }
    const Body& body() const { return m_body; }
    const std::vector<std::string>& warnings() const { return m_mesh.warnings; }
    /// Drape time [s]: simulated time across restarts.
    double time() const;
    /// Global draped positions (|V|×3), in mesh.panels order.
    const sim::MatX3& positions() const;

  private:
    struct Start; // how a (re)built simulation starts
    bool ensurePrepared();
    Result<void> ensureBody();
    Result<void> ensureMesh();
    Result<void> build(const Start& start);
    Result<void> continueDrape(const std::string& why);
    void afterStep();
    /// Interactive drapes whose sewing has ended: the settling preconditioner.
    void settle();
    /// Interactive drapes, at an output frame: the step for the next frame (settlingStep()).
    void chooseStep();
    void raise(DrapeEvent::Kind kind, std::string message);
    DrapeStatus stepOnce();
    DrapeStatus finalStatus() const;

    BodyProvider m_bodies;
    Project m_project;
    bool m_haveBodySource = false;
    BodySource m_bodySource; ///< the source m_body was made from
    Body m_body;
    GarmentMesh m_mesh;
    bool m_meshValid = false;
    TriangulationCache m_triangulations;
    AssembledGarment m_assembled;
    std::unique_ptr<sim::Simulation> m_simulation;
    sim::SnapshotBuffer m_snapshots;
    bool m_publishing = false;
    bool m_interactive = false;
    std::optional<sim::LinearSolver> m_settlingSolver = INTERACTIVE_SETTLING_SOLVER;
    bool m_settlingStep = true;
    double m_stepDistance = 0; ///< the particle distance interactiveStep() was chosen for [m]
    long m_frameSteps = 0;

    std::atomic<DrapePhase> m_phase{DrapePhase::Empty};
    std::atomic<bool> m_pause{false};
    std::atomic<bool> m_cancel{false};
    std::vector<DrapeEvent> m_events;
    std::function<void(long, double, double)> m_onFrame;

    // Time and rest across restarts: a restarted simulation counts from 0.
    double m_limitStart = 0;        ///< drape time the time limit counts from (wake()) [s]
    double m_timeOffset = 0;        ///< drape time at which the current simulation started [s]
    double m_stepSecondsBefore = 0; ///< wall time of earlier simulations' steps [s]
    double m_restSince = -1;        ///< drape time since which the energy has stayed low [s]
    double m_restTime = -1;
    double m_sewnAt = -1;
    double m_sewingStart = 0; ///< drape time at which the current sewing began [s]
    Sewing m_sewing;          ///< the current simulation's sewing phase
    bool m_gravityRaised = false;
    bool m_timeLimit = false;
    std::string m_error;
    double m_startPenetration = 0;
    long m_startIntersecting = 0;
    long m_placedCrossings = 0;
    std::vector<SlotShift> m_shifts; ///< per panel: moved on its slot to clear other panels
    std::vector<PlacementLift> m_placementLifts;
    double m_kineticEnergyPerVertex = 0;
};

} // namespace atelier::patterns
