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
/// of a vertex kept whole. The unknowns are ordered in two halves and a separator between
/// them, moved last: the breadth-first level of the mesh graph (from the first unknown) where
/// half of them are reached, or, when smaller, the unknowns of the first half in vertex order
/// that couple to the second. The halves do not couple, so they factorise and solve at the
/// same time on two threads, then the separator: the triangular solves use both cores, with
/// the same bits for any thread count, and nothing is dropped (IC(0) of the reordered K;
/// within a part, vertex order). Systems under 1,024 unknowns, or whose separator would hold
/// over a fifth of them, keep the vertex order. A pivot block that is not positive
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
    /// Unknowns of the two halves solved at the same time (0 when not split) and of the
    /// separator solved after them.
    int halfUnknowns(int half) const { return m_halfEnd[half + 1] - m_halfEnd[half]; }
    int separatorUnknowns() const { return unknowns() - m_halfEnd[2]; }
    double shift() const { return m_shift; } ///< α of the last factorisation [-]

  private:
    void analyse(const BlockSparseMatrix& A, const std::vector<char>& constrained,
                 const Groups* groups);
    bool factorizeShifted(double alpha);
    bool factorizeRows(int begin, int end, double alpha);
    void forwardRows(int begin, int end) const;
    void backwardRows(int begin, int end) const;
    /// Orders the unknowns (vertex order, or the two halves and their separator), renumbers
    /// unknownOf to match and sets m_halfEnd.
    void order(std::vector<int>& unknownOf, const BlockSparseMatrix& A);

    // Structure key.
    std::uint64_t m_patternId = 0;
    int m_blockRows = -1;
    std::vector<char> m_constrained;
    Groups m_groups;

    std::vector<int> m_vertexOfUnknown; ///< per unknown: its vertex (a group's first)
    /// Unknowns [0, m_halfEnd[1]) and [m_halfEnd[1], m_halfEnd[2]) do not couple; the
    /// separator [m_halfEnd[2], unknowns()) follows them.
    int m_halfEnd[3] = {0, 0, 0};
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
