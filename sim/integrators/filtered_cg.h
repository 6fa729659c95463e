#pragma once
/// Preconditioned conjugate gradients with constraint filtering (Baraff & Witkin 1998, §5.3).

#include "sim/core/block_sparse.h"

#include <vector>

namespace atelier::sim {

struct CgResult {
    int iterations = 0;
    double relativeResidual = 0; ///< |S(b - A x)| / |S b|
    bool converged = false;
};

/// Solves S A x = S b for the free vertices, with x held at its initial value on the
/// constrained ones (S = filter: identity on free vertices, zero on constrained).
/// Block-Jacobi preconditioner (inverse of each 3×3 diagonal block). A must be symmetric
/// positive definite on the free subspace. The workspace is reused between calls.
class FilteredCg {
  public:
    CgResult solve(const BlockSparseMatrix& A, const MatX3& b, const std::vector<char>& constrained,
                   MatX3& x, double tolerance, int maxIterations);

  private:
    void filter(MatX3& r, const std::vector<char>& constrained) const;
    MatX3 m_r, m_z, m_p, m_q;
    std::vector<Mat3> m_precond;
};

} // namespace atelier::sim
