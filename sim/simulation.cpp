#include "sim/simulation.h"

#include "sim/collision/collision_stage.h"
#include "sim/collision/contact_forces.h"
#include "sim/collision/obstacle.h"
#include "sim/constraints/kinematic.h"
#include "sim/constraints/seam_elastics.h"
#include "sim/core/parallel.h"
#include "sim/forces/air.h"
#include "sim/forces/bending.h"
#include "sim/forces/fem.h"
#include "sim/forces/springs.h"
#include "sim/forces/volino.h"
#include "sim/integrators/explicit_rk.h"
#include "sim/integrators/filtered_cg.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

namespace atelier::sim {

namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point a, Clock::time_point b) {
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

} // namespace

std::string_view integratorName(IntegratorKind kind) {
    switch (kind) {
    case IntegratorKind::Euler: return "euler";
    case IntegratorKind::Midpoint: return "midpoint";
    case IntegratorKind::Rk4: return "rk4";
    case IntegratorKind::Rk45: return "rk45";
    case IntegratorKind::ImplicitEuler: return "implicit-euler";
    }
    return "?";
}

std::optional<IntegratorKind> integratorFromName(std::string_view name) {
    for (auto k : {IntegratorKind::Euler, IntegratorKind::Midpoint, IntegratorKind::Rk4,
                   IntegratorKind::Rk45, IntegratorKind::ImplicitEuler}) {
        if (integratorName(k) == name) {
            return k;
        }
    }
    return std::nullopt;
}

std::string_view stretchModelName(StretchModel model) {
    switch (model) {
    case StretchModel::Springs: return "springs";
    case StretchModel::Volino: return "volino";
    case StretchModel::Fem: return "fem";
    }
    return "?";
}

std::optional<StretchModel> stretchModelFromName(std::string_view name) {
    for (auto m : {StretchModel::Springs, StretchModel::Volino, StretchModel::Fem}) {
        if (stretchModelName(m) == name) {
            return m;
        }
    }
    return std::nullopt;
}

double maxEdgeStrain(const ClothMesh& mesh, const MatX3& x, int offset) {
    double worst = -1.0;
    for (int e = 0; e < mesh.edges.rows(); ++e) {
        const int a = mesh.edges(e, 0);
        const int b = mesh.edges(e, 1);
        const double rest = (mesh.rest.row(b) - mesh.rest.row(a)).norm();
        const double len = (x.row(b + offset) - x.row(a + offset)).norm();
        worst = std::max(worst, len / rest - 1.0);
    }
    return worst;
}

// ---------------------------------------------------------------------------------------------

struct Simulation::Impl {
    SceneSpec scene;
    std::string error;
    std::vector<int> offsets{0};
    int n = 0;
    MatX3 x, v;
    VecX mass, invMass;
    MatX3 pinPosition;           ///< rows for pinned vertices: their hold position
    std::vector<char> pinned;    ///< per vertex
    std::vector<int> driveOf;    ///< per vertex: index of its drive or -1
    std::vector<std::array<int, 2>> allEdges; ///< global edges of all cloths (high damping)
    std::vector<std::unique_ptr<ForceModel>> models;
    std::vector<std::string> stages;
    std::vector<double*> modelTimers;
    double t = 0;
    double dtNext = 0;     ///< next step to try [s]
    double dtNominal = 0;  ///< fixed-step integrators: the scene's step [s]
    std::string lastRejection; ///< why the last step was rejected (for error messages)
    double previousErrorRatio = 1.0; ///< rk45: error / tolerance of the last accepted step
    RunStats stats;
    bool failed = false;
    double lowestY = INF;  ///< lowest vertex height reached, for the gravitational energy bound
    double massHeight0 = 0; ///< Σ m_i h_i at the start, h = height along −g [kg·m]
    double baseEnergyInput = 0; ///< initial kinetic + elastic energy + constraint work [J]

    std::unique_ptr<ExplicitRkStepper> rk;
    FilteredCg cg;
    BlockSparseMatrix jacobian;
    MatX3 xNew, vNew, acc, force, forceStart, accEnd, rhs, dv, scratch, xSave, vSave;
    MatX3 dampingForce; // implicitStep's (∂f/∂v)·v
    std::vector<char> held; ///< implicit Euler: per vertex, whether CG keeps its Δv
    std::unique_ptr<CollisionStage> collision;
    ContactForces contactForces; ///< implicit Euler: the contacts inside the solve
    double hStep = 0;        ///< the step being taken [s]
    double collisionPower = 0; ///< power of the contact corrections at the step's start [W]
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

    /// Seam welding: union-find over welded pairs, and the groups of ≥ 2 vertices.
    std::vector<int> weldParent;
    std::vector<char> pairWelded;
    std::vector<std::vector<int>> weldGroups;

    explicit Impl(SceneSpec s) : scene(std::move(s)) {}

    int weldRoot(int v) {
        while (weldParent[static_cast<std::size_t>(v)] != v) {
            v = weldParent[static_cast<std::size_t>(v)] =
                weldParent[static_cast<std::size_t>(weldParent[static_cast<std::size_t>(v)])];
        }
        return v;
    }
    /// Welds the seam pairs that have closed; returns whether any did.
    bool weldClosedSeams();
    std::vector<std::size_t> newlyWelded; ///< pairs weldClosedSeams welded this step
    MatX3 xPreMerge, vPreMerge;           ///< the state before this step's merge
    std::vector<int> mergeMoved;          ///< vertices the merge moved
    /// Vertices crossing cloth in the merge xPreMerge → x (only weld-group members move).
    std::vector<int> mergeCrossings();
    /// Joins the weld sets of the pair's two vertices; returns whether they were apart.
    bool joinWeld(const SeamPair& p) {
        const int ra = weldRoot(p.a), rb = weldRoot(p.b);
        if (ra == rb) {
            return false;
        }
        weldParent[static_cast<std::size_t>(std::max(ra, rb))] = std::min(ra, rb);
        return true;
    }
    /// Weld groups (weldGroups) from weldParent.
    void rebuildWeldGroups();
    /// Where this step's merge (xPreMerge → x) makes cloth cross cloth: un-welds the new pairs
    /// involved and merges again without them; members of older groups involved stay where
    /// they were before the merge.
    void unweldCrossingMerges();
    /// SceneSpec::sewingEndsWhenSewn: ends the sewing phase at t once every pair is welded.
    void endSewingIfSewn();
    /// A: each welded group takes its mass-weighted mean position and velocity (a held member
    /// imposes its own). Momentum-conserving and dissipative.
    void mergeWelds(MatX3* xs, MatX3& vs) const;
    /// B: each welded group shares its mass-weighted mean acceleration.
    void shareWeldAccelerations(MatX3& a) const;
    /// Imposed seams (B): each open pair's relative acceleration becomes
    /// \f$ -r/\tau^2 - 2\dot r/\tau \f$, split by mass (momentum conserved). Returns the
    /// power of the corrections [W].
    double imposeSeamAccelerations(const MatX3& xs, const MatX3& vs, MatX3& a) const;
    /// Imposed seams in implicit Euler: the same law integrated implicitly on the end-of-step
    /// relative velocities.
    void imposeSeamVelocities(double h, MatX3& vEnd) const;
    bool pairOpen(std::size_t k) const { return pairWelded.empty() || !pairWelded[k]; }
    SeamElastics* seamElastics = nullptr; ///< the seam model when seams are elastic
    bool seamsRouted = false; ///< some pair has a via point (routing ran this sewing phase)
    /// Seam routing: re-chooses the via points of the open pairs blocked by an obstacle (see
    /// SceneSpec::seamRouteClearance); energy the moved targets add counts as put in.
    void routeSeams();
    /// The sewing phase's growing pull (SceneSpec::seamReachGrowthStart), set for time t.
    void growSeamReach();
    double seamPower = 0; ///< power of the imposed seam corrections at the step's start [W]

