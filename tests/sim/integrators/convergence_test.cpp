// Measured order of convergence of each integrator on a smooth problem, and the embedded
// Runge–Kutta pair's error estimate against the true error.

#include "sim/integrators/explicit_rk.h"
#include "sim/simulation.h"
#include "sim/test_scenes.h"

#include <gtest/gtest.h>

#include <cmath>

namespace atelier::sim {
namespace {

/// A soft 4×4 sheet swinging from two pins, with a sideways initial velocity: smooth and
/// non-linear (large rotations), cheap.
SceneSpec smoothProblem(IntegratorKind kind, double dt, double duration) {
    SceneSpec s = test::smallSheet(StretchModel::Fem, 4, 1.0, true);
    ClothSpec& c = s.cloths[0];
    c.material.stretchWeft = c.material.stretchWarp = 40.0;
    c.material.shear = 10.0;
    c.material.bending = 1e-4;
    c.material.damping = 1e-3;
    c.velocity = MatX3::Zero(c.position.rows(), 3);
    for (int i = 0; i < c.position.rows(); ++i) {
        c.velocity(i, 2) = 0.5 * c.position(i, 1);
    }
    s.integrator.kind = kind;
    s.integrator.dt = dt;
    s.integrator.maxDt = dt;
    s.duration = duration;
    s.frameRate = 1.0 / duration;
    return s;
}

MatX3 finalPositions(IntegratorKind kind, double dt, double duration) {
    Simulation sim(smoothProblem(kind, dt, duration));
    EXPECT_EQ(sim.run(duration), RunStatus::Finished) << sim.error();
    EXPECT_EQ(sim.stats().rejectedSteps, 0);
    return sim.positions();
}

double measuredOrder(IntegratorKind kind, double h0) {
    const double duration = 0.2;
    const MatX3 reference = finalPositions(IntegratorKind::Rk4, h0 / 64, duration);
    double previous = 0;
    double order = 0;
    for (int k = 0; k < 3; ++k) {
        const double h = h0 / std::pow(2.0, k);
        const double err =
            (finalPositions(kind, h, duration) - reference).rowwise().norm().maxCoeff();
        if (k > 0) {
            order = std::log2(previous / err);
        }
        previous = err;
    }
    return order;
}

TEST(Convergence, ExplicitEulerIsFirstOrder) {
    EXPECT_NEAR(measuredOrder(IntegratorKind::Euler, 2e-3), 1.0, 0.3);
}

TEST(Convergence, MidpointIsSecondOrder) {
    EXPECT_NEAR(measuredOrder(IntegratorKind::Midpoint, 4e-3), 2.0, 0.3);
}

TEST(Convergence, Rk4IsFourthOrder) {
    EXPECT_NEAR(measuredOrder(IntegratorKind::Rk4, 1e-2), 4.0, 0.3);
}

TEST(Convergence, ImplicitEulerIsFirstOrder) {
    EXPECT_NEAR(measuredOrder(IntegratorKind::ImplicitEuler, 2e-3), 1.0, 0.3);
}

TEST(Convergence, EmbeddedEstimateTracksTheTrueError) {
    // One Cash–Karp step from a moving state: the estimate (difference of the 5th- and
    // 4th-order solutions) must match the true error of the embedded 4th-order solution
    // (which it estimates) and shrink like h⁵; the propagated 5th-order solution must be the
    // more accurate of the two.
    Simulation sim(smoothProblem(IntegratorKind::Rk45, 1e-3, 0.2));
    ASSERT_EQ(sim.advance(0.05), RunStatus::Finished);
    const MatX3 x0 = sim.positions();
    const MatX3 v0 = sim.velocities();
    const VecX m = sim.masses();
    const auto& pins = sim.scene().pins;
    AccelerationFn acc = [&](double, const MatX3& x, const MatX3& v, MatX3& a) {
        sim.evaluateForces(x, v, a);
        for (int i = 0; i < a.rows(); ++i) {
            a.row(i) /= m[i];
        }
        for (int p : pins) {
            a.row(p).setZero();
        }
    };
    auto reference = [&](double h) {
        ExplicitRkStepper rk4(ButcherTableau::rk4());
        MatX3 x = x0;
        MatX3 v = v0;
        MatX3 xn;
        MatX3 vn;
        const int n = 400;
        for (int k = 0; k < n; ++k) {
            rk4.step(0, h / n, x, v, acc, xn, vn);
            x = xn;
            v = vn;
        }
        return x;
    };
    ExplicitRkStepper ck(ButcherTableau::cashKarp());
    ButcherTableau fourth = ButcherTableau::cashKarp();
    fourth.b = fourth.bEmbedded;
    fourth.bEmbedded.clear();
    ExplicitRkStepper ck4(fourth);
    double previousEstimate = 0;
    for (int k = 0; k < 3; ++k) {
        const double h = 2e-3 / std::pow(2.0, k);
        MatX3 x;
        MatX3 v;
        const double estimate = ck.step(0, h, x0, v0, acc, x, v, nullptr, 0.0);
        MatX3 x4;
        MatX3 v4;
        ck4.step(0, h, x0, v0, acc, x4, v4);
        const MatX3 ref = reference(h);
        const double error5 = (x - ref).rowwise().norm().maxCoeff();
        const double error4 = (x4 - ref).rowwise().norm().maxCoeff();
        EXPECT_GT(estimate / error4, 0.7)
            << "h = " << h << " error4 " << error4 << " est " << estimate;
        EXPECT_LT(estimate / error4, 1.4) << "h = " << h;
        EXPECT_LT(error5, error4) << "h = " << h;
        if (k > 0) {
            const double order = std::log2(previousEstimate / estimate);
            EXPECT_NEAR(order, 5.0, 0.7) << "h = " << h;
        }
        previousEstimate = estimate;
    }
}

} // namespace
} // namespace atelier::sim
