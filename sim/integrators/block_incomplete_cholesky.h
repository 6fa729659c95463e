#pragma once
/// Block incomplete LDLᵀ factorisation, IC(0) on 3×3 blocks, of the filtered, reduced
/// implicit-Euler system: the conjugate-gradient preconditioner of the implicit solve.

#include "sim/core/block_sparse.h"

#include <cstdint>
#include <vector>

namespace atelier::sim {

/// \f$ K \approx L D L^T \f$ for \f$ K = S P^T A P S \f$, the system `FilteredCg` solves (P
/// merges each vertex group, a welded seam, into one unknown; S drops constrained unknowns),
/// with L unit lower block-triangular on K's own block pattern (no fill) and D block diagonal
/// (3×3 symmetric positive definite blocks): Meijerink & van der Vorst's IC(0) with the blocks
/// of a vertex kept whole. Unknowns in vertex order. A pivot block that is not positive
/// definite (IC(0) exists for M-matrices, not for every SPD matrix) restarts the factorisation
/// with K's diagonal blocks scaled by 1 + α, α = 10⁻³, 10⁻², ..., 1 (Manteuffel's shift).
/// The structure (unknowns and pattern) is kept while the pattern of A, the groups and the
/// constrained vertices stay the same.
class BlockIncompleteCholesky {
  public:
    using Groups = std::vector<std::vector<int>>;

    /// Whether the structure was built for this pattern, these groups and constrained
    /// vertices. `constrained` is per vertex; a group counts as constrained when its first
    /// vertex is marked.
    bool matches(const BlockSparseMatrix& A, const std::vector<char>& constrained,
                 const Groups* groups) const;
    /// Factorises K for A; returns false (and `valid()` false) when no shift gave positive
    /// definite pivots, or K is not finite.
    bool factorize(const BlockSparseMatrix& A, const std::vector<char>& constrained,
                   const Groups* groups);
    bool valid() const { return m_valid; }
    /// z = P S (L D Lᵀ)⁻¹ S Pᵀ r on the first vertex of each group and on every ungrouped
    /// free vertex, 0 on the other rows. `r` holds the reduced residual: rows of the members
    /// other than the first are ignored. Requires `valid()`.
    void apply(const MatX3& r, MatX3& z) const;

    int unknowns() const { return static_cast<int>(m_vertexOfUnknown.size()); }
    double shift() const { return m_shift; } ///< α of the last factorisation [-]

  private:
    void analyse(const BlockSparseMatrix& A, const std::vector<char>& constrained,
                 const Groups* groups);
    bool factorizeShifted(double alpha);

    // Structure key.
    std::uint64_t m_patternId = 0;
    int m_blockRows = -1;
    std::vector<char> m_constrained;
    Groups m_groups;

    std::vector<int> m_vertexOfUnknown; ///< per unknown: its vertex (a group's first)
    /// Strictly lower block pattern of K by rows: row a's columns (ascending, < a) are
    /// m_col[m_rowStart[a] .. m_rowStart[a + 1]).
    std::vector<int> m_rowStart;
    std::vector<int> m_col;
    /// Per block slot of A: where it adds into K: ≥ 0 a lower block (index into m_col),
    /// −1 − a the diagonal block of unknown a, INT_MIN nowhere (upper, or constrained).
    std::vector<int> m_target;
    std::vector<Mat3> m_kLower, m_kDiagonal; ///< K's values
    std::vector<Mat3> m_l;                   ///< L's strictly lower blocks (pattern m_col)
    std::vector<Mat3> m_w;                   ///< L_ab D_b, kept for the updates
    std::vector<Mat3> m_dInverse;            ///< D⁻¹ per unknown
    std::vector<Mat3> m_d;                   ///< D per unknown
    std::vector<int> m_mark;                 ///< factorisation workspace, per unknown
    double m_shift = 0;
    bool m_valid = false;
    mutable MatX3 m_y;
};

} // namespace atelier::sim