    bool hasDrives() const { return !scene.drives.empty(); }
    /// Gravity acts in the step starting at t (steps stop at gravityStartTime).
    bool gravityActive() const { return scene.gravity && t >= scene.gravityStartTime - 1e-12; }

    void build();
    void accelerations(double time, const MatX3& xs, const MatX3& vs, MatX3& a);
    void applyCorrectionsA(double h);
    bool explicitStep(double h, double& errorRatio);
    bool implicitStep(double h);
    bool step(double maxH);
    double constraintPower(const MatX3& f, const MatX3& a, const MatX3& vel) const;
    /// Whether some vertex held by a drive moves (then the constraint does work).
    bool heldVerticesMove() const;
    /// Sets invMass: 0 for vertices held at time t (pins, exact drives not yet released).
    void updateHeld();
    /// Energy put in so far (see RunStats::energyInput), with `xs` counted for the lowest point.
    double energyBound(const MatX3& xs) const;
};

double Simulation::Impl::energyBound(const MatX3& xs) const {
    double e = baseEnergyInput;
    if (scene.gravity && scene.gravityVector.norm() > 0) {
        const Vec3 up = -scene.gravityVector.normalized();
        const double low = std::min(lowestY, (xs * up).minCoeff());
        e += scene.gravityVector.norm() * (massHeight0 - mass.sum() * low);
    }
    return e;
}

void Simulation::Impl::build() {
    for (const ClothSpec& c : scene.cloths) {
        offsets.push_back(offsets.back() + c.mesh.vertexCount());
    }
    n = offsets.back();
    x.resize(n, 3);
    v.setZero(n, 3);
    mass.setZero(n);
    for (std::size_t ci = 0; ci < scene.cloths.size(); ++ci) {
        const ClothSpec& c = scene.cloths[ci];
        const int off = offsets[ci];
        const int nv = c.mesh.vertexCount();
        x.middleRows(off, nv) = c.position;
        if (c.velocity.rows() == nv) {
            v.middleRows(off, nv) = c.velocity;
        }
        const VecX m = lumpedMasses(c.mesh, c.material.density);
        mass.segment(off, nv) = m;
        for (int e = 0; e < c.mesh.edges.rows(); ++e) {
            allEdges.push_back({c.mesh.edges(e, 0) + off, c.mesh.edges(e, 1) + off});
        }
        switch (c.model) {
        case StretchModel::Springs:
            models.push_back(std::make_unique<SpringStretch>(c.mesh, off, c.material, c.crossSprings));
            break;
        case StretchModel::Volino:
            models.push_back(std::make_unique<VolinoStretch>(c.mesh, off, c.material, m));
            break;
        case StretchModel::Fem:
            models.push_back(std::make_unique<FemStretch>(c.mesh, off, c.material));
            break;
        }
        if (c.bending && c.material.bending > 0 && c.mesh.hinges.rows() > 0) {
            models.push_back(std::make_unique<DihedralBending>(c.mesh, off, c.material,
                                                               c.restAngles, c.plasticity));
        }
        if (scene.air.enabled) {
            models.push_back(std::make_unique<AirDrag>(c.mesh, off, scene.air));
        }
    }
    if (!scene.seams.empty() && scene.seamMode == SeamMode::Elastic) {
        auto seams = std::make_unique<SeamElastics>(scene.seams, mass, scene.seamTimeConstant,
                                                    scene.seamReach,
                                                    scene.seamStiffnessPerLength);
        seamElastics = seams.get();
        models.push_back(std::move(seams));
    }
    pinned.assign(static_cast<std::size_t>(n), 0);
    pinPosition = x;
    for (int p : scene.pins) {
        pinned[static_cast<std::size_t>(p)] = 1;
    }
    driveOf.assign(static_cast<std::size_t>(n), -1);
    for (std::size_t d = 0; d < scene.drives.size(); ++d) {
        driveOf[static_cast<std::size_t>(scene.drives[d].vertex)] = static_cast<int>(d);
    }
    updateHeld();

    // The pipeline: only what the scene needs.
    if (!scene.pins.empty()) {
        stages.emplace_back("constraints.pins");
    }
    if (hasDrives()) {
        stages.emplace_back("constraints.drives");
    }
    if (scene.highDampingTimeConstant > 0) {
        stages.emplace_back("constraints.high-damping");
    }
    if (!scene.seams.empty() && scene.seamMode == SeamMode::Imposed) {
        stages.emplace_back("constraints.seams");
    }
    if (!scene.seams.empty() && (scene.seamWeldDistance > 0 || scene.seamWeldAllTime >= 0)) {
        stages.emplace_back("constraints.seam-welds");
    }
    for (const auto& m : models) {
        stages.emplace_back(m->name());
    }
    if (scene.gravity) {
        stages.emplace_back("gravity");
    }
    if (CollisionStage::needed(scene)) {
        if (!scene.obstacles.empty()) {
            stages.emplace_back("collision.obstacles");
        }
        if (std::any_of(scene.cloths.begin(), scene.cloths.end(),
                        [](const ClothSpec& c) { return c.selfCollision; })) {
            stages.emplace_back("collision.self");
        }
        if (scene.collision.continuous) {
            stages.emplace_back("collision.continuous");
        }
        stages.emplace_back("collision.response");
    }
    stages.push_back("integrator." + std::string(integratorName(scene.integrator.kind)));
    if (scene.integrator.kind == IntegratorKind::Rk45) {
        stages.emplace_back("step-control.error-estimate");
    }

    for (const auto& m : models) {
        modelTimers.push_back(&stats.stageSeconds["forces." + std::string(m->name())]);
    }
    timerForces = &stats.stageSeconds["forces.total"];
    timerConstraints = &stats.stageSeconds["constraints"];
    timerIntegrator = &stats.stageSeconds["integrator"];
    if (scene.integrator.kind == IntegratorKind::ImplicitEuler) {
        timerSolve = &stats.stageSeconds["implicit.solve"];
        std::vector<std::pair<int, int>> pairs;
        for (const auto& m : models) {
            m->jacobianPattern(pairs);
        }
        jacobian = BlockSparseMatrix(n, pairs);
    }

    switch (scene.integrator.kind) {
    case IntegratorKind::Euler: rk = std::make_unique<ExplicitRkStepper>(ButcherTableau::euler()); break;
    case IntegratorKind::Midpoint: rk = std::make_unique<ExplicitRkStepper>(ButcherTableau::midpoint()); break;
    case IntegratorKind::Rk4: rk = std::make_unique<ExplicitRkStepper>(ButcherTableau::rk4()); break;
    case IntegratorKind::Rk45: rk = std::make_unique<ExplicitRkStepper>(ButcherTableau::cashKarp()); break;
    case IntegratorKind::ImplicitEuler: break;
    }
    dtNominal = scene.integrator.dt;
    dtNext = scene.integrator.dt;
    if (CollisionStage::needed(scene)) {
        timerCollision = &stats.stageSeconds["collision"];
        // The start (hierarchies, trapped vertices) is timed apart: `collision` is a share of
        // the steps' wall time.
        StageTimer timer(stats.stageSeconds["collision.setup"]);
        collision = std::make_unique<CollisionStage>(scene, offsets, x);
        collision->update(0.0, 0.0, x, x, v, invMass); // resolve the start, find trapped vertices
        stats.maxPenetration = collision->penetration(x);
        stats.contacts = collision->figures().contacts;
    }

    // Energy the initial state holds (kinetic + elastic); gravity is added as the run goes.
    double e0 = 0.5 * (mass.array() * v.rowwise().squaredNorm().array()).sum();
    for (const auto& m : models) {
        if (m->hasEnergy()) {
            e0 += m->energy(x);
        }
    }
    baseEnergyInput = e0;
    if (scene.gravity && scene.gravityVector.norm() > 0) {
        const Vec3 up = -scene.gravityVector.normalized();
        massHeight0 = (mass.array() * (x * up).array()).sum();
        lowestY = (x * up).minCoeff();
    }
}

