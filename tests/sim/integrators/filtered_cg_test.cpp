// Filtered CG: the plain solve against a dense one, constrained vertices held, and merged
// vertex groups (welded seams) solved as the reduced system P^T A P y = P^T b.

#include "sim/integrators/filtered_cg.h"

#include <Eigen/Dense>
#include <gtest/gtest.h>

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

TEST(FilteredCg, SolvesTheDenseSystem) {
    const int n = 12;
    const BlockSparseMatrix A = ringMatrix(n, 1);
    const MatX3 b = randomRhs(n, 2);
    MatX3 x = MatX3::Zero(n, 3);
    sim::FilteredCg cg;
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
    sim::FilteredCg cg;
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

} // namespace
} // namespace atelier
