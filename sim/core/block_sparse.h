#pragma once
/// Sparse matrix of 3×3 blocks with a fixed pattern, for Jacobians of per-vertex forces.

#include "sim/core/types.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace atelier::sim {

/// Square block-CSR matrix: (3|V| × 3|V|) stored as |V| block rows of 3×3 blocks.
/// The pattern is fixed at construction (symmetric: (i,j) present iff (j,i) is) and always
/// holds the diagonal; values are set with `setZero()` and accumulated with `add()`.
class BlockSparseMatrix {
  public:
    BlockSparseMatrix() = default;
    /// Builds the pattern from vertex pairs (i ≠ j, either order, duplicates allowed).
    BlockSparseMatrix(int blockRows, const std::vector<std::pair<int, int>>& pairs);

    int blockRows() const { return static_cast<int>(m_rowStart.size()) - 1; }
    int nonZeroBlocks() const { return static_cast<int>(m_col.size()); }

    void setZero();
    /// Index of block (i, j) in the value array, or -1 when not in the pattern.
    int slot(int i, int j) const;
    /// Adds `b` to block (i, j). The block must be in the pattern.
    void add(int i, int j, const Mat3& b) { m_val[static_cast<std::size_t>(slot(i, j))] += b; }
    void addAt(int slotIndex, const Mat3& b) { m_val[static_cast<std::size_t>(slotIndex)] += b; }
    /// Adds s·I to every diagonal block i with the per-row scale `diag(i)`.
    void addDiagonal(const VecX& diag);
    Mat3& block(int slotIndex) { return m_val[static_cast<std::size_t>(slotIndex)]; }
    const Mat3& block(int slotIndex) const { return m_val[static_cast<std::size_t>(slotIndex)]; }
    int diagonalSlot(int i) const { return m_diag[static_cast<std::size_t>(i)]; }

    /// y = A·x, both (|V|×3).
    void multiply(const MatX3& x, MatX3& y) const;
    /// Dense copy for tests and small problems.
    Eigen::MatrixXd toDense() const;

    const std::vector<int>& rowStart() const { return m_rowStart; }
    /// Identifies the pattern: equal for a matrix and its copies, different for every matrix
    /// built from pairs (0: the empty default). Lets callers cache slot indices.
    std::uint64_t patternId() const { return m_patternId; }
    const std::vector<int>& columns() const { return m_col; }

  private:
    std::vector<int> m_rowStart{0};
    std::vector<int> m_col;
    std::vector<int> m_diag;
    std::vector<Mat3> m_val;
    std::uint64_t m_patternId = 0;
};

} // namespace atelier::sim