void Simulation::Impl::accelerations(double time, const MatX3& xs, const MatX3& vs, MatX3& a) {
    {
        StageTimer timer(*timerForces);
        force.setZero(n, 3);
        for (std::size_t k = 0; k < models.size(); ++k) {
            StageTimer modelTimer(*modelTimers[k]);
            models[k]->addForces(xs, vs, force);
        }
    }
    ++stats.forceEvaluations;
    if (&xs == &x && !scene.drives.empty()) {
        forceStart = force; // forces at the step's start, for the work of the drives
    }
    a.resize(n, 3);
    for (int i = 0; i < n; ++i) {
        a.row(i) = mass[i] > 0 ? Vec3(force.row(i).transpose() / mass[i]) : Vec3::Zero();
    }
    if (gravityActive()) {
        a.rowwise() += scene.gravityVector.transpose();
    }
    // B: held vertices get the acceleration of their constraint: zero for pins and exact drives
    // (piecewise linear paths); for tracker-following drives the critically damped law toward
    // the path (time constant τ), which replaces the mechanical acceleration so the grab
    // filters the input's noise whatever the cloth's mass and stiffness. Whether a drive is
    // active is decided at the step's start (steps stop at path keys and release times).
    for (int i = 0; i < n; ++i) {
        if (invMass[i] == 0) {
            a.row(i).setZero();
        }
    }
    for (const Drive& drive : scene.drives) {
        if (drive.followTimeConstant <= 0 || !driveActive(drive, t)) {
            continue;
        }
        const PathSample p = samplePath(drive, time);
        const double tau = drive.followTimeConstant;
        const int i = drive.vertex;
        a.row(i) = (-(xs.row(i).transpose() - p.position) / (tau * tau) -
                    2.0 * (vs.row(i).transpose() - p.velocity) / tau)
                       .transpose();
    }
    if (scene.seamMode == SeamMode::Imposed && !scene.seams.empty() &&
        scene.integrator.kind != IntegratorKind::ImplicitEuler) {
        const double power = imposeSeamAccelerations(xs, vs, a);
        if (&xs == &x) {
            seamPower = power;
        }
    }
    if (scene.integrator.kind != IntegratorKind::ImplicitEuler) {
        // Implicit Euler merges welded velocities after its solve instead: sharing stiff
        // forces across the weld explicitly in its right-hand side would be unstable.
        shareWeldAccelerations(a);
    }
    if (collision && scene.integrator.kind != IntegratorKind::ImplicitEuler) {
        // B: contacts hold (no re-approach) with Coulomb friction.
        StageTimer timer(*timerCollision);
        const double power = collision->correctAccelerations(vs, a, mass, invMass, hStep);
        if (&xs == &x) {
            collisionPower = power;
        }
    }
}

double Simulation::Impl::constraintPower(const MatX3& f, const MatX3& a,
                                         const MatX3& vel) const {
    // Power delivered by the drives: on a held vertex with imposed acceleration a the
    // constraint applies R = m a − f − m g, moving at velocity v.
    double p = 0;
    for (const Drive& d : scene.drives) {
        const int i = d.vertex;
        if (invMass[i] == 0 && mass[i] > 0) {
            Vec3 reaction = mass[i] * a.row(i).transpose() - f.row(i).transpose();
            if (gravityActive()) {
                reaction -= mass[i] * scene.gravityVector;
            }
            p += reaction.dot(vel.row(i).transpose());
        }
    }
    return p;
}

bool Simulation::Impl::heldVerticesMove() const {
    for (const Drive& d : scene.drives) {
        if (invMass[d.vertex] == 0 && v.row(d.vertex).squaredNorm() > 0) {
            return true;
        }
    }
    return false;
}

void Simulation::Impl::updateHeld() {
    invMass.resize(n);
    for (int i = 0; i < n; ++i) {
        bool held = pinned[static_cast<std::size_t>(i)] != 0;
        const int d = driveOf[static_cast<std::size_t>(i)];
        if (!held && d >= 0) {
            const Drive& drive = scene.drives[static_cast<std::size_t>(d)];
            held = driveActive(drive, t);
        }
        invMass[i] = (held || mass[i] <= 0) ? 0.0 : 1.0 / mass[i];
    }
}

void Simulation::Impl::applyCorrectionsA(double h) {
    StageTimer timer(*timerConstraints);
    if (hasDrives()) {
        updateHeld();
    }
    double injected = 0;
    for (int p : scene.pins) {
        injected -= 0.5 * mass[p] * v.row(p).squaredNorm();
        x.row(p) = pinPosition.row(p);
        v.row(p).setZero();
    }
    for (const Drive& d : scene.drives) {
        if (!driveActive(d, t) || d.followTimeConstant > 0) {
            continue;
        }
        const PathSample s = samplePath(d, t);
        const double before = 0.5 * mass[d.vertex] * v.row(d.vertex).squaredNorm();
        x.row(d.vertex) = s.position.transpose();
        v.row(d.vertex) = s.velocity.transpose();
        injected += 0.5 * mass[d.vertex] * v.row(d.vertex).squaredNorm() - before;
    }
    baseEnergyInput += std::max(0.0, injected);
    if (scene.highDampingTimeConstant > 0) {
        applyHighDamping(allEdges, invMass, h, scene.highDampingTimeConstant, v);
    }
    mergeWelds(&x, v);
}

void Simulation::Impl::growSeamReach() {
    if (seamElastics == nullptr || scene.seamReachGrowthStart < 0 || !(scene.seamReach > 0) ||
        scene.seamWeldAllTime <= scene.seamReachGrowthStart) {
        return;
    }
    const double s = std::clamp((t - scene.seamReachGrowthStart) /
                                    (scene.seamWeldAllTime - scene.seamReachGrowthStart),
                                0.0, 1.0);
    const double reach = scene.seamReach * (1.0 + (scene.seamReachGrowth - 1.0) * s);
    if (reach == seamElastics->reach()) {
        return;
    }
    // A longer reach raises the potential of wide gaps: energy put in, counted.
    const double before = seamElastics->energy(x);
    seamElastics->setReach(reach);
    baseEnergyInput += std::max(0.0, seamElastics->energy(x) - before);
}

