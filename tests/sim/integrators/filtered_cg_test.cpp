// Filtered CG: the plain solve against a dense one, constrained vertices held, and merged
// vertex groups (welded seams) solved as the reduced system P^T A P y = P^T b; the block
// incomplete Cholesky preconditioner against block-Jacobi; capped solves reported.

#include "sim/core/parallel.h"
#include "sim/integrators/block_incomplete_cholesky.h"
#include "sim/integrators/filtered_cg.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

namespace atelier {
namespace {

using sim::BlockSparseMatrix;
using sim::MatX3;

/// A random symmetric positive definite block matrix on a ring of n vertices (each coupled to
/// its two neighbours), as a mass matrix plus a spring-like stiffness.
BlockSparseMatrix ringMatrix(int n, unsigned seed) {
    std::vector<std::pair<int, int>> pairs;
    for (int i = 0; i < n; ++i) {
        pairs.emplace_back(i, (i + 1) % n);
    }
    BlockSparseMatrix A(n, pairs);
    A.setZero();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int i = 0; i < n; ++i) {
        const int j = (i + 1) % n;
        Eigen::Vector3d d(u(rng), u(rng), u(rng));
        const sim::Mat3 k = 50.0 * d * d.transpose() + 5.0 * sim::Mat3::Identity();
        A.add(i, i, k);
        A.add(j, j, k);
        A.add(i, j, -k);
        A.add(j, i, -k);
    }
    A.addDiagonal(sim::VecX::Constant(n, 1.0));
    return A;
}

MatX3 randomRhs(int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    MatX3 b(n, 3);
    for (int i = 0; i < n; ++i) {
        b.row(i) << u(rng), u(rng), u(rng);
    }
    return b;
}

Eigen::VectorXd flat(const MatX3& m) {
    return Eigen::Map<const Eigen::VectorXd>(m.data(), m.size());
}

/// A random symmetric positive definite block matrix on an m×m grid of vertices (springs to
/// the right, lower and diagonal neighbours, as a triangulated sheet), stiff against the mass
/// as a cloth's implicit system is: block-Jacobi needs tens of iterations.
BlockSparseMatrix gridMatrix(int m, unsigned seed, double stiffness) {
    std::vector<std::pair<int, int>> pairs;
    for (int r = 0; r < m; ++r) {
        for (int c = 0; c < m; ++c) {
            const int i = r * m + c;
            if (c + 1 < m) {
                pairs.emplace_back(i, i + 1);
            }
            if (r + 1 < m) {
                pairs.emplace_back(i, i + m);
            }
            if (c + 1 < m && r + 1 < m) {
                pairs.emplace_back(i, i + m + 1);
            }
        }
    }
    BlockSparseMatrix A(m * m, pairs);
    A.setZero();
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (const auto& [i, j] : pairs) {
        Eigen::Vector3d d(u(rng), u(rng), u(rng));
        const sim::Mat3 k = stiffness * (d * d.transpose() + 0.1 * sim::Mat3::Identity());
        A.add(i, i, k);
        A.add(j, j, k);
        A.add(i, j, -k);
        A.add(j, i, -k);
    }
    A.addDiagonal(sim::VecX::Constant(m * m, 1.0));
    return A;
}

/// The dense solution of the filtered reduced system: unknowns per group or free vertex,
/// held vertices at their value in `fixedRows`.
Eigen::VectorXd reducedReference(const BlockSparseMatrix& A, const MatX3& b,
                                 const std::vector<std::vector<int>>& groups,
                                 const std::vector<char>& held, const MatX3& fixedRows) {
    const int n = A.blockRows();
    std::vector<int> unknownOf(n, -1);
    int m = 0;
    for (const auto& g : groups) {
        bool groupHeld = false;
        for (int v : g) {
            groupHeld = groupHeld || held[v] != 0;
        }
        for (int v : g) {
            unknownOf[v] = groupHeld ? -2 : m;
        }
        m += groupHeld ? 0 : 1;
    }
    for (int i = 0; i < n; ++i) {
        if (unknownOf[i] == -1 && !held[i]) {
            unknownOf[i] = m++;
        }
    }
    Eigen::MatrixXd P = Eigen::MatrixXd::Zero(3 * n, 3 * m);
    for (int i = 0; i < n; ++i) {
        if (unknownOf[i] >= 0) {
            P.block<3, 3>(3 * i, 3 * unknownOf[i]).setIdentity();
        }
    }
    const Eigen::VectorXd fixed = flat(fixedRows);
    const Eigen::MatrixXd Ad = A.toDense();
    const Eigen::VectorXd y =
        (P.transpose() * Ad * P).ldlt().solve(P.transpose() * (flat(b) - Ad * fixed));
    return P * y + fixed;
}

sim::FilteredCg solverOf(sim::LinearSolver kind) {
    return sim::FilteredCg(kind);
}

TEST(FilteredCg, SolvesTheDenseSystem) {
    const int n = 12;
    const BlockSparseMatrix A = ringMatrix(n, 1);
    const MatX3 b = randomRhs(n, 2);
    MatX3 x = MatX3::Zero(n, 3);
    sim::FilteredCg cg = solverOf(sim::LinearSolver::BlockJacobi);
    const sim::CgResult r = cg.solve(A, b, std::vector<char>(n, 0), x, 1e-12, 500);
    EXPECT_TRUE(r.converged);
    const Eigen::VectorXd expected = A.toDense().ldlt().solve(flat(b));
    EXPECT_LT((flat(x) - expected).norm(), 1e-9 * expected.norm());
}

TEST(FilteredCg, MergedGroupsShareOneUnknownAndSolveTheReducedSystem) {
    const int n = 12;
    const BlockSparseMatrix A = ringMatrix(n, 3);
    const MatX3 b = randomRhs(n, 4);
    // Vertices far apart on the ring, as the two sides of a seam are; 7 is also held.
    const std::vector<std::vector<int>> groups = {{1, 6}, {3, 9, 11}};
    std::vector<char> held(n, 0);
    held[4] = 1;
    MatX3 x = MatX3::Zero(n, 3);
    x.row(4) << 0.1, -0.2, 0.3;
    sim::FilteredCg cg = solverOf(sim::LinearSolver::BlockJacobi);
    const sim::CgResult r = cg.solve(A, b, held, x, 1e-12, 500, &groups);
    EXPECT_TRUE(r.converged);
    for (const auto& g : groups) {
        for (int v : g) {
            EXPECT_EQ(x.row(v), x.row(g[0])) << "vertex " << v;
        }
    }
    EXPECT_EQ(x.row(4), (Eigen::RowVector3d(0.1, -0.2, 0.3)));

    // Reference: the reduced system with P (unknown per group or free vertex), dense.
    std::vector<int> unknownOf(n, -1);
    int m = 0;
    for (const auto& g : groups) {
        for (int v : g) {
            unknownOf[v] = m;
        }
        ++m;
    }
    for (int i = 0; i < n; ++i) {
        if (unknownOf[i] < 0 && !held[i]) {
            unknownOf[i] = m++;
        }
    }
    Eigen::MatrixXd P = Eigen::MatrixXd::Zero(3 * n, 3 * m);
    for (int i = 0; i < n; ++i) {
        if (unknownOf[i] >= 0) {
            P.block<3, 3>(3 * i, 3 * unknownOf[i]).setIdentity();
        }
    }
    Eigen::VectorXd fixed = Eigen::VectorXd::Zero(3 * n);
    fixed.segment<3>(3 * 4) << 0.1, -0.2, 0.3;
    const Eigen::MatrixXd Ad = A.toDense();
    const Eigen::VectorXd y =
        (P.transpose() * Ad * P).ldlt().solve(P.transpose() * (flat(b) - Ad * fixed));
    const Eigen::VectorXd expected = P * y + fixed;
    EXPECT_LT((flat(x) - expected).norm(), 1e-9 * expected.norm());
}

/// The seam-like case on a sheet: groups of far-apart vertices, one group with a held member,
/// held vertices with a prescribed Δv.
struct GroupedProblem {
    BlockSparseMatrix A = gridMatrix(8, 5, 200.0);
    MatX3 b = randomRhs(64, 6);
    std::vector<std::vector<int>> groups = {{1, 40}, {3, 50, 63}, {7, 56}};
    std::vector<char> held = std::vector<char>(64, 0);
    MatX3 x0 = MatX3::Zero(64, 3);
    GroupedProblem() {
        held[4] = 1;
        held[56] = 1; // the group {7, 56} is held at 56's value
        x0.row(4) << 0.1, -0.2, 0.3;
        x0.row(56) << -0.05, 0.0, 0.02;
    }
    MatX3 fixedRows() const {
        MatX3 f = MatX3::Zero(64, 3);
        f.row(4) = x0.row(4);
        f.row(56) = f.row(7) = x0.row(56);
        return f;
    }
};

TEST(FilteredCg, IncompleteCholeskySolvesTheGroupedFilteredSystemAsBlockJacobiDoes) {
    const GroupedProblem p;
    const Eigen::VectorXd expected = reducedReference(p.A, p.b, p.groups, p.held, p.fixedRows());
    MatX3 xJacobi = p.x0;
    sim::FilteredCg jacobi = solverOf(sim::LinearSolver::BlockJacobi);
    const sim::CgResult rj = jacobi.solve(p.A, p.b, p.held, xJacobi, 1e-12, 1000, &p.groups);
    MatX3 xIc = p.x0;
    sim::FilteredCg ic = solverOf(sim::LinearSolver::BlockIncompleteCholesky);
    const sim::CgResult ri = ic.solve(p.A, p.b, p.held, xIc, 1e-12, 1000, &p.groups);
    ASSERT_TRUE(rj.converged);
    ASSERT_TRUE(ri.converged);
    EXPECT_LT(ri.iterations, rj.iterations);
    EXPECT_LT((flat(xIc) - expected).norm(), 1e-9 * expected.norm());
    EXPECT_LT((flat(xIc) - flat(xJacobi)).norm(), 1e-9 * expected.norm());
    for (const auto& g : p.groups) {
        for (int v : g) {
            EXPECT_EQ(xIc.row(v), xIc.row(g[0])) << "vertex " << v;
        }
    }
    EXPECT_EQ(xIc.row(4), p.x0.row(4));
    EXPECT_EQ(xIc.row(7), p.x0.row(56));
}

TEST(FilteredCg, OnAPatternWithoutFillTheIncompleteFactorIsExact) {
    // A chain (a ring cut open, one vertex held in the middle): its factor has no fill, so
    // IC(0) is the exact LDLᵀ and one iteration solves the system.
    const int n = 12;
    std::vector<std::pair<int, int>> pairs;
    for (int i = 0; i + 1 < n; ++i) {
        pairs.emplace_back(i, i + 1);
    }
    const BlockSparseMatrix ring = ringMatrix(n, 7);
    BlockSparseMatrix A(n, pairs);
    A.setZero();
    for (int i = 0; i < n; ++i) {
        A.add(i, i, ring.block(ring.diagonalSlot(i)));
        if (i + 1 < n) {
            A.add(i, i + 1, ring.block(ring.slot(i, i + 1)));
            A.add(i + 1, i, ring.block(ring.slot(i + 1, i)));
        }
    }
    std::vector<char> held(n, 0);
    held[5] = 1;
    const MatX3 b = randomRhs(n, 8);
    MatX3 x = MatX3::Zero(n, 3);
    sim::FilteredCg ic = solverOf(sim::LinearSolver::BlockIncompleteCholesky);
    const sim::CgResult r = ic.solve(A, b, held, x, 1e-12, 100);
    EXPECT_TRUE(r.converged);
    EXPECT_EQ(r.iterations, 1);
    const Eigen::VectorXd expected = reducedReference(A, b, {}, held, MatX3::Zero(n, 3));
    EXPECT_LT((flat(x) - expected).norm(), 1e-9 * expected.norm());
}

TEST(FilteredCg, IncompleteCholeskyFollowsANewStructure) {
    GroupedProblem p;
    sim::FilteredCg cg = solverOf(sim::LinearSolver::BlockIncompleteCholesky);
    MatX3 x = p.x0;
    ASSERT_TRUE(cg.solve(p.A, p.b, p.held, x, 1e-12, 1000, &p.groups).converged);
    // A seam welds (a new group) and a vertex is released: the factor's structure follows.
    p.groups.push_back({20, 30});
    p.held[4] = 0;
    x = p.x0;
    const sim::CgResult r = cg.solve(p.A, p.b, p.held, x, 1e-12, 1000, &p.groups);
    ASSERT_TRUE(r.converged);
    const Eigen::VectorXd expected = reducedReference(p.A, p.b, p.groups, p.held, p.fixedRows());
    EXPECT_LT((flat(x) - expected).norm(), 1e-9 * expected.norm());
}

/// A with its vertices renumbered: vertex i becomes newIndex[i].
BlockSparseMatrix renumbered(const BlockSparseMatrix& A, const std::vector<int>& newIndex) {
    std::vector<std::pair<int, int>> pairs;
    for (int i = 0; i < A.blockRows(); ++i) {
        for (int s = A.rowStart()[i]; s < A.rowStart()[i + 1]; ++s) {
            if (A.columns()[s] > i) {
                pairs.emplace_back(newIndex[i], newIndex[A.columns()[s]]);
            }
        }
    }
    BlockSparseMatrix B(A.blockRows(), pairs);
    B.setZero();
    for (int i = 0; i < A.blockRows(); ++i) {
        for (int s = A.rowStart()[i]; s < A.rowStart()[i + 1]; ++s) {
            B.add(newIndex[i], newIndex[A.columns()[s]], A.block(s));
        }
    }
    return B;
}

TEST(FilteredCg, ALargeSystemSplitsItsIncompleteFactorInTwoHalvesWithTheSameBitsOnAnyThreads) {
    // A 40×40 sheet numbered row by row: the rows before the middle and after it, and the 40
    // unknowns of row 19, which couple to row 20, as the separator.
    const int m = 40;
    const std::vector<char> free(static_cast<std::size_t>(m * m), 0);
    sim::BlockIncompleteCholesky factor;
    ASSERT_TRUE(factor.factorize(gridMatrix(m, 9, 200.0), free, nullptr));
    EXPECT_EQ(factor.halfUnknowns(0), 19 * m);
    EXPECT_EQ(factor.halfUnknowns(1), 20 * m);
    EXPECT_EQ(factor.separatorUnknowns(), m);
    // Numbered at random (the corner kept first), no cut in vertex order is small: from the
    // corner the breadth-first levels are the rings max(row, column) = k of 2k + 1 unknowns
    // (the diagonal springs reach (r + 1, c + 1) in one step), k² of them before ring k. Half
    // of 1,600 is reached in ring 28: 784 before it, its 57 the separator, 759 after it.
    std::vector<int> newIndex(static_cast<std::size_t>(m * m));
    std::iota(newIndex.begin(), newIndex.end(), 0);
    std::shuffle(newIndex.begin() + 1, newIndex.end(), std::mt19937(11));
    const BlockSparseMatrix A = renumbered(gridMatrix(m, 9, 200.0), newIndex);
    ASSERT_TRUE(factor.factorize(A, free, nullptr));
    EXPECT_EQ(factor.halfUnknowns(0), 784);
    EXPECT_EQ(factor.halfUnknowns(1), 759);
    EXPECT_EQ(factor.separatorUnknowns(), 57);
    const MatX3 b = randomRhs(m * m, 10);
    MatX3 reference = MatX3::Zero(m * m, 3);
    sim::FilteredCg jacobi = solverOf(sim::LinearSolver::BlockJacobi);
    const sim::CgResult rj = jacobi.solve(A, b, free, reference, 1e-12, 5000);
    ASSERT_TRUE(rj.converged);
    std::vector<MatX3> solutions;
    std::vector<int> iterations;
    for (const int threads : {1, 2}) {
        sim::setThreadCount(threads);
        sim::FilteredCg ic = solverOf(sim::LinearSolver::BlockIncompleteCholesky);
        MatX3 x = MatX3::Zero(m * m, 3);
        const sim::CgResult r = ic.solve(A, b, free, x, 1e-12, 5000);
        EXPECT_TRUE(r.converged);
        EXPECT_LT(r.iterations, rj.iterations / 2);
        EXPECT_LT((flat(x) - flat(reference)).norm(), 1e-9 * flat(reference).norm());
        solutions.push_back(x);
        iterations.push_back(r.iterations);
    }
    sim::setThreadCount(0);
    EXPECT_EQ(iterations[0], iterations[1]);
    EXPECT_EQ(solutions[0], solutions[1]) << "the same bits on one thread and on two";

    // Small systems keep the vertex order.
    const GroupedProblem p;
    ASSERT_TRUE(factor.factorize(p.A, p.held, &p.groups));
    EXPECT_EQ(factor.halfUnknowns(0) + factor.halfUnknowns(1), 0);
    EXPECT_EQ(factor.separatorUnknowns(), factor.unknowns());
}

TEST(FilteredCg, ASolveStoppedAtTheCapSaysSo) {
    const GroupedProblem p;
    sim::FilteredCg cg = solverOf(sim::LinearSolver::BlockJacobi);
    MatX3 x = p.x0;
    const sim::CgResult r = cg.solve(p.A, p.b, p.held, x, 1e-12, 3, &p.groups);
    EXPECT_EQ(r.iterations, 3);
    EXPECT_FALSE(r.converged);
    EXPECT_TRUE(r.capped);
    EXPECT_GT(r.relativeResidual, 1e-6);
    x = p.x0;
    const sim::CgResult full = cg.solve(p.A, p.b, p.held, x, 1e-12, 1000, &p.groups);
    EXPECT_TRUE(full.converged);
    EXPECT_FALSE(full.capped);
    EXPECT_LE(full.relativeResidual, 1e-12);
}

} // namespace
} // namespace atelier
