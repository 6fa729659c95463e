#pragma once
/// Preconditioned conjugate gradients with constraint filtering (Baraff & Witkin 1998, §5.3).

#include "sim/core/block_sparse.h"
#include "sim/integrators/block_incomplete_cholesky.h"
#include "sim/integrators/linear_solver.h"

#include <vector>

namespace atelier::sim {

struct CgResult {
    int iterations = 0;
    double relativeResidual = 0; ///< |S(b - A x)| / |S b|
    bool converged = false;
    /// Stopped at the iteration cap above the tolerance (a breakdown, A not positive definite
    /// along a direction, ends unconverged without it).
    bool capped = false;
};

/// Solves S A x = S b for the free vertices, with x held at its initial value on the
/// constrained ones (S = filter: identity on free vertices, zero on constrained).
/// A must be symmetric positive definite on the free subspace. The workspace (and the
/// incomplete factorisation's structure) is reused between calls.
///
/// Merged vertices (welded seams): with `groups`, the vertices of each group share one
/// unknown, x_i = x_g for every member i. The solve is then the reduced system
/// \f$ P^T A P\,y = P^T b \f$ (P copies a group's unknown to its members), assembled on the
/// fly: members' residuals are summed into the group's first vertex, its block-Jacobi block
/// is the sum of the group's blocks. A group with a constrained member is constrained to that
/// member's value.
class FilteredCg {
  public:
    FilteredCg() = default;
    explicit FilteredCg(LinearSolver preconditioner) : m_preconditioner(preconditioner) {}

    CgResult solve(const BlockSparseMatrix& A, const MatX3& b, const std::vector<char>& constrained,
                   MatX3& x, double tolerance, int maxIterations,
                   const std::vector<std::vector<int>>* groups = nullptr);

    LinearSolver preconditioner() const { return m_preconditioner; }
    void setPreconditioner(LinearSolver preconditioner) { m_preconditioner = preconditioner; }

  private:
    void filter(MatX3& r) const;
    /// P^T: members' rows summed into their group's first vertex, then zeroed.
    void gather(MatX3& r) const;
    /// P: the group's first vertex copied to its members.
    void scatter(MatX3& x) const;
    void buildBlockJacobi(const BlockSparseMatrix& A);
    LinearSolver m_preconditioner = LinearSolver::BlockJacobi;
    const std::vector<std::vector<int>>* m_groups = nullptr;
    std::vector<char> m_constrained; ///< per vertex, with groups: the group's first vertex
    MatX3 m_r, m_z, m_p, m_q, m_s;
    std::vector<Mat3> m_precond;
    BlockIncompleteCholesky m_incomplete;
};

} // namespace atelier::sim