void Simulation::Impl::routeSeams() {
    if (seamElastics == nullptr || !collision || !(scene.seamRouteClearance > 0)) {
        return;
    }
    const bool sewing = scene.seamWeldAllTime < 0 || t < scene.seamWeldAllTime - 1e-12;
    if (!sewing && !seamsRouted) {
        return; // after sewing: nothing to route, nothing left to clear
    }
    const double before = seamElastics->energy(x);
    seamsRouted = false;
    for (std::size_t k = 0; k < scene.seams.size(); ++k) {
        const SeamPair& p = scene.seams[k];
        Vec3 via;
        const bool route = sewing && pairOpen(k) &&
                           collision->routeAround(x.row(p.a).transpose(), x.row(p.b).transpose(),
                                                  scene.seamRouteClearance, via);
        seamElastics->setVia(k, route ? &via : nullptr);
        seamsRouted = seamsRouted || route;
    }
    baseEnergyInput += std::max(0.0, seamElastics->energy(x) - before);
}

void Simulation::Impl::endSewingIfSewn() {
    if (!(scene.seamWeldAllTime > t) || scene.seams.empty() ||
        stats.weldedSeamPairs < static_cast<long>(scene.seams.size())) {
        return;
    }
    // Every pair is sewn: what the rest of the phase waits for has happened. Gravity, if it
    // was to start with the phase's end, starts now.
    if (scene.gravityStartTime > t && scene.gravityStartTime <= scene.seamWeldAllTime + 1e-12) {
        scene.gravityStartTime = t;
    }
    scene.seamWeldAllTime = t;
    stats.sewingEndTime = t;
}

bool Simulation::Impl::weldClosedSeams() {
    const bool all = scene.seamWeldAllTime >= 0 && t >= scene.seamWeldAllTime - 1e-12;
    if (all && stats.sewingEndTime < 0) {
        stats.sewingEndTime = t;
    }
    if (!(scene.seamWeldDistance > 0) && !all) {
        return false;
    }
    if (weldParent.empty()) {
        weldParent.resize(static_cast<std::size_t>(n));
        std::iota(weldParent.begin(), weldParent.end(), 0);
        pairWelded.assign(scene.seams.size(), 0);
    }
    const double d2 = scene.seamWeldDistance * scene.seamWeldDistance;
    bool changed = false;
    newlyWelded.clear();
    for (std::size_t k = 0; k < scene.seams.size(); ++k) {
        const SeamPair& p = scene.seams[k];
        if (pairWelded[k]) {
            continue;
        }
        const double gap2 = (x.row(p.a) - x.row(p.b)).squaredNorm();
        if (gap2 > d2) {
            if (!all) {
                continue;
            }
            stats.largestForcedWeld = std::max(stats.largestForcedWeld, std::sqrt(gap2));
            stats.forcedWeldGaps.resize(scene.seams.size(), 0.0);
            stats.forcedWeldGaps[k] = std::sqrt(gap2);
        }
        pairWelded[k] = 1;
        ++stats.weldedSeamPairs;
        newlyWelded.push_back(k);
        changed = joinWeld(p) || changed;
    }
    if (changed) {
        rebuildWeldGroups();
    }
    return changed;
}

void Simulation::Impl::rebuildWeldGroups() {
    std::map<int, std::vector<int>> groups;
    for (const SeamPair& p : scene.seams) {
        for (int v : {p.a, p.b}) {
            groups[weldRoot(v)].push_back(v);
        }
    }
    weldGroups.clear();
    for (auto& [root, members] : groups) {
        std::sort(members.begin(), members.end());
        members.erase(std::unique(members.begin(), members.end()), members.end());
        if (members.size() >= 2) {
            weldGroups.push_back(std::move(members));
        }
    }
}

void Simulation::Impl::unweldCrossingMerges() {
    for (int round = 0; round < 8; ++round) {
        const std::vector<int> crossing = mergeCrossings();
        if (crossing.empty()) {
            return;
        }
        std::vector<char> rootCrosses(static_cast<std::size_t>(n), 0);
        for (int v : crossing) {
            rootCrosses[static_cast<std::size_t>(weldRoot(v))] = 1;
        }
        std::vector<std::size_t> kept;
        bool undone = false;
        for (std::size_t k : newlyWelded) {
            if (!rootCrosses[static_cast<std::size_t>(weldRoot(scene.seams[k].a))]) {
                kept.push_back(k);
                continue;
            }
            pairWelded[k] = 0;
            --stats.weldedSeamPairs;
            ++stats.deferredWelds;
            if (k < stats.forcedWeldGaps.size()) {
                stats.forcedWeldGaps[k] = 0;
            }
            undone = true;
        }
        if (!undone) {
            // Older groups brought back together after the collision corrections moved their
            // members apart: where that crosses, those members stay where the corrections put
            // them (the group keeps one velocity and is merged again at a later step).
            for (int i : crossing) {
                x.row(i) = xPreMerge.row(i);
            }
            continue;
        }
        newlyWelded = std::move(kept);
        std::iota(weldParent.begin(), weldParent.end(), 0);
        for (std::size_t k = 0; k < scene.seams.size(); ++k) {
            if (pairWelded[k]) {
                joinWeld(scene.seams[k]);
            }
        }
        rebuildWeldGroups();
        stats.largestForcedWeld = stats.forcedWeldGaps.empty()
                                      ? 0.0
                                      : *std::max_element(stats.forcedWeldGaps.begin(),
                                                          stats.forcedWeldGaps.end());
        x = xPreMerge;
        v = vPreMerge;
        mergeWelds(&x, v);
    }
    // Rounds exhausted (or the last one merged again): whatever still crosses stays where it
    // was before the merge.
    for (int i : mergeCrossings()) {
        x.row(i) = xPreMerge.row(i);
    }
}

std::vector<int> Simulation::Impl::mergeCrossings() {
    mergeMoved.clear();
    for (const std::vector<int>& g : weldGroups) {
        for (int i : g) {
            if (x.row(i) != xPreMerge.row(i)) {
                mergeMoved.push_back(i);
            }
        }
    }
    return collision->crossingVertices(xPreMerge, x, mergeMoved);
}

void Simulation::Impl::mergeWelds(MatX3* xs, MatX3& vs) const {
    for (const std::vector<int>& g : weldGroups) {
        double m = 0;
        Vec3 px = Vec3::Zero(), pv = Vec3::Zero();
        int heldVertex = -1;
        for (int i : g) {
            if (invMass[i] == 0) {
                heldVertex = i;
            }
            m += mass[i];
            if (xs != nullptr) {
                px += mass[i] * xs->row(i).transpose();
            }
            pv += mass[i] * vs.row(i).transpose();
        }
        if (heldVertex >= 0) {
            if (xs != nullptr) {
                px = xs->row(heldVertex).transpose();
            }
            pv = vs.row(heldVertex).transpose();
        } else if (m > 0) {
            px /= m;
            pv /= m;
        } else {
            continue;
        }
        for (int i : g) {
            if (xs != nullptr) {
                xs->row(i) = px.transpose();
            }
            vs.row(i) = pv.transpose();
        }
    }
}

