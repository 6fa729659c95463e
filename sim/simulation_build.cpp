/// Building a Simulation: its state and force models, the stages of its pipeline, and its
/// solver and collision stage (only what the scene needs).

#include "sim/collision/obstacle.h"
#include "sim/forces/air.h"
#include "sim/forces/bending.h"
#include "sim/forces/continuum_bending.h"
#include "sim/forces/fem.h"
#include "sim/forces/seam_bending.h"
#include "sim/forces/springs.h"
#include "sim/forces/volino.h"
#include "sim/simulation.h"
#include "sim/simulation_impl.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace atelier::sim {

void Simulation::Impl::build() {
    buildStateAndModels();
    listStages();
    buildSolver();
}

void Simulation::Impl::buildStateAndModels() {
    for (const ClothSpec& c : scene.cloths) {
        offsets.push_back(offsets.back() + c.mesh.vertexCount());
    }
    n = offsets.back();
    x.resize(n, 3);
    v.setZero(n, 3);
    mass.setZero(n);
    // Pinned at build: the continuum bending treats fully pinned triangles as a clamp.
    std::vector<char> held(static_cast<std::size_t>(n), 0);
    for (int p : scene.pins) {
        if (p >= 0 && p < n) {
            held[static_cast<std::size_t>(p)] = 1;
        }
    }
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
            allEdgeRest.push_back(
                (c.mesh.rest.row(c.mesh.edges(e, 1)) - c.mesh.rest.row(c.mesh.edges(e, 0))).norm());
            edgeCloth.push_back(static_cast<int>(ci));
        }
        switch (c.model) {
        case StretchModel::Springs:
            models.push_back(
                std::make_unique<SpringStretch>(c.mesh, off, c.material, c.crossSprings));
            break;
        case StretchModel::Volino:
            models.push_back(std::make_unique<VolinoStretch>(c.mesh, off, c.material, m));
            break;
        case StretchModel::Fem:
            models.push_back(std::make_unique<FemStretch>(c.mesh, off, c.material));
            break;
        }
        const bool bends =
            c.material.bending > 0 || c.material.bendingWeft > 0 || c.material.bendingWarp > 0;
        if (c.bending && bends && c.mesh.hinges.rows() > 0) {
            if (c.bendingModel == BendingModel::Continuum) {
                models.push_back(std::make_unique<ContinuumBending>(
                    c.mesh, off, c.material, c.restAngles, c.plasticity, held));
            } else {
                models.push_back(std::make_unique<DihedralBending>(c.mesh, off, c.material,
                                                                   c.restAngles, c.plasticity));
            }
        }
        if (scene.air.enabled) {
            models.push_back(std::make_unique<AirDrag>(c.mesh, off, scene.air));
        }
    }
    if (!scene.seams.empty() && scene.seamMode == SeamMode::Elastic) {
        auto seams = std::make_unique<SeamElastics>(scene.seams, mass, scene.seamTimeConstant,
                                                    scene.seamReach, scene.seamStiffnessPerLength);
        seamElastics = seams.get();
        models.push_back(std::move(seams));
    }
    pinned.assign(static_cast<std::size_t>(n), 0);
    pinPosition = x;
    for (int p : scene.pins) {
        pinned[static_cast<std::size_t>(p)] = 1;
    }
    welds = SeamWelds(scene.seams, n);
    if (scene.seamBending && !scene.seams.empty()) {
        if (auto hinges = SeamBending::build(scene, offsets)) {
            seamBending = hinges.get();
            seamBending->followWelds(welds);
            models.push_back(std::move(hinges));
        }
    }
    driveOf.assign(static_cast<std::size_t>(n), -1);
    for (std::size_t d = 0; d < scene.drives.size(); ++d) {
        driveOf[static_cast<std::size_t>(scene.drives[d].vertex)] = static_cast<int>(d);
    }
    updateHeld();
}

void Simulation::Impl::listStages() {
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
    if (!scene.seams.empty()) {
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
}

void Simulation::Impl::buildSolver() {
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
    case IntegratorKind::Euler:
        rk = std::make_unique<ExplicitRkStepper>(ButcherTableau::euler());
        break;
    case IntegratorKind::Midpoint:
        rk = std::make_unique<ExplicitRkStepper>(ButcherTableau::midpoint());
        break;
    case IntegratorKind::Rk4:
        rk = std::make_unique<ExplicitRkStepper>(ButcherTableau::rk4());
        break;
    case IntegratorKind::Rk45:
        rk = std::make_unique<ExplicitRkStepper>(ButcherTableau::cashKarp());
        break;
    case IntegratorKind::ImplicitEuler:
        cg.setPreconditioner(scene.integrator.linearSolver);
        break;
    }
    dtNominal = scene.integrator.dt;
    dtNext = scene.integrator.dt;
    if (CollisionStage::needed(scene)) {
        timerCollision = &stats.stageSeconds["collision"];
        // The start (hierarchies, trapped vertices) is timed apart: `collision` is a share of
        // the steps' wall time.
        StageTimer timer(stats.stageSeconds["collision.setup"]);
        collision = std::make_unique<CollisionStage>(scene, offsets, x);
        double thinnest = std::numeric_limits<double>::infinity();
        for (const ClothSpec& c : scene.cloths) {
            if (c.selfCollision) {
                thinnest = std::min(thinnest, c.thickness);
            }
        }
        mergeUnchecked = std::isfinite(thinnest) ? 0.5 * thinnest : 0.0;
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

} // namespace atelier::sim
