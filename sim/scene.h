#pragma once
/// What a simulation is asked to do: cloths, constraints, environment and solver settings.
/// Plain data: `sim/` takes arrays; files and JSON are io/'s business.

#include "sim/integrators/linear_solver.h"
#include "sim/material.h"
#include "sim/mesh/cloth_mesh.h"

#include <array>
#include <string>
#include <vector>

namespace atelier::sim {

/// In-plane (stretch/shear) model of a cloth.
enum class StretchModel {
    Springs, ///< edge springs (+ optional cross springs): the baseline
    Volino,  ///< Volino & Magnenat-Thalmann 1997 §3.1 corrected-elongation triangle model
    Fem,     ///< orthotropic St. Venant–Kirchhoff constant-strain triangles
};

/// Bending model of a cloth.
enum class BendingModel {
    Hinge,     ///< discrete shells, `material.bending` per hinge (sim/forces/bending.h)
    Continuum, ///< plate bending with rigidity `material.bending` on any mesh, orthotropic
               ///< (sim/forces/continuum_bending.h)
};

enum class IntegratorKind { Euler, Midpoint, Rk4, Rk45, ImplicitEuler };

/// Every stretch model and integrator, in the order messages list them.
inline constexpr std::array<StretchModel, 3> STRETCH_MODELS = {
    StretchModel::Springs, StretchModel::Volino, StretchModel::Fem};
inline constexpr std::array<IntegratorKind, 5> INTEGRATOR_KINDS = {
    IntegratorKind::Euler, IntegratorKind::Midpoint, IntegratorKind::Rk4, IntegratorKind::Rk45,
    IntegratorKind::ImplicitEuler};

/// One piece of cloth. Vertex indices in constraints are global: cloths are concatenated in order.
struct ClothSpec {
    std::string name = "cloth";
    ClothMesh mesh; ///< topology and rest shape (built with buildClothMesh)
    MatX3 position; ///< (|V|×3) initial positions [m]
    MatX3 velocity; ///< (|V|×3) initial velocities [m/s]; empty = at rest
    Material material;
    StretchModel model = StretchModel::Fem;
    bool crossSprings = false; ///< springs model only: add springs across each hinge
    bool bending = true;       ///< bending (with `bendingModel`)
    /// Hinge by default until the hard cases pass with Continuum (decisions/020).
    BendingModel bendingModel = BendingModel::Hinge;
    bool plasticity = false; ///< bending plasticity (material.plasticYieldAngle)
    /// (|H|) optional per-hinge rest fold angle [rad] (0 = flat); empty = flat pattern.
    VecX restAngles;
    /// Collision thickness: the distance this cloth keeps from obstacles and other cloth,
    /// added to theirs [m].
    double thickness = 0.002;
    /// Detect and resolve this cloth's collisions with itself (and with other cloths that
    /// also ask for it). Off = the stage is not in the pipeline for it.
    bool selfCollision = false;
};

/// A rigid pose of an obstacle at a time: world = R(rotation)·local + translation.
struct ObstacleKey {
    double time = 0;                 ///< [s]
    Vec3 translation = Vec3::Zero(); ///< [m]
    /// Rotation vector (axis × angle) [rad]. Keys are interpolated linearly in the rotation
    /// vector, so a spin about one axis may hold many turns between two keys.
    Vec3 rotation = Vec3::Zero();
};

/// A collision obstacle: a triangle mesh (loaded, or generated from a shape), static or
/// moving rigidly by keyframes or per vertex by frames. Outward normals by the right-hand
/// rule (counter-clockwise seen from outside).
struct ObstacleSpec {
    std::string name = "obstacle";
    MatX3 vertices;   ///< (|V|×3) in the obstacle's own frame [m]
    MatX3i triangles; ///< (|F|×3)
    /// Watertight and consistently oriented: it has an inside, and a cloth vertex found
    /// inside is pushed out (to the side it entered from). Open meshes (a plane) have two
    /// sides, and a vertex keeps the side it was on.
    bool closed = false;
    std::vector<ObstacleKey> keys; ///< rigid motion; empty = static at its own frame
    /// Per-vertex animation (an animated body): positions per frame (|V|×3 each) at
    /// `frameTimes`, linearly interpolated; when set it replaces `keys`.
    std::vector<double> frameTimes;
    std::vector<MatX3> frames;
    double thickness = 0.002;     ///< collision thickness of the obstacle surface [m]
    double staticFriction = 0.4;  ///< Coulomb static coefficient [-]
    double kineticFriction = 0.3; ///< Coulomb kinetic coefficient [-]
};

/// Contacts inside the implicit solve (CollisionOptions::solveContacts,
/// sim/collision/contact_forces.h).
struct ContactSolveOptions {
    /// Normal stiffness of a contact as a multiple of m/h², m the contact's effective mass and
    /// h the step [-]. A vertex carrying the weight of N others sinks by N·g·h²/κ into the layer.
    double stiffness = 100.0;
    /// Thickness of the layer above the contact distance in which the spring acts, as a
    /// fraction of the distance [-]. The corrections after the solve still push anything
    /// closer than the distance out; a contact at rest sits in this layer, where they do not act.
    double margin = 0.25;
    /// Friction: below this relative tangential speed ε the Coulomb force is a viscosity
    /// μ_s·λ/ε (sticking: a creep of at most ε under any load within the static cone); above
    /// it the kinetic force μ_k·λ against the slip [m/s].
    double slipSpeed = 1e-4;
    /// Cloth–cloth contacts in the solve too (each side's own blocks; the coupling between
    /// the sides stays explicit). Off: only cloth–obstacle contacts, and cloth–cloth contacts
    /// act only through the corrections after the solve (which is what left piled sheets
    /// stretched and let a dragged fold deadlock against the fail-safe: see the README).
    bool selfContacts = true;
};

/// Collision stage settings (used only when the scene has obstacles or self-collision).
struct CollisionOptions {
    /// Continuous detection over each step (vertex–triangle and edge–edge), so fast obstacles
    /// and large steps cannot tunnel.
    bool continuous = true;
    /// Gauss–Seidel passes of the position/velocity corrections per step.
    int iterations = 4;
    /// Contacts are gathered within (1 + proximityFactor) × the contact distance, so that
    /// vertices about to touch are known to the next step [-].
    double proximityFactor = 0.5;
    /// Largest speed at which a vertex found inside a closed obstacle is carried out along
    /// the cloth toward where it entered [m/s].
    double extractionSpeed = 1.0;
    /// Self-collision fail-safe: after the corrections, cloth–cloth pairs still crossing over
    /// the step (tested exactly, without curvature culling) have their vertices put back at
    /// the step's start, which was free of those crossings. No new self-intersection can
    /// appear, at the cost of one swept test per nearby primitive pair.
    bool failSafe = true;
    /// Implicit Euler: contacts also act inside the linear solve (a stiff spring in a thin
    /// layer above the contact distance and lagged Coulomb friction), so cloth resting on a
    /// body is held up and stuck by the solve itself and the drape can come to rest. The
    /// corrections after the step stay as they are. Off = contacts act only after the solve.
    bool solveContacts = true;
    ContactSolveOptions solve;
};

/// A vertex moved along a path: position keyframes, linearly interpolated in time.
/// Before the first key it holds the first; after `releaseTime` it is free.
struct Drive {
    int vertex = 0;
    std::vector<double> times;   ///< keyframe times [s], increasing
    std::vector<Vec3> positions; ///< keyframe positions [m]
    double releaseTime = 1e300;  ///< time after which the vertex is no longer driven [s]
    /// Tracker input: instead of following the path exactly (A + B), the vertex's acceleration
    /// is set (B) to the critically damped law a = −(x − p)/τ² − 2(v − ṗ)/τ with this time
    /// constant τ [s], which low-pass filters a noisy path whatever the cloth pulling on it.
    /// 0 = exact.
    double followTimeConstant = 0.0;
};

/// How seam pairs are pulled together.
enum class SeamMode {
    /// A force (C) of a critically damped spring with the time constant: closing competes
    /// with the load, so a heavy panel hanging from a seam holds it open by ~a·τ².
    Elastic,
    /// The same law imposed on the pair's relative acceleration (B), whatever the other
    /// forces: every gap closes like (1 + t/τ)e^{−t/τ} under any load (garment sewing).
    Imposed,
};

/// A seam elastic pulling two vertices together.
struct SeamPair {
    int a = 0;
    int b = 0;
    /// Length of seam the pair stands for (half its neighbours' spacing on each side,
    /// averaged) [m], for SceneSpec::seamStiffnessPerLength; 0 = none.
    double length = 0.0;
    /// Once welded, the rest fold angle of the seam's hinges at this pair [rad] (0 = flat: the
    /// cloth runs on across the seam); positive where the seam turns away from the front of the
    /// cloth on the pair's `a` side (a convex edge seen from that side, `dihedralAngle`).
    double foldAngle = 0.0;
    /// Once welded, the seam's bending rigidity as a multiple of its cloths' (1 = as stiff as
    /// the cloth beside it; a seam allowance pressed open adds two layers: about 3) [-].
    double bendingScale = 1.0;
};

struct AirOptions {
    bool enabled = false;
    /// Linear drag coefficient on the normal relative velocity, per area [N·s/m³]
    /// (f = -c·A·((v - wind)·n) n per triangle).
    double dragCoefficient = 0.5;
    Vec3 wind = Vec3::Zero(); ///< wind velocity [m/s]
};

struct IntegratorOptions {
    IntegratorKind kind = IntegratorKind::Rk45;
    double dt = 1e-3;        ///< fixed step, or the first step of rk45 [s]
    double tolerance = 1e-4; ///< rk45: allowed local error per step on positions [m]
    /// rk45: velocity errors count as position errors after this time [s]: a step is accepted
    /// when max(|Δx|, T·|Δv|) <= tolerance. Undamped stiff modes that grow slowly in position
    /// show first in velocity; this catches them.
    double velocityErrorTime = 0.01;
    double minDt = 1e-9;     ///< below this step the run stops with an error [s]
    double maxDt = 1.0 / 30; ///< upper bound of the adaptive step [s]
    double growth = 1.5;     ///< largest step growth factor after an accepted step ("grow slowly")
    /// A step after which some edge is longer than (1 + divergenceStrain) × its rest length is
    /// taken as diverging and rejected like a non-finite one (explicit methods beyond their
    /// stability limit blow up through huge but finite values first).
    double divergenceStrain = 10.0;
    /// A step whose collision corrections leave some edge longer than (1 + collisionStrainLimit)
    /// × its rest length, and longer than before the corrections and at the step's start, is
    /// counted and named (RunStats::stretchingSteps, stretching): contacts fighting over the
    /// mesh (a contact distance near the edge length) stretched a heavy stiff sheet at 15 mm
    /// thickness to 3.2× its edges' rest length in silence (docs/decisions/029-strain-guard.md).
    double collisionStrainLimit = 1.0;
    /// A step whose kinetic energy exceeds this many times the energy put into the cloth so
    /// far (initial energy, work of gravity, pins and drives) is rejected as diverging.
    double divergenceEnergyFactor = 10.0;
    /// Implicit Euler: conjugate-gradient relative tolerance and iteration cap.
    double cgTolerance = 1e-6;
    int cgMaxIterations = 500;
    /// Implicit Euler: the preconditioner of the solve (docs/decisions/019-linear-solver.md).
    LinearSolver linearSolver = LinearSolver::BlockJacobi;
};

struct SceneSpec {
    std::vector<ClothSpec> cloths;
    std::vector<ObstacleSpec> obstacles;
    CollisionOptions collision;
    std::vector<int> pins; ///< global vertex indices held at their initial position
    std::vector<Drive> drives;
    std::vector<SeamPair> seams;
    double seamTimeConstant = 0.05; ///< time constant of every seam elastic [s]
    /// Elastic seams: beyond a gap of this length a seam pulls with a constant force, so wide
    /// gaps close at about seamReach/(2τ) rather than snapping shut [m]; 0 = linear.
    double seamReach = 0.0;
    SeamMode seamMode = SeamMode::Elastic;
    /// Elastic seams: stiffness added per metre of seam (SeamPair::length) to each pair's
    /// μ/τ², damping 2τ times it: the seam's strength against the fabric's tension per length,
    /// whatever the mesh resolution [N/m²]; 0 = μ/τ² only.
    double seamStiffnessPerLength = 0.0;
    /// A seam pair whose gap closes below this distance is welded for good: from then on its
    /// vertices move as one (positions and velocities merged by mass, A; accelerations shared,
    /// B), so a closed seam stays closed under any tension [m]. 0 = elastics only. The caller
    /// ends a sewing phase by welding every pair whatever its gap (Simulation::weldAllSeams,
    /// Simulation::setSewingDeadline).
    double seamWeldDistance = 0.0;
    /// Seam routing (elastic seams, closed obstacles): an open pair whose straight chord passes
    /// through an obstacle is pulled around it, both vertices towards a via point this far
    /// outside (SeamElastics::setVia), re-chosen every step while routing is on
    /// (Simulation::setSeamRouting) [m]; 0 = off.
    double seamRouteClearance = 0.0;
    /// Welded seams bend like the cloth beside them: a hinge across every seam edge whose two
    /// pairs are welded (sim/forces/seam_bending.h). Off, a welded seam is a free hinge.
    bool seamBending = true;
    /// High damping: purely dissipative velocity damping (A) of every vertex toward the mean
    /// velocity of its neighbours, time constant [s]; 0 = off.
    double highDampingTimeConstant = 0.0;
    /// The scene has gravity (it may be held while a garment is sewn: Simulation::setGravity).
    bool gravity = true;
    Vec3 gravityVector = Vec3(0, -STANDARD_GRAVITY, 0); ///< [m/s²]
    AirOptions air;
    IntegratorOptions integrator;
    double duration = 1.0;   ///< simulated time [s]
    double frameRate = 30.0; ///< output frames per second [1/s]
};

} // namespace atelier::sim