void Simulation::Impl::shareWeldAccelerations(MatX3& a) const {
    for (const std::vector<int>& g : weldGroups) {
        double m = 0;
        Vec3 pa = Vec3::Zero();
        int heldVertex = -1;
        for (int i : g) {
            if (invMass[i] == 0) {
                heldVertex = i;
            }
            m += mass[i];
            pa += mass[i] * a.row(i).transpose();
        }
        if (heldVertex >= 0) {
            pa = a.row(heldVertex).transpose();
        } else if (m > 0) {
            pa /= m;
        } else {
            continue;
        }
        for (int i : g) {
            a.row(i) = pa.transpose();
        }
    }
}

double Simulation::Impl::imposeSeamAccelerations(const MatX3& xs, const MatX3& vs,
                                                MatX3& a) const {
    const double tau = scene.seamTimeConstant;
    double power = 0;
    for (std::size_t k = 0; k < scene.seams.size(); ++k) {
        if (!pairOpen(k)) {
            continue;
        }
        const int ia = scene.seams[k].a, ib = scene.seams[k].b;
        const double wa = invMass[ia], wb = invMass[ib];
        if (wa + wb == 0) {
            continue;
        }
        const Vec3 r = xs.row(ia) - xs.row(ib);
        const Vec3 rv = vs.row(ia) - vs.row(ib);
        const Vec3 want = -r / (tau * tau) - 2.0 * rv / tau;
        const Vec3 delta = want - (a.row(ia) - a.row(ib)).transpose();
        // Split by inverse mass: the pair's reaction forces are equal and opposite.
        a.row(ia) += (wa / (wa + wb)) * delta.transpose();
        a.row(ib) -= (wb / (wa + wb)) * delta.transpose();
        power += delta.dot(rv) / (wa + wb);
    }
    return power;
}

void Simulation::Impl::imposeSeamVelocities(double h, MatX3& vEnd) const {
    const double tau = scene.seamTimeConstant;
    const double denominator = 1.0 + 2.0 * h / tau + h * h / (tau * tau);
    for (std::size_t k = 0; k < scene.seams.size(); ++k) {
        if (!pairOpen(k)) {
            continue;
        }
        const int ia = scene.seams[k].a, ib = scene.seams[k].b;
        const double wa = invMass[ia], wb = invMass[ib];
        if (wa + wb == 0) {
            continue;
        }
        const Vec3 r = x.row(ia) - x.row(ib);
        const Vec3 rv0 = v.row(ia) - v.row(ib);
        // Backward Euler of r'' = −r/τ² − 2r'/τ over the step.
        const Vec3 want = (rv0 - h * r / (tau * tau)) / denominator;
        const Vec3 delta = want - (vEnd.row(ia) - vEnd.row(ib)).transpose();
        vEnd.row(ia) += (wa / (wa + wb)) * delta.transpose();
        vEnd.row(ib) -= (wb / (wa + wb)) * delta.transpose();
    }
}

bool Simulation::Impl::explicitStep(double h, double& errorRatio) {
    AccelerationFn fn = [this](double time, const MatX3& xs, const MatX3& vs, MatX3& a) {
        accelerations(time, xs, vs, a);
    };
    StageTimer timer(*timerIntegrator);
    const double err =
        rk->step(t, h, x, v, fn, xNew, vNew, &acc, scene.integrator.velocityErrorTime);
    if (scene.integrator.kind == IntegratorKind::Rk45) {
        errorRatio = err / scene.integrator.tolerance;
    } else {
        errorRatio = 0;
    }
    return std::isfinite(errorRatio) && xNew.allFinite() && vNew.allFinite();
}

bool Simulation::Impl::implicitStep(double h) {
    StageTimer timer(*timerIntegrator);
    // Baraff & Witkin 1998: (M − h ∂f/∂v − h² ∂f/∂x) Δv = h (f + h ∂f/∂x v).
    accelerations(t, x, v, acc);
    // The right-hand side uses the corrected accelerations (gravity, B and C included).
    rhs.resize(n, 3);
    for (int i = 0; i < n; ++i) {
        rhs.row(i) = mass[i] * acc.row(i);
    }
    const bool contactsInSolve = collision && scene.collision.solveContacts;
    if (contactsInSolve) {
        StageTimer timer(*timerCollision);
        collision->predictObstacleVelocities(t, h);
        contactForces.prepare(collision->contacts(), x, v, invMass, dtNominal, scene.collision.solve);
        contactForces.addForces(rhs);
    }
    jacobian.setZero();
    for (const auto& m : models) {
        m->addJacobian(x, v, -h * h, -h, JacobianMode::Definite, jacobian);
    }
    if (contactsInSolve) {
        contactForces.addJacobian(-h * h, -h, jacobian);
    }
    // h² (∂f/∂x) v from the one assembly (it was assembled a second time for this, a tenth of a
    // drape's time): J v = −h² (∂f/∂x) v − h (∂f/∂v) v, and (∂f/∂v) v comes from the models
    // without assembly (for most, their damping force: check (g), tests/sim/forces).
    jacobian.multiply(v, scratch);
    dampingForce.setZero(n, 3);
    for (const auto& m : models) {
        m->addDampingProduct(x, v, dampingForce);
    }
    if (contactsInSolve) {
        contactForces.addJacobianProduct(0.0, 1.0, v, dampingForce);
    }
    rhs = h * rhs - scratch - h * dampingForce;
    jacobian.addDiagonal(mass);
    held.assign(static_cast<std::size_t>(n), 0);
    for (int i = 0; i < n; ++i) {
        held[static_cast<std::size_t>(i)] = invMass[i] == 0 ? 1 : 0;
    }
    dv.setZero(n, 3);
    // Tracker-following drives: their velocity change is imposed, from the backward-Euler
    // form of the critically damped law (stable for any h/τ).
    for (const Drive& d : scene.drives) {
        if (d.followTimeConstant > 0 && driveActive(d, t)) {
            const double tau = d.followTimeConstant;
            const PathSample p = samplePath(d, t + h);
            const Vec3 xi = x.row(d.vertex).transpose();
            const Vec3 vi = v.row(d.vertex).transpose();
            const Vec3 vNext = (vi + h * (-(xi - p.position) / (tau * tau) + 2.0 * p.velocity / tau)) /
                               (1.0 + h * h / (tau * tau) + 2.0 * h / tau);
            dv.row(d.vertex) = (vNext - vi).transpose();
        }
    }
    CgResult r;
    {
        StageTimer solveTimer(*timerSolve);
        // Welded seam vertices are one unknown of the solve: solved apart, each was pulled by
        // its own panel and the merge after the solve threw most of that motion away.
        r = cg.solve(jacobian, rhs, held, dv, scene.integrator.cgTolerance,
                     scene.integrator.cgMaxIterations, &weldGroups);
    }
    stats.cgIterations += r.iterations;
    vNew = v + dv;
    if (scene.seamMode == SeamMode::Imposed && !scene.seams.empty()) {
        const double before = 0.5 * (mass.array() * vNew.rowwise().squaredNorm().array()).sum();
        imposeSeamVelocities(h, vNew);
        const double after = 0.5 * (mass.array() * vNew.rowwise().squaredNorm().array()).sum();
        seamPower = std::max(0.0, after - before) / h;
    }
    mergeWelds(nullptr, vNew); // welded pairs keep one velocity (positions follow below)
    if (collision) {
        // Contacts on the end-of-step velocities (the implicit form of B), with friction.
        StageTimer timer(*timerCollision);
        const double before = 0.5 * (mass.array() * vNew.rowwise().squaredNorm().array()).sum();
        collision->correctVelocities(vNew, invMass);
        const double after = 0.5 * (mass.array() * vNew.rowwise().squaredNorm().array()).sum();
        collisionPower = std::max(0.0, after - before) / h; // moving obstacles put energy in
        if (contactsInSolve) {
            collisionPower += std::max(0.0, contactForces.obstaclePower());
            contactPotential = contactForces.potential();
        }
    }
    xNew = x + h * vNew;
    return xNew.allFinite() && vNew.allFinite();
}

