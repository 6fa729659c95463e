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

void FilteredCg::filter(MatX3& r) const {
    for (std::size_t i = 0; i < m_constrained.size(); ++i) {
        if (m_constrained[i] != 0) {
            r.row(static_cast<Eigen::Index>(i)).setZero();
        }
    }
}

void FilteredCg::gather(MatX3& r) const {
    if (m_groups == nullptr) {
        return;
    }
    for (const std::vector<int>& g : *m_groups) {
        for (std::size_t k = 1; k < g.size(); ++k) {
            r.row(g[0]) += r.row(g[k]);
            r.row(g[k]).setZero();
        }
    }
}

void FilteredCg::scatter(MatX3& x) const {
    if (m_groups == nullptr) {
        return;
    }
    for (const std::vector<int>& g : *m_groups) {
        for (std::size_t k = 1; k < g.size(); ++k) {
            x.row(g[k]) = x.row(g[0]);
        }
    }
}

void FilteredCg::buildBlockJacobi(const BlockSparseMatrix& A) {
    const int n = A.blockRows();
    m_precond.resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
        m_precond[static_cast<std::size_t>(i)] = A.block(A.diagonalSlot(i));
    }
    if (m_groups != nullptr) {
        for (const std::vector<int>& g : *m_groups) {
            const std::size_t first = static_cast<std::size_t>(g[0]);
            for (std::size_t k = 1; k < g.size(); ++k) {
                m_precond[first] += m_precond[static_cast<std::size_t>(g[k])];
            }
            for (std::size_t k = 0; k < g.size(); ++k) {
                for (std::size_t l = 0; l < g.size(); ++l) {
                    const int slot = k == l ? -1 : A.slot(g[k], g[l]);
                    if (slot >= 0) {
                        m_precond[first] += A.block(slot);
                    }
                }
            }
        }
    }
    for (int i = 0; i < n; ++i) {
        Eigen::FullPivLU<Mat3> lu(m_precond[static_cast<std::size_t>(i)]);
        m_precond[static_cast<std::size_t>(i)] =
            lu.isInvertible() ? Mat3(lu.inverse()) : Mat3::Identity();
    }
}

CgResult FilteredCg::solve(const BlockSparseMatrix& A, const MatX3& b,
                           const std::vector<char>& constrained, MatX3& x, double tolerance,
                           int maxIterations, const std::vector<std::vector<int>>* groups) {
    const int n = A.blockRows();
    m_groups = groups != nullptr && !groups->empty() ? groups : nullptr;
    m_constrained = constrained;
    if (m_groups != nullptr) {
        for (const std::vector<int>& g : *m_groups) {
            const std::size_t first = static_cast<std::size_t>(g[0]);
            for (std::size_t k = 0; k < g.size(); ++k) {
                if (constrained[static_cast<std::size_t>(g[k])] != 0) {
                    m_constrained[first] = 1;
                    x.row(g[0]) = x.row(g[k]);
                }
            }
        }
        scatter(x);
    }
    CgResult result;
    // No shift gave positive definite pivots: block-Jacobi for this solve.
    const bool incomplete = m_preconditioner == LinearSolver::BlockIncompleteCholesky &&
                            m_incomplete.factorize(A, m_constrained, m_groups);
    if (!incomplete) {
        buildBlockJacobi(A);
    }
    auto precondition = [&](const MatX3& r, MatX3& z) {
        if (incomplete) {
            m_incomplete.apply(r, z);
            return;
        }
        z.resize(r.rows(), 3);
        for (int i = 0; i < n; ++i) {
            z.row(i) = (m_precond[static_cast<std::size_t>(i)] * r.row(i).transpose()).transpose();
        }
    };
    A.multiply(x, m_q);
    m_r = b - m_q;
    gather(m_r);
    filter(m_r);
    m_z = b;
    gather(m_z);
    filter(m_z);
    const double bNorm = std::sqrt(dot(m_z, m_z));
    if (bNorm == 0.0) {
        result.converged = true;
        return result;
    }
    precondition(m_r, m_z); // members' rows of r are zero, so are z's: the reduced space
    filter(m_z);
    m_p = m_z;
    double rz = dot(m_r, m_z);
    bool brokeDown = false;
    for (int it = 0; it < maxIterations; ++it) {
        const double rNorm = std::sqrt(dot(m_r, m_r));
        result.relativeResidual = rNorm / bNorm;
        if (result.relativeResidual <= tolerance) {
            result.converged = true;
            break;
        }
        if (m_groups != nullptr) {
            m_s = m_p;
            scatter(m_s);
            A.multiply(m_s, m_q);
            gather(m_q);
        } else {
            A.multiply(m_p, m_q);
        }
        filter(m_q);
        const double pq = dot(m_p, m_q);
        if (!(pq > 0.0) || !std::isfinite(pq)) {
            brokeDown = true; // not positive definite along p: stop with what we have
            break;
        }
        const double alpha = rz / pq;
        x.noalias() += alpha * m_p;
        m_r.noalias() -= alpha * m_q;
        precondition(m_r, m_z);
        filter(m_z);
        const double rzNew = dot(m_r, m_z);
        m_p = m_z + (rzNew / rz) * m_p;
        rz = rzNew;
        result.iterations = it + 1;
    }
    scatter(x);
    result.relativeResidual = std::sqrt(dot(m_r, m_r)) / bNorm;
    result.converged = result.relativeResidual <= tolerance;
    result.capped = !result.converged && !brokeDown && result.iterations >= maxIterations;
    return result;
}

} // namespace atelier::sim
