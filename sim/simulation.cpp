#include "sim/simulation.h"

#include "sim/collision/obstacle.h"
#include "sim/constraints/kinematic.h"
#include "sim/core/parallel.h"
#include "sim/scene_validation.h"
#include "sim/simulation_impl.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>

namespace atelier::sim {

std::string_view integratorName(IntegratorKind kind) {
    switch (kind) {
    case IntegratorKind::Euler:
        return "euler";
    case IntegratorKind::Midpoint:
        return "midpoint";
    case IntegratorKind::Rk4:
        return "rk4";
    case IntegratorKind::Rk45:
        return "rk45";
    case IntegratorKind::ImplicitEuler:
        return "implicit-euler";
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
    case StretchModel::Springs:
        return "springs";
    case StretchModel::Volino:
        return "volino";
    case StretchModel::Fem:
        return "fem";
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

std::string_view bendingModelName(BendingModel model) {
    switch (model) {
    case BendingModel::Hinge:
        return "hinge";
    case BendingModel::Continuum:
        return "continuum";
    }
    return "?";
}

std::optional<BendingModel> bendingModelFromName(std::string_view name) {
    for (auto m : {BendingModel::Hinge, BendingModel::Continuum}) {
        if (bendingModelName(m) == name) {
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

double Simulation::Impl::energyBound(const MatX3& xs) const {
    double e = baseEnergyInput;
    if (scene.gravity && scene.gravityVector.norm() > 0) {
        const Vec3 up = -scene.gravityVector.normalized();
        const double low = std::min(lowestY, (xs * up).minCoeff());
        e += scene.gravityVector.norm() * (massHeight0 - mass.sum() * low);
    }
    return e;
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
        if (drive.followTimeConstant <= 0 || !driveActive(drive, t) ||
            pinned[static_cast<std::size_t>(drive.vertex)]) {
            continue; // a pin holds the vertex, whatever drives it
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
        welds.shareAccelerations(a, mass, invMass);
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

double Simulation::Impl::constraintPower(const MatX3& f, const MatX3& a, const MatX3& vel) const {
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
    if (collision && collision->selfCollision()) {
        // The corrections of the last step may have left welded groups apart (weldAfterStep):
        // bringing them together must not carry cloth through cloth either.
        StageTimer collisionTimer(*timerCollision); // collision work (nested here)
        welds.mergeWithoutCrossing(x, v, mass, invMass, weldCrossingTest(), mergeUnchecked);
    } else {
        welds.merge(&x, v, mass, invMass);
    }
}

SeamWelds::CrossingTest Simulation::Impl::weldCrossingTest() {
    return [this](const MatX3& before, const MatX3& after, const std::vector<int>& moved) {
        return collision->crossingVertices(before, after, moved);
    };
}

void Simulation::Impl::routeSeams() {
    if (seamElastics == nullptr || !collision || !(scene.seamRouteClearance > 0)) {
        return;
    }
    if (!seamRouting && !seamsRouted) {
        return; // after sewing: nothing to route, nothing left to clear
    }
    const double before = seamElastics->energy(x);
    seamsRouted = false;
    for (std::size_t k = 0; k < scene.seams.size(); ++k) {
        const SeamPair& p = scene.seams[k];
        Vec3 via;
        const bool route = seamRouting && pairOpen(k) &&
                           collision->routeAround(x.row(p.a).transpose(), x.row(p.b).transpose(),
                                                  scene.seamRouteClearance, via);
        seamElastics->setVia(k, route ? &via : nullptr);
        seamsRouted = seamsRouted || route;
    }
    baseEnergyInput += std::max(0.0, seamElastics->energy(x) - before);
}

bool Simulation::Impl::weldClosedSeams() {
    if (sewingDeadline >= 0 && t >= sewingDeadline - 1e-12) {
        forceWelds = true;
    }
    if (!(scene.seamWeldDistance > 0) && !forceWelds) {
        return false;
    }
    return welds.weldClosed(x, scene.seamWeldDistance, forceWelds, weldFigures);
}

double Simulation::Impl::imposeSeamAccelerations(const MatX3& xs, const MatX3& vs, MatX3& a) const {
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
        contactForces.prepare(collision->contacts(), x, v, invMass, dtNominal,
                              scene.collision.solve);
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
        if (d.followTimeConstant > 0 && driveActive(d, t) &&
            !pinned[static_cast<std::size_t>(d.vertex)]) {
            const double tau = d.followTimeConstant;
            const PathSample p = samplePath(d, t + h);
            const Vec3 xi = x.row(d.vertex).transpose();
            const Vec3 vi = v.row(d.vertex).transpose();
            const Vec3 vNext =
                (vi + h * (-(xi - p.position) / (tau * tau) + 2.0 * p.velocity / tau)) /
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
                     scene.integrator.cgMaxIterations, &welds.groups());
    }
    stats.cgIterations += r.iterations;
    ++stats.linearSolves;
    stats.unconvergedSolves += r.converged ? 0 : 1;
    stats.cappedSolves += r.capped ? 1 : 0;
    stats.worstRelativeResidual = std::max(stats.worstRelativeResidual, r.relativeResidual);
    vNew = v + dv;
    if (scene.seamMode == SeamMode::Imposed && !scene.seams.empty()) {
        const double before = 0.5 * (mass.array() * vNew.rowwise().squaredNorm().array()).sum();
        imposeSeamVelocities(h, vNew);
        const double after = 0.5 * (mass.array() * vNew.rowwise().squaredNorm().array()).sum();
        seamPower = std::max(0.0, after - before) / h;
    }
    welds.merge(nullptr, vNew, mass,
                invMass); // welded pairs keep one velocity (positions follow below)
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

double Simulation::Impl::beginStep(double maxH) {
    double h = std::min({dtNext, maxH, scene.integrator.maxDt});
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
    if (sewingDeadline > t + 1e-12 && sewingDeadline < t + h) {
        h = sewingDeadline - t;
    }
    routeSeams();
    return h;
}

bool Simulation::Impl::attemptStep(double h, double& errorRatio, double& work) {
    const IntegratorOptions& opt = scene.integrator;
    hStep = h;
    collisionPower = 0;
    seamPower = 0;
    contactPotential = 0;
    xSave = x; // members: no allocation after the first step
    vSave = v;
    applyCorrectionsA(h);
    errorRatio = 0;
    bool ok =
        opt.kind == IntegratorKind::ImplicitEuler ? implicitStep(h) : explicitStep(h, errorRatio);
    work = 0;
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
        ok = ke <=
             opt.divergenceEnergyFactor * (energyBound(xNew) + std::max(0.0, work) + contactWork) +
                 1e-6 * mass.sum(); // below ~1 mm/s of motion: never a divergence
        energyRejected = !ok;
        keRejected = ke;
    }
    const bool accept = ok && errorRatio <= 1.0;
    if (accept && collision) {
        xPreCollision = xNew;
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
        // Counted and said, not rejected: retried smaller, the same corrections stretch the
        // same way, and legitimate ones (trapped cloth carried out) do it too.
        if (const std::string s = collisionStretch(); !s.empty()) {
            ++stats.stretchingSteps;
            stats.stretching = s + " at t = " + std::to_string(t + h) + " s";
        }
    }
    if (accept) {
        work +=
            std::max(0.0, seamPower * h) + std::max(0.0, contactPotential - lastContactPotential);
        seamPower = 0;
        lastContactPotential = contactPotential;
        return true;
    }
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
    if (!ok) {
        errorRatio = std::numeric_limits<double>::infinity(); // shrink the step by 4
    }
    return false;
}

std::string Simulation::Impl::collisionStretch() const {
    const double limit = scene.integrator.collisionStrainLimit;
    std::size_t worst = allEdges.size();
    double worstStrain = limit;
    double worstBefore = 0;
    for (std::size_t e = 0; e < allEdges.size(); ++e) {
        const int a = allEdges[e][0], b = allEdges[e][1];
        const double rest = allEdgeRest[e];
        const double strain = (xNew.row(b) - xNew.row(a)).norm() / rest - 1.0;
        if (!(strain > worstStrain)) {
            continue;
        }
        const double before = (xPreCollision.row(b) - xPreCollision.row(a)).norm() / rest - 1.0;
        const double start = (x.row(b) - x.row(a)).norm() / rest - 1.0;
        if (strain > before && strain > start) {
            worstStrain = strain;
            worstBefore = before;
            worst = e;
        }
    }
    if (worst == allEdges.size()) {
        return {};
    }
    const int c = edgeCloth[worst];
    const int off = offsets[static_cast<std::size_t>(c)];
    const ClothSpec& cloth = scene.cloths[static_cast<std::size_t>(c)];
    std::ostringstream why;
    why << "the collision corrections stretched edge (" << allEdges[worst][0] - off << ", "
        << allEdges[worst][1] - off << ") of cloth '" << cloth.name << "' from "
        << 1.0 + worstBefore << " to " << 1.0 + worstStrain << " × its rest length ("
        << allEdgeRest[worst] << " m; limit " << 1.0 + limit << " ×): contacts fighting over "
        << "the mesh, as where the contact distance (cloth thickness " << cloth.thickness
        << " m plus the obstacle's or other cloth's) nears the edge length";
    return why.str();
}

void Simulation::Impl::updateSeamHinges() {
    if (seamBending == nullptr) {
        return;
    }
    // A seam's hinges act once it is welded (and not held), holding the fold it was welded
    // with: energy put in, as a forced weld's stretch is. Let act, they grow from nothing to
    // their stiffness over SEAM_BENDING_RAMP: switched on at once, the folds a sewing phase
    // left were pushed at full strength in one step, and the 20 mm dress went 1.2 mm into the
    // body.
    const double before = seamBending->energy(x);
    if (seamBendingHeld) {
        seamBending->switchOff();
    } else {
        seamBending->followWelds(welds);
    }
    seamBending->setStrength((t - seamBendingSince) / detail::SEAM_BENDING_RAMP);
    baseEnergyInput += std::max(0.0, seamBending->energy(x) - before);
}

void Simulation::Impl::weldAfterStep() {
    const double forcedBefore = weldFigures.largestForced;
    const bool newWelds = weldClosedSeams();
    if (newWelds || !welds.empty()) {
        // Also after the collision corrections, which move vertices one by one: a welded
        // group leaves every step as one point.
        StageTimer timer(*timerConstraints);
        // Pairs welded from afar (end of sewing) stretch the cloth: that elastic energy is
        // put in by the weld, so the divergence check counts it.
        double elasticBefore = 0;
        const bool forced = newWelds && weldFigures.largestForced > forcedBefore;
        if (forced) {
            for (const auto& m : models) {
                elasticBefore += m->hasEnergy() ? m->energy(x) : 0.0;
            }
        }
        xPreMerge = x;
        vPreMerge = v;
        welds.merge(&x, v, mass, invMass);
        if (collision && collision->selfCollision()) {
            // A weld moves both sides of the pair onto their common point: where that
            // carries a triangle through the cloth beside the seam, the pair is not welded
            // this step (its elastic keeps pulling), so welds never make intersections.
            StageTimer collisionTimer(*timerCollision); // collision work (nested here)
            welds.unweldCrossing(xPreMerge, vPreMerge, x, v, mass, invMass, weldCrossingTest(),
                                 weldFigures);
        }
        if (forced) {
            double elasticAfter = 0;
            for (const auto& m : models) {
                elasticAfter += m->hasEnergy() ? m->energy(x) : 0.0;
            }
            baseEnergyInput += std::max(0.0, elasticAfter - elasticBefore);
        }
        updateSeamHinges();
    }
    // Every change of the figures welds or defers a pair: copy them only then.
    if (weldFigures.weldedPairs != stats.weldedSeamPairs ||
        weldFigures.deferred != stats.deferredWelds) {
        stats.weldedSeamPairs = weldFigures.weldedPairs;
        stats.largestForcedWeld = weldFigures.largestForced;
        stats.deferredWelds = weldFigures.deferred;
        stats.forcedWeldGaps = weldFigures.forcedGaps;
    }
}

void Simulation::Impl::endStep(double h, double errorRatio) {
    const IntegratorOptions& opt = scene.integrator;
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
}

bool Simulation::Impl::step(double maxH) {
    const IntegratorOptions& opt = scene.integrator;
    double h = beginStep(maxH);
    for (;;) {
        if (h < opt.minDt) {
            std::ostringstream s;
            s << "time step fell below the floor (" << h << " s < " << opt.minDt
              << " s) at t = " << t
              << " s: the state cannot be integrated stably (last rejection: " << lastRejection
              << ")";
            error = s.str();
            failed = true;
            return false;
        }
        const auto start = Clock::now();
        double errorRatio = 0;
        double work = 0;
        const bool accept = attemptStep(h, errorRatio, work);
        stats.wallTime += seconds(start, Clock::now());
        if (!accept) {
            ++stats.rejectedSteps;
            x = xSave;
            v = vSave;
            // A non-finite or diverging state: a quarter; too large an error: by the estimate.
            h *=
                std::isfinite(errorRatio) ? std::max(0.1, 0.9 * std::pow(errorRatio, -0.25)) : 0.25;
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
        weldAfterStep();
        stats.wallTime += seconds(weldStart, Clock::now());
        endStep(h, errorRatio);
        return true;
    }
}

// ---------------------------------------------------------------------------------------------

std::optional<std::string> Simulation::validate(const SceneSpec& s) {
    return validateScene(s);
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

RunStatus Simulation::Impl::stepToFrame(double until, bool& frameDone) {
    frameDone = false;
    if (failed) {
        return RunStatus::Failed;
    }
    if (!(frameTarget >= 0)) {
        // A new frame: it ends at the next frame time (or `until`). The target is computed as
        // run() always has, t + (next − t), and kept until reached, so stepping one step at a
        // time takes exactly the steps of an uninterrupted run.
        const double frame = 1.0 / scene.frameRate;
        frameIndex = static_cast<long>(std::floor(t / frame + 1e-9));
        const double nextFrame = std::min(until, static_cast<double>(frameIndex + 1) * frame);
        frameTarget = t + (nextFrame - t);
    }
    if (until < frameTarget) {
        frameTarget = t + (until - t); // a nearer end than the frame's, asked for now
    }
    const double eps = 1e-12 * std::max(1.0, frameTarget);
    if (t < frameTarget - eps && !step(frameTarget - t)) {
        stats.error = error;
        stats.finite = x.allFinite() && v.allFinite();
        return RunStatus::Failed;
    }
    if (!posedObstacles.empty()) {
        settlePosedObstacles();
    }
    if (t >= frameTarget - eps) {
        t = std::max(t, frameTarget);
        stats.simTime = t;
        frameTarget = -1;
        ++frameIndex;
        frameDone = true;
        if (collision) {
            // A measurement for the report, not part of the steps.
            StageTimer timer(stats.stageSeconds["collision.measure"]);
            stats.maxPenetration = std::max(stats.maxPenetration, collision->penetration(x));
        }
    }
    if (snapshots != nullptr) {
        publishSnapshot();
    }
    return RunStatus::Finished;
}

RunStatus Simulation::step(double until) {
    bool frameDone = false;
    if (!(m_impl->t < until - 1e-12)) {
        return m_impl->failed ? RunStatus::Failed : RunStatus::Finished;
    }
    return m_impl->stepToFrame(until, frameDone);
}

RunStatus Simulation::run(double until, const std::function<void(int, double)>& onFrame,
                          const std::atomic<bool>* cancel) {
    Impl& s = *m_impl;
    if (s.failed) {
        return RunStatus::Failed;
    }
    while (s.t < until - 1e-12) {
        if (cancel != nullptr && cancel->load()) {
            return RunStatus::Cancelled;
        }
        bool frameDone = false;
        if (s.stepToFrame(until, frameDone) != RunStatus::Finished) {
            return RunStatus::Failed;
        }
        if (frameDone && onFrame) {
            onFrame(static_cast<int>(s.frameIndex), s.t);
        }
    }
    return RunStatus::Finished;
}

bool Simulation::atFrame() const {
    return !(m_impl->frameTarget >= 0);
}
long Simulation::frameIndex() const {
    return m_impl->frameIndex;
}

double Simulation::time() const {
    return m_impl->t;
}
void Simulation::setGravity(bool on) {
    m_impl->gravityOn = on;
}

void Simulation::setSeamBending(bool on) {
    if (on && m_impl->seamBendingHeld) {
        m_impl->seamBendingSince = m_impl->t;
    }
    m_impl->seamBendingHeld = !on;
    m_impl->updateSeamHinges();
}

void Simulation::setFrictionScale(double scale) {
    if (m_impl->collision) {
        m_impl->collision->setFrictionScale(scale);
    }
}

void Simulation::setSeamReach(double reach) {
    Impl& s = *m_impl;
    if (s.seamElastics == nullptr || reach == s.seamElastics->reach()) {
        return;
    }
    // A longer reach raises the potential of wide gaps: energy put in, counted.
    const double before = s.seamElastics->energy(s.x);
    s.seamElastics->setReach(reach);
    s.baseEnergyInput += std::max(0.0, s.seamElastics->energy(s.x) - before);
}

void Simulation::setSeamRouting(bool on) {
    m_impl->seamRouting = on;
}

void Simulation::weldAllSeams() {
    m_impl->forceWelds = true;
}

void Simulation::setSewingDeadline(double time) {
    m_impl->sewingDeadline = time;
}

void Simulation::setLinearSolver(LinearSolver solver) {
    m_impl->cg.setPreconditioner(solver);
}

void Simulation::setStep(double dt) {
    if (dt > 0) {
        m_impl->dtNominal = dt;
        m_impl->dtNext = dt;
    }
}

double Simulation::nominalStep() const {
    return m_impl->dtNominal;
}

LinearSolver Simulation::linearSolver() const {
    return m_impl->cg.preconditioner();
}

bool Simulation::seamsWelded() const {
    const Impl& s = *m_impl;
    return !s.scene.seams.empty() &&
           s.stats.weldedSeamPairs >= static_cast<long>(s.scene.seams.size());
}
const MatX3& Simulation::positions() const {
    return m_impl->x;
}
const MatX3& Simulation::velocities() const {
    return m_impl->v;
}
const VecX& Simulation::masses() const {
    return m_impl->mass;
}
const SceneSpec& Simulation::scene() const {
    return m_impl->scene;
}
const std::vector<int>& Simulation::clothOffsets() const {
    return m_impl->offsets;
}
std::vector<std::string> Simulation::activeStages() const {
    return m_impl->stages;
}
const std::string& Simulation::error() const {
    return m_impl->error;
}
const CollisionStage* Simulation::collision() const {
    return m_impl->collision.get();
}

long Simulation::intersectingTrianglePairs(long* withObstacles) const {
    if (withObstacles != nullptr) {
        *withObstacles = 0;
    }
    return m_impl->collision ? m_impl->collision->intersectingTrianglePairs(
                                   m_impl->x, m_impl->welds.groups(), withObstacles)
                             : 0;
}

double Simulation::penetration() const {
    return m_impl->collision ? m_impl->collision->penetration(m_impl->x) : 0.0;
}

double Simulation::contactLayerCrush() const {
    return m_impl->collision ? m_impl->collision->contactLayerCrush(m_impl->x) : 0.0;
}

bool Simulation::seamPairWelded(std::size_t k) const {
    return m_impl->welds.welded(k);
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