bool Simulation::Impl::step(double maxH) {
    const IntegratorOptions& opt = scene.integrator;
    double h = std::min({dtNext, maxH, opt.maxDt});
    for (const Drive& d : scene.drives) {
        const double ev = nextPathEvent(d, t);
        if (ev > t + 1e-12 && ev < t + h) {
            h = ev - t;
        }
    }
    for (const ObstacleSpec& o : scene.obstacles) {
        const double ev = nextObstacleEvent(o, t);
        if (ev > t + 1e-12 && ev < t + h) {
            h = ev - t;
        }
    }
    if (scene.gravity && scene.gravityStartTime > t + 1e-12 && scene.gravityStartTime < t + h) {
        h = scene.gravityStartTime - t;
    }
    growSeamReach();
    routeSeams();
    if (collision && scene.sewingFrictionScale != 1.0) {
        const bool sewing = scene.seamWeldAllTime >= 0 && t < scene.seamWeldAllTime - 1e-12;
        collision->setFrictionScale(sewing ? scene.sewingFrictionScale : 1.0);
    }
    for (;;) {
        if (h < opt.minDt) {
            std::ostringstream s;
            s << "time step fell below the floor (" << h << " s < " << opt.minDt
              << " s) at t = " << t << " s: the state cannot be integrated stably (last rejection: "
              << lastRejection << ")";
            error = s.str();
            failed = true;
            return false;
        }
        const auto start = Clock::now();
        hStep = h;
        collisionPower = 0;
        seamPower = 0;
        contactPotential = 0;
        xSave = x; // members: no allocation after the first step
        vSave = v;
        applyCorrectionsA(h);
        bool ok;
        double errorRatio = 0;
        if (opt.kind == IntegratorKind::ImplicitEuler) {
            ok = implicitStep(h);
        } else {
            ok = explicitStep(h, errorRatio);
        }
        double work = 0;
        bool energyRejected = false;
        double keRejected = 0;
        if (ok && errorRatio <= 1.0) {
            if (heldVerticesMove()) {
                // Work of the drives over the step, trapezoidal in their reaction forces (one
                // more force evaluation, only while a drive moves a vertex).
                const double p0 = constraintPower(forceStart, acc, v);
                accelerations(t + h, xNew, vNew, accEnd);
                work = 0.5 * h * (p0 + constraintPower(force, accEnd, vNew));
            }
            const double ke = 0.5 * (mass.array() * vNew.rowwise().squaredNorm().array()).sum();
            // Contacts with moving obstacles do work too (B, or the implicit velocity pass).
            const double contactWork =
                std::max(0.0, collisionPower * h) + std::max(0.0, seamPower * h) + contactPotential;
            ok = ke <= opt.divergenceEnergyFactor *
                               (energyBound(xNew) + std::max(0.0, work) + contactWork) +
                           1e-6 * mass.sum(); // below ~1 mm/s of motion: never a divergence
            energyRejected = !ok;
            keRejected = ke;
        }
        const bool accept = ok && errorRatio <= 1.0;
        if (accept && collision) {
            // Collision detection over the step and the kinematic corrections (A) of the end
            // state; energy the corrections add (moving obstacles, friction carrying the cloth)
            // counts as put in.
            StageTimer timer(*timerCollision);
            const double before = 0.5 * (mass.array() * vNew.rowwise().squaredNorm().array()).sum();
            collision->update(t, t + h, x, xNew, vNew, invMass);
            const double after = 0.5 * (mass.array() * vNew.rowwise().squaredNorm().array()).sum();
            work += std::max(0.0, after - before) + std::max(0.0, collisionPower * h);
            collisionPower = 0;
            stats.contacts = collision->figures().contacts;
        }
        if (accept) {
            work += std::max(0.0, seamPower * h) +
                    std::max(0.0, contactPotential - lastContactPotential);
            seamPower = 0;
            lastContactPotential = contactPotential;
        }
        if (!accept) {
            std::ostringstream why;
            if (energyRejected) {
                why << "kinetic energy " << keRejected << " J above " << opt.divergenceEnergyFactor
                    << " × the energy put in";
            } else if (!ok) {
                why << "non-finite state";
            } else {
                why << "error estimate " << errorRatio << " × tolerance";
            }
            why << " at h = " << h << " s";
            lastRejection = why.str();
        }
        stats.wallTime += seconds(start, Clock::now());
        if (!accept) {
            ++stats.rejectedSteps;
            x = xSave;
            v = vSave;
            if (!ok || !std::isfinite(errorRatio)) {
                h *= 0.25;
            } else {
                h *= std::max(0.1, 0.9 * std::pow(errorRatio, -0.25));
            }
            dtNext = h;
            continue;
        }
        baseEnergyInput += std::max(0.0, work);
        x.swap(xNew);
        v.swap(vNew);
        t += h;
        for (const auto& m : models) {
            m->acceptStep(x, h);
        }
        const auto weldStart = Clock::now(); // the welds are part of the step's wall time
        const double forcedBefore = stats.largestForcedWeld;
        const bool newWelds = weldClosedSeams();
        if (newWelds || !weldGroups.empty()) {
            // Also after the collision corrections, which move vertices one by one: a welded
            // group leaves every step as one point.
            StageTimer timer(*timerConstraints);
            // Pairs welded from afar (end of sewing) stretch the cloth: that elastic energy is
            // put in by the weld, so the divergence check counts it.
            double elasticBefore = 0;
            const bool forced = newWelds && stats.largestForcedWeld > forcedBefore;
            if (forced) {
                for (const auto& m : models) {
                    elasticBefore += m->hasEnergy() ? m->energy(x) : 0.0;
                }
            }
            xPreMerge = x;
            vPreMerge = v;
            mergeWelds(&x, v);
            if (collision && collision->selfCollision()) {
                // A weld moves both sides of the pair onto their common point: where that
                // carries a triangle through the cloth beside the seam, the pair is not welded
                // this step (its elastic keeps pulling), so welds never make intersections.
                StageTimer collisionTimer(*timerCollision); // collision work (nested here)
                unweldCrossingMerges();
            }
            if (forced) {
                double elasticAfter = 0;
                for (const auto& m : models) {
                    elasticAfter += m->hasEnergy() ? m->energy(x) : 0.0;
                }
                baseEnergyInput += std::max(0.0, elasticAfter - elasticBefore);
            }
        }
        if (scene.sewingEndsWhenSewn) {
            endSewingIfSewn();
        }
        stats.wallTime += seconds(weldStart, Clock::now());
        ++stats.steps;
        stats.minDt = stats.steps == 1 ? h : std::min(stats.minDt, h);
        stats.maxDt = std::max(stats.maxDt, h);
        stats.simTime = t;
        if (scene.gravity) {
            const Vec3 g = scene.gravityVector;
            // Height along −g of the lowest vertex.
            const double gn = g.norm();
            if (gn > 0) {
                const double low = (x * (-g / gn)).minCoeff();
                lowestY = std::min(lowestY, low);
            }
        }
        if (opt.kind == IntegratorKind::Rk45) {
            // PI step control (Gustafsson 1991; Hairer & Wanner II §IV.2): the integral term
            // alone hunts at the stability limit of stiff cloth; the proportional term on the
            // previous error damps that, cutting rejections.
            const double e = std::max(errorRatio, 1e-6);
            const double grow = 0.9 * std::pow(e, -0.7 / 5.0) * std::pow(previousErrorRatio, 0.4 / 5.0);
            previousErrorRatio = e;
            dtNext = h * std::clamp(grow, 0.2, opt.growth);
        } else {
            // Fixed-step methods return to the nominal step after a rejection, gradually.
            dtNext = std::min(dtNominal, h * 2.0);
        }
        return true;
    }
}

