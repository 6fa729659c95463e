#include "sim/integrators/filtered_cg.h"

#include "sim/core/parallel.h"

#include <Eigen/Dense>

#include <cmath>

namespace atelier::sim {

namespace {
double dot(const MatX3& a, const MatX3& b) {
    return (a.array() * b.array()).sum();
}
} // namespace

void FilteredCg::filter(MatX3& r, const std::vector<char>& constrained) const {
    for (std::size_t i = 0; i < constrained.size(); ++i) {
        if (constrained[i] != 0) {
            r.row(static_cast<Eigen::Index>(i)).setZero();
        }
    }
}

CgResult FilteredCg::solve(const BlockSparseMatrix& A, const MatX3& b,
                           const std::vector<char>& constrained, MatX3& x, double tolerance,
                           int maxIterations) {
    const int n = A.blockRows();
    m_precond.resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        const Mat3& d = A.block(A.diagonalSlot(i));
        Eigen::FullPivLU<Mat3> lu(d);
        m_precond[static_cast<std::size_t>(i)] =
            lu.isInvertible() ? Mat3(lu.inverse()) : Mat3::Identity();
    }
    auto precondition = [&](const MatX3& r, MatX3& z) {
        z.resize(r.rows(), 3);
        for (int i = 0; i < n; ++i) {
            z.row(i) = (m_precond[static_cast<std::size_t>(i)] * r.row(i).transpose()).transpose();
        }
    };
    CgResult result;
    A.multiply(x, m_q);
    m_r = b - m_q;
    filter(m_r, constrained);
    m_z = b;
    filter(m_z, constrained);
    const double bNorm = std::sqrt(dot(m_z, m_z));
    if (bNorm == 0.0) {
        result.converged = true;
        return result;
    }
    precondition(m_r, m_z);
    filter(m_z, constrained);
    m_p = m_z;
    double rz = dot(m_r, m_z);
    for (int it = 0; it < maxIterations; ++it) {
        const double rNorm = std::sqrt(dot(m_r, m_r));
        result.relativeResidual = rNorm / bNorm;
        if (result.relativeResidual <= tolerance) {
            result.converged = true;
            return result;
        }
        A.multiply(m_p, m_q);
        filter(m_q, constrained);
        const double pq = dot(m_p, m_q);
        if (!(pq > 0.0) || !std::isfinite(pq)) {
            break; // not positive definite along p: stop with what we have
        }
        const double alpha = rz / pq;
        x.noalias() += alpha * m_p;
        m_r.noalias() -= alpha * m_q;
        precondition(m_r, m_z);
        filter(m_z, constrained);
        const double rzNew = dot(m_r, m_z);
        m_p = m_z + (rzNew / rz) * m_p;
        rz = rzNew;
        result.iterations = it + 1;
    }
    result.relativeResidual = std::sqrt(dot(m_r, m_r)) / bNorm;
    result.converged = result.relativeResidual <= tolerance;
    return result;
}

} // namespace atelier::sim
