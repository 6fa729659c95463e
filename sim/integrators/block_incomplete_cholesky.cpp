#include "sim/integrators/block_incomplete_cholesky.h"

#include "sim/core/parallel.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <array>
#include <climits>
#include <utility>

namespace atelier::sim {

namespace {
constexpr int NOWHERE = INT_MIN;
/// Manteuffel's shifts tried in turn: K's diagonal blocks scaled by 1 + α.
constexpr std::array<double, 5> SHIFTS = {0.0, 1e-3, 1e-2, 1e-1, 1.0};
/// Systems with fewer unknowns keep the vertex order: two threads gain nothing on them.
constexpr int MIN_SPLIT_UNKNOWNS = 1024;
/// A split whose separator would hold more than this share of the unknowns is not made.
constexpr double MAX_SEPARATOR_SHARE = 0.2;
} // namespace

bool BlockIncompleteCholesky::matches(const BlockSparseMatrix& A,
                                      const std::vector<char>& constrained,
                                      const Groups* groups) const {
    static const Groups NO_GROUPS;
    const Groups& g = groups != nullptr ? *groups : NO_GROUPS;
    return m_blockRows == A.blockRows() && m_patternId == A.patternId() &&
           m_constrained == constrained && m_groups == g;
}

void BlockIncompleteCholesky::analyse(const BlockSparseMatrix& A,
                                      const std::vector<char>& constrained, const Groups* groups) {
    const int n = A.blockRows();
    const auto at = [](int i) { return static_cast<std::size_t>(i); };
    m_blockRows = n;
    m_patternId = A.patternId();
    m_constrained = constrained;
    m_groups = groups != nullptr ? *groups : Groups{};
    // Each vertex's unknown: that of its group's first vertex, none when constrained.
    std::vector<int> first(at(n));
    for (int i = 0; i < n; ++i) {
        first[at(i)] = i;
    }
    for (const std::vector<int>& g : m_groups) {
        for (const int v : g) {
            first[at(v)] = g[0];
        }
    }
    std::vector<int> own(at(n), -1);
    m_vertexOfUnknown.clear();
    for (int i = 0; i < n; ++i) {
        if (first[at(i)] == i && constrained[at(i)] == 0) {
            own[at(i)] = static_cast<int>(m_vertexOfUnknown.size());
            m_vertexOfUnknown.push_back(i);
        }
    }
    std::vector<int> unknownOf(at(n));
    for (int i = 0; i < n; ++i) {
        unknownOf[at(i)] = own[at(first[at(i)])];
    }
    order(unknownOf, A);
    const int m = unknowns();
    const std::vector<int>& rowStart = A.rowStart();
    const std::vector<int>& columns = A.columns();
    std::vector<std::pair<int, int>> lower; // (row, column), row > column
    for (int i = 0; i < n; ++i) {
        const int a = unknownOf[at(i)];
        for (int s = rowStart[at(i)]; a >= 0 && s < rowStart[at(i) + 1]; ++s) {
            const int b = unknownOf[at(columns[at(s)])];
            if (b >= 0 && b < a) {
                lower.emplace_back(a, b);
            }
        }
    }
    std::sort(lower.begin(), lower.end());
    lower.erase(std::unique(lower.begin(), lower.end()), lower.end());
    m_rowStart.assign(at(m) + 1, 0);
    m_col.resize(lower.size());
    for (std::size_t k = 0; k < lower.size(); ++k) {
        ++m_rowStart[at(lower[k].first) + 1];
        m_col[k] = lower[k].second;
    }
    for (int a = 0; a < m; ++a) {
        m_rowStart[at(a) + 1] += m_rowStart[at(a)];
    }
    m_target.assign(columns.size(), NOWHERE);
    for (int i = 0; i < n; ++i) {
        const int a = unknownOf[at(i)];
        for (int s = rowStart[at(i)]; a >= 0 && s < rowStart[at(i) + 1]; ++s) {
            const int b = unknownOf[at(columns[at(s)])];
            if (b == a) {
                m_target[at(s)] = -1 - a;
            } else if (b >= 0 && b < a) {
                const auto begin = m_col.begin() + m_rowStart[at(a)];
                const auto end = m_col.begin() + m_rowStart[at(a) + 1];
                m_target[at(s)] = static_cast<int>(std::lower_bound(begin, end, b) - m_col.begin());
            }
        }
    }
    m_kLower.resize(m_col.size());
    m_l.resize(m_col.size());
    m_w.resize(m_col.size());
    m_kDiagonal.resize(at(m));
    m_d.resize(at(m));
    m_dInverse.resize(at(m));
    m_mark.assign(at(m), -1);
}

void BlockIncompleteCholesky::order(std::vector<int>& unknownOf, const BlockSparseMatrix& A) {
    const int m = unknowns();
    const auto at = [](int i) { return static_cast<std::size_t>(i); };
    m_halfEnd[0] = 0;
    m_halfEnd[1] = 0;
    m_halfEnd[2] = 0;
    if (m < MIN_SPLIT_UNKNOWNS) {
        return;
    }
    // Breadth-first levels from the first unknown (each further component from its first
    // unknown, a level further on): unknowns couple only within a level and to the next, so
    // the level where half the unknowns are reached separates those before it from those
    // after it (on a garment, a ring of a few percent of the unknowns).
    const std::vector<int>& rowStart = A.rowStart();
    const std::vector<int>& columns = A.columns();
    std::vector<std::vector<int>> neighbours(at(m));
    for (int i = 0; i < A.blockRows(); ++i) {
        const int a = unknownOf[at(i)];
        for (int s = rowStart[at(i)]; a >= 0 && s < rowStart[at(i) + 1]; ++s) {
            const int b = unknownOf[at(columns[at(s)])];
            if (b >= 0 && b != a) {
                neighbours[at(a)].push_back(b);
            }
        }
    }
    std::vector<int> level(at(m), -1);
    std::vector<int> queue;
    queue.reserve(at(m));
    int deepest = -1;
    for (int start = 0; start < m; ++start) {
        if (level[at(start)] >= 0) {
            continue;
        }
        level[at(start)] = deepest + 1;
        queue.push_back(start);
        for (std::size_t q = queue.size() - 1; q < queue.size(); ++q) {
            const int a = queue[q];
            deepest = std::max(deepest, level[at(a)]);
            for (const int b : neighbours[at(a)]) {
                if (level[at(b)] < 0) {
                    level[at(b)] = level[at(a)] + 1;
                    queue.push_back(b);
                }
            }
        }
    }
    std::vector<int> perLevel(at(deepest) + 1, 0);
    for (const int l : level) {
        ++perLevel[at(l)];
    }
    int cut = 0;
    for (int reached = 0; cut <= deepest && reached + perLevel[at(cut)] <= m / 2; ++cut) {
        reached += perLevel[at(cut)];
    }
    std::vector<char> part(at(m));
    for (int a = 0; a < m; ++a) {
        part[at(a)] = level[at(a)] < cut ? 0 : (level[at(a)] > cut ? 1 : 2);
    }
    // Vertex order cut in the middle, the first half's unknowns that couple to the second as
    // the separator: smaller on a sheet meshed row by row (one row), and closer to the
    // vertex order, which IC(0) converges best in. The smaller separator is taken.
    std::vector<char> halves(at(m));
    for (int a = 0; a < m; ++a) {
        halves[at(a)] = a < m / 2 ? 0 : 1;
        for (const int b : neighbours[at(a)]) {
            if (a < m / 2 && b >= m / 2) {
                halves[at(a)] = 2;
            }
        }
    }
    if (std::count(halves.begin(), halves.end(), 2) < perLevel[at(std::min(cut, deepest))]) {
        part = std::move(halves);
    }
    if (std::count(part.begin(), part.end(), 2) > MAX_SEPARATOR_SHARE * m) {
        return;
    }
    std::vector<int> position(at(m));
    std::vector<int> vertexOf(at(m));
    int next = 0;
    for (int p = 0; p < 3; ++p) {
        for (int a = 0; a < m; ++a) {
            if (part[at(a)] == p) {
                position[at(a)] = next;
                vertexOf[at(next)] = m_vertexOfUnknown[at(a)];
                ++next;
            }
        }
        if (p < 2) {
            m_halfEnd[p + 1] = next;
        }
    }
    m_vertexOfUnknown = std::move(vertexOf);
    for (int& u : unknownOf) {
        u = u >= 0 ? position[at(u)] : u;
    }
}

bool BlockIncompleteCholesky::factorize(const BlockSparseMatrix& A,
                                        const std::vector<char>& constrained,
                                        const Groups* groups) {
    if (!matches(A, constrained, groups)) {
        analyse(A, constrained, groups);
    }
    std::fill(m_kLower.begin(), m_kLower.end(), Mat3::Zero());
    std::fill(m_kDiagonal.begin(), m_kDiagonal.end(), Mat3::Zero());
    // K = S Pᵀ A P S: every block of A adds into the block of its rows' and columns' unknowns
    // (the lower triangle from the lower blocks of A, their transposes being the upper).
    for (int s = 0; s < A.nonZeroBlocks(); ++s) {
        const int t = m_target[static_cast<std::size_t>(s)];
        if (t >= 0) {
            m_kLower[static_cast<std::size_t>(t)] += A.block(s);
        } else if (t != NOWHERE) {
            m_kDiagonal[static_cast<std::size_t>(-1 - t)] += A.block(s);
        }
    }
    m_valid = false;
    for (const double alpha : SHIFTS) {
        if (factorizeShifted(alpha)) {
            m_shift = alpha;
            m_valid = true;
            break;
        }
    }
    return m_valid;
}

bool BlockIncompleteCholesky::factorizeShifted(double alpha) {
    // The halves' rows use only their own half's rows: both at once, then the separator.
    std::array<char, 2> ok = {1, 1};
    parallelForEach(2, m_halfEnd[2] > 0, [&](std::int64_t h) {
        ok[static_cast<std::size_t>(h)] =
            factorizeRows(m_halfEnd[h], m_halfEnd[h + 1], alpha) ? 1 : 0;
    });
    return ok[0] != 0 && ok[1] != 0 && factorizeRows(m_halfEnd[2], unknowns(), alpha);
}

bool BlockIncompleteCholesky::factorizeRows(int rowBegin, int rowEnd, double alpha) {
    for (int a = rowBegin; a < rowEnd; ++a) {
        const int begin = m_rowStart[static_cast<std::size_t>(a)];
        const int end = m_rowStart[static_cast<std::size_t>(a) + 1];
        for (int s = begin; s < end; ++s) {
            m_mark[static_cast<std::size_t>(m_col[static_cast<std::size_t>(s)])] = s;
        }
        Mat3 pivot = (1.0 + alpha) * m_kDiagonal[static_cast<std::size_t>(a)];
        for (int s = begin; s < end; ++s) {
            // L_ab D_b = K_ab − Σ_{c < b} L_ac D_c L_bcᵀ over the c in both rows' patterns.
            const int b = m_col[static_cast<std::size_t>(s)];
            Mat3 w = m_kLower[static_cast<std::size_t>(s)];
            for (int t = m_rowStart[static_cast<std::size_t>(b)];
                 t < m_rowStart[static_cast<std::size_t>(b) + 1]; ++t) {
                const int mark =
                    m_mark[static_cast<std::size_t>(m_col[static_cast<std::size_t>(t)])];
                if (mark >= 0) {
                    w.noalias() -= m_w[static_cast<std::size_t>(mark)] *
                                   m_l[static_cast<std::size_t>(t)].transpose();
                }
            }
            m_w[static_cast<std::size_t>(s)] = w;
            m_l[static_cast<std::size_t>(s)] = w * m_dInverse[static_cast<std::size_t>(b)];
            pivot.noalias() -= w * m_l[static_cast<std::size_t>(s)].transpose();
        }
        for (int s = begin; s < end; ++s) {
            m_mark[static_cast<std::size_t>(m_col[static_cast<std::size_t>(s)])] = -1;
        }
        pivot = 0.5 * (pivot + pivot.transpose()).eval();
        const Eigen::LLT<Mat3> llt(pivot);
        if (llt.info() != Eigen::Success || !pivot.allFinite()) {
            return false;
        }
        m_d[static_cast<std::size_t>(a)] = pivot;
        m_dInverse[static_cast<std::size_t>(a)] = llt.solve(Mat3::Identity());
    }
    return true;
}

void BlockIncompleteCholesky::forwardRows(int begin, int end) const {
    // L y = r on rows [begin, end).
    for (int a = begin; a < end; ++a) {
        Vec3 y = m_y.row(a).transpose();
        for (int s = m_rowStart[static_cast<std::size_t>(a)];
             s < m_rowStart[static_cast<std::size_t>(a) + 1]; ++s) {
            y.noalias() -= m_l[static_cast<std::size_t>(s)] *
                           m_y.row(m_col[static_cast<std::size_t>(s)]).transpose();
        }
        m_y.row(a) = y.transpose();
    }
}

void BlockIncompleteCholesky::backwardRows(int begin, int end) const {
    // Lᵀ x = y by columns of Lᵀ (rows of L), last first, on rows [begin, end).
    for (int a = end - 1; a >= begin; --a) {
        const Vec3 x = m_y.row(a).transpose();
        for (int s = m_rowStart[static_cast<std::size_t>(a)];
             s < m_rowStart[static_cast<std::size_t>(a) + 1]; ++s) {
            m_y.row(m_col[static_cast<std::size_t>(s)]) -=
                (m_l[static_cast<std::size_t>(s)].transpose() * x).transpose();
        }
    }
}

void BlockIncompleteCholesky::apply(const MatX3& r, MatX3& z) const {
    const int m = unknowns();
    m_y.resize(m, 3);
    for (int a = 0; a < m; ++a) {
        m_y.row(a) = r.row(m_vertexOfUnknown[static_cast<std::size_t>(a)]);
    }
    // L y = r (the halves at once, then the separator), then D, then Lᵀ x = y (the
    // separator, whose columns reach into both halves, then the halves at once).
    const bool split = m_halfEnd[2] > 0;
    parallelForEach(2, split, [&](std::int64_t h) { forwardRows(m_halfEnd[h], m_halfEnd[h + 1]); });
    forwardRows(m_halfEnd[2], m);
    for (int a = 0; a < m; ++a) {
        m_y.row(a) = (m_dInverse[static_cast<std::size_t>(a)] * m_y.row(a).transpose()).transpose();
    }
    backwardRows(m_halfEnd[2], m);
    parallelForEach(2, split,
                    [&](std::int64_t h) { backwardRows(m_halfEnd[h], m_halfEnd[h + 1]); });
    z.setZero(r.rows(), 3);
    for (int a = 0; a < m; ++a) {
        z.row(m_vertexOfUnknown[static_cast<std::size_t>(a)]) = m_y.row(a);
    }
}

} // namespace atelier::sim