// ---------------------------------------------------------------------------------------------

std::optional<std::string> Simulation::validate(const SceneSpec& s) {
    if (s.cloths.empty()) {
        return std::string("the scene has no cloth");
    }
    int total = 0;
    for (std::size_t ci = 0; ci < s.cloths.size(); ++ci) {
        const ClothSpec& c = s.cloths[ci];
        const std::string who = "cloth " + std::to_string(ci) + " (" + c.name + ")";
        const int nv = c.mesh.vertexCount();
        if (c.mesh.triangleCount() == 0 || c.mesh.restArea.size() != c.mesh.triangleCount()) {
            return who + ": mesh has no triangles or was not built";
        }
        for (int t = 0; t < c.mesh.triangleCount(); ++t) {
            if (!(c.mesh.restArea[t] > 0)) {
                return who + ": triangle " + std::to_string(t) + ": zero or negative rest area";
            }
        }
        if (c.position.rows() != nv) {
            return who + ": " + std::to_string(c.position.rows()) + " positions for " +
                   std::to_string(nv) + " vertices";
        }
        if (c.velocity.rows() != 0 && c.velocity.rows() != nv) {
            return who + ": velocity count does not match the vertex count";
        }
        for (int i = 0; i < nv; ++i) {
            if (!c.position.row(i).allFinite()) {
                return who + ": vertex " + std::to_string(i) + ": position is not finite";
            }
        }
        const Material& m = c.material;
        if (!(m.density > 0) || !std::isfinite(m.density)) {
            return who + ": material density must be positive and finite";
        }
        if (!(m.stretchWeft > 0) || !(m.stretchWarp > 0) || !(m.shear > 0) ||
            !std::isfinite(m.stretchWeft + m.stretchWarp + m.shear)) {
            return who + ": stretch and shear stiffness must be positive and finite";
        }
        if (!(m.bending >= 0) || !(m.damping >= 0) || !std::isfinite(m.bending + m.damping)) {
            return who + ": bending and damping must be non-negative and finite";
        }
        const double nu21 = m.poisson * m.stretchWarp / m.stretchWeft;
        if (!(m.poisson >= 0) || !(m.poisson * nu21 < 1.0) ||
            (c.model == StretchModel::Volino && m.poisson >= 0.5)) {
            return who + ": Poisson ratio out of range (need 0 <= nu and nu12*nu21 < 1; volino: nu < 0.5)";
        }
        if (c.restAngles.size() != 0 && c.restAngles.size() != c.mesh.hinges.rows()) {
            return who + ": rest_angles has " + std::to_string(c.restAngles.size()) +
                   " values for " + std::to_string(c.mesh.hinges.rows()) + " interior edges";
        }
        total += nv;
    }
    for (int p : s.pins) {
        if (p < 0 || p >= total) {
            return "pin vertex " + std::to_string(p) + " out of range [0, " + std::to_string(total) + ")";
        }
    }
    for (std::size_t d = 0; d < s.drives.size(); ++d) {
        const Drive& dr = s.drives[d];
        const std::string who = "drive " + std::to_string(d);
        if (dr.vertex < 0 || dr.vertex >= total) {
            return who + ": vertex " + std::to_string(dr.vertex) + " out of range";
        }
        if (dr.times.empty() || dr.times.size() != dr.positions.size()) {
            return who + ": needs as many key times as key positions, at least one";
        }
        for (std::size_t k = 1; k < dr.times.size(); ++k) {
            if (!(dr.times[k] > dr.times[k - 1])) {
                return who + ": key times must increase (key " + std::to_string(k) + ")";
            }
        }
        for (const Vec3& p : dr.positions) {
            if (!p.allFinite()) {
                return who + ": key positions must be finite";
            }
        }
        if (dr.followTimeConstant < 0) {
            return who + ": follow time constant must be >= 0";
        }
    }
    for (std::size_t k = 0; k < s.seams.size(); ++k) {
        const SeamPair& p = s.seams[k];
        if (p.a < 0 || p.a >= total || p.b < 0 || p.b >= total || p.a == p.b) {
            return "seam " + std::to_string(k) + ": vertices must be two different vertices in range";
        }
    }
    if (!(s.gravityStartTime >= 0) || !std::isfinite(s.gravityStartTime)) {
        return std::string("gravity start time must be zero or positive");
    }
    if (!(s.seamWeldDistance >= 0)) {
        return std::string("seam weld distance must be zero or positive");
    }
    if (!(s.seamReach >= 0) || !std::isfinite(s.seamReach)) {
        return std::string("seam reach must be zero or positive");
    }
    if (!(s.seamRouteClearance >= 0) || !std::isfinite(s.seamRouteClearance)) {
        return std::string("seam route clearance must be zero or positive");
    }
    if (!(s.seamStiffnessPerLength >= 0) || !std::isfinite(s.seamStiffnessPerLength)) {
        return std::string("seam stiffness per length must be zero or positive");
    }
    for (std::size_t k = 0; k < s.seams.size(); ++k) {
        if (!(s.seams[k].length >= 0) || !std::isfinite(s.seams[k].length)) {
            return "seam pair " + std::to_string(k) + ": length must be zero or positive";
        }
    }
    if (!s.seams.empty() && !(s.seamTimeConstant > 0)) {
        return std::string("seam time constant must be positive");
    }
    for (std::size_t k = 0; k < s.obstacles.size(); ++k) {
        const ObstacleSpec& ob = s.obstacles[k];
        const std::string who = "obstacle " + std::to_string(k) + " (" + ob.name + ")";
        const int nv = static_cast<int>(ob.vertices.rows());
        if (ob.triangles.rows() == 0 || nv == 0) {
            return who + ": mesh has no triangles";
        }
        if (!ob.vertices.allFinite()) {
            return who + ": vertex positions must be finite";
        }
        for (Eigen::Index t = 0; t < ob.triangles.rows(); ++t) {
            for (int c = 0; c < 3; ++c) {
                if (ob.triangles(t, c) < 0 || ob.triangles(t, c) >= nv) {
                    return who + ": triangle " + std::to_string(t) + " has a vertex out of range";
                }
            }
        }
        if (ob.closed && !isClosedOriented(ob.triangles, nv)) {
            return who + ": marked closed but not watertight with consistent orientation";
        }
        if (!(ob.thickness >= 0) || !(ob.staticFriction >= 0) || !(ob.kineticFriction >= 0) ||
            !std::isfinite(ob.thickness + ob.staticFriction + ob.kineticFriction)) {
            return who + ": thickness and friction must be non-negative and finite";
        }
        for (std::size_t i = 1; i < ob.keys.size(); ++i) {
            if (!(ob.keys[i].time > ob.keys[i - 1].time)) {
                return who + ": key times must increase (key " + std::to_string(i) + ")";
            }
        }
        for (const ObstacleKey& key : ob.keys) {
            if (!key.translation.allFinite() || !key.rotation.allFinite() || !std::isfinite(key.time)) {
                return who + ": keys must be finite";
            }
        }
        if (ob.frames.size() != ob.frameTimes.size()) {
            return who + ": as many frame times as frames are needed";
        }
        for (std::size_t i = 0; i < ob.frames.size(); ++i) {
            if (ob.frames[i].rows() != nv || !ob.frames[i].allFinite()) {
                return who + ": frame " + std::to_string(i) + " must have " + std::to_string(nv) +
                       " finite positions";
            }
            if (i > 0 && !(ob.frameTimes[i] > ob.frameTimes[i - 1])) {
                return who + ": frame times must increase (frame " + std::to_string(i) + ")";
            }
        }
    }
    for (std::size_t ci = 0; ci < s.cloths.size(); ++ci) {
        if (!(s.cloths[ci].thickness >= 0) || !std::isfinite(s.cloths[ci].thickness)) {
            return "cloth " + std::to_string(ci) + ": thickness must be non-negative and finite";
        }
    }
    if (!(s.collision.iterations >= 1) || !(s.collision.proximityFactor >= 0) ||
        !(s.collision.extractionSpeed > 0)) {
        return std::string("collision: need iterations >= 1, proximity factor >= 0, extraction speed > 0");
    }
    const IntegratorOptions& o = s.integrator;
    if (!(o.dt > 0) || !(o.minDt > 0) || !(o.maxDt >= o.minDt) || !(o.tolerance > 0) ||
        !(o.growth > 1.0)) {
        return std::string("integrator: need dt > 0, tolerance > 0, 0 < min_dt <= max_dt, growth > 1");
    }
    if (!(s.duration >= 0) || !std::isfinite(s.duration) || !(s.frameRate > 0)) {
        return std::string("duration must be >= 0 and frame rate > 0");
    }
    if (!(s.highDampingTimeConstant >= 0)) {
        return std::string("high damping time constant must be >= 0");
    }
    return std::nullopt;
}

