#include "sim/core/block_sparse.h"

#include "sim/core/parallel.h"

#include <algorithm>
#include <atomic>

namespace atelier::sim {

BlockSparseMatrix::BlockSparseMatrix(int blockRows, const std::vector<std::pair<int, int>>& pairs) {
    static std::atomic<std::uint64_t> patterns{0};
    m_patternId = ++patterns;
    const auto n = static_cast<std::size_t>(blockRows);
    std::vector<std::vector<int>> rows(n);
    for (std::size_t i = 0; i < n; ++i) {
        rows[i].push_back(static_cast<int>(i));
    }
    for (const auto& [a, b] : pairs) {
        if (a == b) {
            continue;
        }
        rows[static_cast<std::size_t>(a)].push_back(b);
        rows[static_cast<std::size_t>(b)].push_back(a);
    }
    m_rowStart.assign(n + 1, 0);
    m_diag.assign(n, -1);
    for (std::size_t i = 0; i < n; ++i) {
        auto& r = rows[i];
        std::sort(r.begin(), r.end());
        r.erase(std::unique(r.begin(), r.end()), r.end());
        m_rowStart[i + 1] = m_rowStart[i] + static_cast<int>(r.size());
    }
    m_col.reserve(static_cast<std::size_t>(m_rowStart[n]));
    for (std::size_t i = 0; i < n; ++i) {
        for (int c : rows[i]) {
            if (c == static_cast<int>(i)) {
                m_diag[i] = static_cast<int>(m_col.size());
            }
            m_col.push_back(c);
        }
    }
    m_val.assign(m_col.size(), Mat3::Zero());
}

void BlockSparseMatrix::setZero() {
    std::fill(m_val.begin(), m_val.end(), Mat3::Zero());
}

int BlockSparseMatrix::slot(int i, int j) const {
    const auto begin = m_col.begin() + m_rowStart[static_cast<std::size_t>(i)];
    const auto end = m_col.begin() + m_rowStart[static_cast<std::size_t>(i) + 1];
    const auto it = std::lower_bound(begin, end, j);
    if (it == end || *it != j) {
        return -1;
    }
    return static_cast<int>(it - m_col.begin());
}

void BlockSparseMatrix::addDiagonal(const VecX& diag) {
    for (int i = 0; i < blockRows(); ++i) {
        m_val[static_cast<std::size_t>(m_diag[static_cast<std::size_t>(i)])].diagonal().array() +=
            diag[i];
    }
}

void BlockSparseMatrix::multiply(const MatX3& x, MatX3& y) const {
    const std::int64_t n = blockRows();
    y.resize(n, 3);
    parallelFor(n, [&](std::int64_t i) {
        Vec3 acc = Vec3::Zero();
        for (int k = m_rowStart[static_cast<std::size_t>(i)];
             k < m_rowStart[static_cast<std::size_t>(i) + 1]; ++k) {
            acc.noalias() += m_val[static_cast<std::size_t>(k)] *
                             x.row(m_col[static_cast<std::size_t>(k)]).transpose();
        }
        y.row(i) = acc.transpose();
    });
}

Eigen::MatrixXd BlockSparseMatrix::toDense() const {
    const int n = blockRows();
    Eigen::MatrixXd d = Eigen::MatrixXd::Zero(3 * n, 3 * n);
    for (int i = 0; i < n; ++i) {
        for (int k = m_rowStart[static_cast<std::size_t>(i)];
             k < m_rowStart[static_cast<std::size_t>(i) + 1]; ++k) {
            d.block<3, 3>(3 * i, 3 * m_col[static_cast<std::size_t>(k)]) +=
                m_val[static_cast<std::size_t>(k)];
        }
    }
    return d;
}

} // namespace atelier::sim
