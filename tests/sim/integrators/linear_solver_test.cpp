// The implicit step's linear solver inside a simulation: the block incomplete Cholesky
// preconditioner gives the block-Jacobi trajectory with far fewer iterations, runs repeat bit
// for bit, a run may switch between them, and solves that stop at the iteration cap are
// counted with their residual.

#include "sim/simulation.h"
#include "sim/test_scenes.h"

#include <gtest/gtest.h>

namespace atelier::sim {
namespace {

/// A horizontal 1 m sheet of 16×16 cells held at two corners: it falls and swings, the case
/// on which block-Jacobi conjugate gradients needs hundreds of iterations a step.
SceneSpec hangingSheet(LinearSolver kind, double cgTolerance, int cgMaxIterations) {
    SceneSpec s = test::smallSheet(StretchModel::Fem, 16, 1.0, true, true);
    s.integrator.kind = IntegratorKind::ImplicitEuler;
    s.integrator.dt = 1.0 / 240;
    s.integrator.maxDt = s.integrator.dt;
    s.integrator.cgTolerance = cgTolerance;
    s.integrator.cgMaxIterations = cgMaxIterations;
    s.integrator.linearSolver = kind;
    s.duration = 0.25;
    s.frameRate = 1.0 / s.duration;
    return s;
}

TEST(LinearSolver, IncompleteCholeskyFollowsTheBlockJacobiTrajectoryInFewerIterations) {
    Simulation jacobi(hangingSheet(LinearSolver::BlockJacobi, 1e-10, 5000));
    Simulation ic(hangingSheet(LinearSolver::BlockIncompleteCholesky, 1e-10, 5000));
    ASSERT_EQ(jacobi.run(0.25), RunStatus::Finished) << jacobi.error();
    ASSERT_EQ(ic.run(0.25), RunStatus::Finished) << ic.error();
    EXPECT_EQ(jacobi.stats().steps, ic.stats().steps);
    EXPECT_EQ(jacobi.stats().unconvergedSolves, 0);
    EXPECT_EQ(ic.stats().unconvergedSolves, 0);
    EXPECT_LT(2 * ic.stats().cgIterations, jacobi.stats().cgIterations);
    // The sheet falls about 0.3 m; both solves are converged to 1e-10.
    EXPECT_LT((jacobi.positions() - ic.positions()).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(LinearSolver, IncompleteCholeskyRunsRepeatBitForBit) {
    Simulation a(hangingSheet(LinearSolver::BlockIncompleteCholesky, 1e-3, 500));
    Simulation b(hangingSheet(LinearSolver::BlockIncompleteCholesky, 1e-3, 500));
    ASSERT_EQ(a.run(0.25), RunStatus::Finished) << a.error();
    ASSERT_EQ(b.run(0.25), RunStatus::Finished) << b.error();
    EXPECT_TRUE(a.positions() == b.positions());
    EXPECT_EQ(a.stats().cgIterations, b.stats().cgIterations);
}

TEST(LinearSolver, SwitchedMidRunTheLaterSolvesTakeFewerIterations) {
    Simulation jacobi(hangingSheet(LinearSolver::BlockJacobi, 1e-10, 5000));
    Simulation switched(hangingSheet(LinearSolver::BlockJacobi, 1e-10, 5000));
    ASSERT_EQ(jacobi.run(0.125), RunStatus::Finished) << jacobi.error();
    ASSERT_EQ(switched.run(0.125), RunStatus::Finished) << switched.error();
    EXPECT_TRUE(jacobi.positions() == switched.positions());
    const long before = jacobi.stats().cgIterations;
    EXPECT_EQ(switched.stats().cgIterations, before);
    switched.setLinearSolver(LinearSolver::BlockIncompleteCholesky);
    EXPECT_EQ(switched.linearSolver(), LinearSolver::BlockIncompleteCholesky);
    EXPECT_EQ(jacobi.linearSolver(), LinearSolver::BlockJacobi);
    EXPECT_EQ(switched.scene().integrator.linearSolver, LinearSolver::BlockJacobi);
    ASSERT_EQ(jacobi.run(0.25), RunStatus::Finished) << jacobi.error();
    ASSERT_EQ(switched.run(0.25), RunStatus::Finished) << switched.error();
    EXPECT_EQ(jacobi.stats().steps, switched.stats().steps);
    EXPECT_EQ(switched.stats().unconvergedSolves, 0);
    EXPECT_LT(2 * (switched.stats().cgIterations - before), jacobi.stats().cgIterations - before);
    EXPECT_LT((jacobi.positions() - switched.positions()).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(LinearSolver, SolvesStoppedAtTheCapAreCountedWithTheirResidual) {
    Simulation capped(hangingSheet(LinearSolver::BlockJacobi, 1e-8, 3));
    ASSERT_EQ(capped.run(0.05), RunStatus::Finished) << capped.error();
    const RunStats& s = capped.stats();
    EXPECT_GT(s.linearSolves, 0);
    // Nearly every solve stops at the cap (a step whose right-hand side is already almost
    // solved may converge within 3 iterations); each one that stops there is counted as
    // capped and unconverged, with its 3 iterations.
    EXPECT_GE(s.cappedSolves, s.linearSolves - 2);
    EXPECT_EQ(s.unconvergedSolves, s.cappedSolves);
    EXPECT_GT(s.worstRelativeResidual, 1e-8);
    EXPECT_LE(s.cgIterations, 3 * s.linearSolves);
    EXPECT_GE(s.cgIterations, 3 * s.cappedSolves);

    Simulation converged(hangingSheet(LinearSolver::BlockJacobi, 1e-8, 5000));
    ASSERT_EQ(converged.run(0.05), RunStatus::Finished) << converged.error();
    EXPECT_EQ(converged.stats().cappedSolves, 0);
    EXPECT_LE(converged.stats().worstRelativeResidual, 1e-8);
}

} // namespace
} // namespace atelier::sim