Simulation::Simulation(SceneSpec scene) : m_impl(std::make_unique<Impl>(std::move(scene))) {
    if (auto e = validate(m_impl->scene)) {
        m_impl->error = *e;
        m_impl->failed = true;
        m_impl->stats.error = *e;
        return;
    }
    m_impl->build();
}

Simulation::~Simulation() = default;

RunStatus Simulation::advance(double dt) {
    Impl& s = *m_impl;
    if (s.failed) {
        return RunStatus::Failed;
    }
    const double target = s.t + dt;
    while (s.t < target - 1e-12 * std::max(1.0, target)) {
        if (!s.step(target - s.t)) {
            s.stats.error = s.error;
            s.stats.finite = s.x.allFinite() && s.v.allFinite();
            return RunStatus::Failed;
        }
    }
    s.t = std::max(s.t, target);
    s.stats.simTime = s.t;
    return RunStatus::Finished;
}

RunStatus Simulation::run(double until, const std::function<void(int, double)>& onFrame,
                          const std::atomic<bool>* cancel) {
    Impl& s = *m_impl;
    if (s.failed) {
        return RunStatus::Failed;
    }
    const double frame = 1.0 / s.scene.frameRate;
    int index = static_cast<int>(std::floor(s.t / frame + 1e-9));
    while (s.t < until - 1e-12) {
        if (cancel != nullptr && cancel->load()) {
            return RunStatus::Cancelled;
        }
        const double nextFrame = std::min(until, (index + 1) * frame);
        if (advance(nextFrame - s.t) != RunStatus::Finished) {
            return RunStatus::Failed;
        }
        ++index;
        if (s.collision) {
            // A measurement for the report, not part of the steps.
            StageTimer timer(s.stats.stageSeconds["collision.measure"]);
            s.stats.maxPenetration = std::max(s.stats.maxPenetration, s.collision->penetration(s.x));
        }
        if (onFrame) {
            onFrame(index, s.t);
        }
    }
    return RunStatus::Finished;
}

double Simulation::time() const { return m_impl->t; }
const MatX3& Simulation::positions() const { return m_impl->x; }
const MatX3& Simulation::velocities() const { return m_impl->v; }
const VecX& Simulation::masses() const { return m_impl->mass; }
const SceneSpec& Simulation::scene() const { return m_impl->scene; }
const std::vector<int>& Simulation::clothOffsets() const { return m_impl->offsets; }
std::vector<std::string> Simulation::activeStages() const { return m_impl->stages; }
const std::string& Simulation::error() const { return m_impl->error; }
const CollisionStage* Simulation::collision() const { return m_impl->collision.get(); }

long Simulation::intersectingTrianglePairs(long* withObstacles) const {
    if (withObstacles != nullptr) {
        *withObstacles = 0;
    }
    return m_impl->collision ? m_impl->collision->intersectingTrianglePairs(m_impl->x, withObstacles)
                             : 0;
}

double Simulation::penetration() const {
    return m_impl->collision ? m_impl->collision->penetration(m_impl->x) : 0.0;
}

const MatX3& Simulation::obstaclePositions(int k) const {
    return m_impl->collision->obstaclePositions(k);
}

const std::vector<std::unique_ptr<ForceModel>>& Simulation::forceModels() const {
    return m_impl->models;
}

const RunStats& Simulation::stats() const {
    Impl& s = *m_impl;
    s.stats.finite = s.x.allFinite() && s.v.allFinite();
    // The gravitational part of the bound: no vertex can have dropped below the lowest point
    // reached, so gravity has done at most |g| (Σ m_i h_i(0) − M·h_lowest) of work.
    s.stats.energyInput = s.energyBound(s.x);
    return s.stats;
}

double Simulation::kineticEnergy() const {
    const Impl& s = *m_impl;
    return 0.5 * (s.mass.array() * s.v.rowwise().squaredNorm().array()).sum();
}

double Simulation::potentialEnergy() const {
    const Impl& s = *m_impl;
    double e = 0;
    for (const auto& m : s.models) {
        if (m->hasEnergy()) {
            e += m->energy(s.x);
        }
    }
    if (s.scene.gravity) {
        e -= (s.mass.array() * (s.x * s.scene.gravityVector).array()).sum();
    }
    return e;
}

double Simulation::maxEdgeStrain() const {
    const Impl& s = *m_impl;
    double worst = -1.0;
    for (std::size_t c = 0; c < s.scene.cloths.size(); ++c) {
        worst = std::max(worst, sim::maxEdgeStrain(s.scene.cloths[c].mesh, s.x, s.offsets[c]));
    }
    return worst;
}

void Simulation::evaluateForces(const MatX3& x, const MatX3& v, MatX3& f) const {
    const Impl& s = *m_impl;
    f.setZero(x.rows(), 3);
    for (const auto& m : s.models) {
        m->addForces(x, v, f);
    }
    if (s.scene.gravity) {
        for (Eigen::Index i = 0; i < x.rows(); ++i) {
            f.row(i) += s.mass[i] * s.scene.gravityVector.transpose();
        }
    }
}

} // namespace atelier::sim
