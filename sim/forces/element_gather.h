#pragma once
/// Race-free, deterministic scatter of per-element results (forces, Jacobian blocks) to
/// vertices: elements write into their own slots of a buffer in one parallel loop, then each
/// vertex sums its slots in a fixed order in a second parallel loop.

#include "sim/core/block_sparse.h"
#include "sim/core/types.h"

#include <utility>
#include <vector>

namespace atelier::sim {

/// Vertex → (element, corner) incidence of a set of k-vertex elements (triangles k = 3,
/// hinges k = 4, springs k = 2), stored as CSR, and the gathers built on it.
///
/// Buffer layouts:
/// - forces: (|F|·k × 3), row `e·k + a` = force on corner a of element e [N];
/// - Jacobian blocks: (|F|·k·k) 3×3 blocks, index `(e·k + a)·k + b` = ∂f_a/∂x_b of element e.
class ElementGather {
  public:
    ElementGather() = default;
    /// `elements` (|F|×k): local vertex indices of each element (entries < 0 are skipped);
    /// `offset`: global index of local vertex 0.
    ElementGather(const Eigen::MatrixXi& elements, int offset);

    int elementCount() const { return m_elementCount; }
    int cornerCount() const { return m_k; }
    /// Number of local vertices (1 + largest index in `elements`).
    int vertexCount() const { return static_cast<int>(m_start.size()) - 1; }
    int offset() const { return m_offset; }
    /// Global index of corner a of element e.
    int globalVertex(int e, int a) const {
        return m_offset + m_elements[static_cast<std::size_t>(e * m_k + a)];
    }

    /// f.row(offset + v) += Σ over the incidences (e, a) of v of buffer.row(e·k + a).
    /// `buffer` (|F|·k × 3), `f` (|V_global|×3).
    void gather(const MatX3& buffer, MatX3& f) const;

    /// J(i, j) += Σ blocks of every element holding both i and j; `blocks` (|F|·k·k), see the
    /// class comment. Parallel over block rows (each thread writes only its rows). J's pattern
    /// must hold `addPattern`'s pairs.
    void gatherJacobian(const std::vector<Mat3>& blocks, BlockSparseMatrix& J) const;

    /// Appends every pair of distinct global vertices that share an element.
    void addPattern(std::vector<std::pair<int, int>>& pairs) const;

  private:
    int m_offset = 0;
    int m_k = 0;
    int m_elementCount = 0;
    std::vector<int> m_elements;  ///< (|F|·k) local indices, row-major copy of `elements`
    std::vector<int> m_start;     ///< (|V|+1) CSR row starts
    std::vector<int> m_incidence; ///< e·k + a for each incidence, sorted by vertex then e, a
    /// Slot in J of each (incidence, corner b), for the pattern `m_slotsFor` (found once: the
    /// lookups were a fifth of a garment drape's time).
    mutable std::vector<int> m_slots;
    mutable std::uint64_t m_slotsFor = 0;
};

} // namespace atelier::sim
