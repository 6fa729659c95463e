#include "sim/constraints/seam_elastics.h"

namespace atelier::sim {

SeamElastics::SeamElastics(const std::vector<SeamPair>& pairs, const VecX& masses,
                           double timeConstant)
    : m_pairs(pairs), m_tau(timeConstant) {
    m_reducedMass.reserve(pairs.size());
    for (const SeamPair& p : pairs) {
        const double ma = masses[p.a];
        const double mb = masses[p.b];
        m_reducedMass.push_back(ma + mb > 0 ? ma * mb / (ma + mb) : 0.0);
    }
    m_via.assign(pairs.size(), Vec3::Zero());
    m_routed.assign(pairs.size(), 0);
}

void SeamElastics::setVia(std::size_t s, const Vec3* via) {
    m_routed[s] = via != nullptr ? 1 : 0;
    if (via != nullptr) {
        m_via[s] = *via;
    }
}

void SeamElastics::addForces(const MatX3& x, const MatX3& v, MatX3& f) const {
    const double k = 1.0 / (m_tau * m_tau);
    const double c = 2.0 / m_tau;
    for (std::size_t s = 0; s < m_pairs.size(); ++s) {
        const int a = m_pairs[s].a;
        const int b = m_pairs[s].b;
        const double mu = m_reducedMass[s];
        if (m_routed[s] != 0) {
            const Eigen::RowVector3d via = m_via[s].transpose();
            f.row(a) += mu * (-k * (x.row(a) - via) - c * v.row(a));
            f.row(b) += mu * (-k * (x.row(b) - via) - c * v.row(b));
            continue;
        }
        const Vec3 fa = mu * (-k * (x.row(a) - x.row(b)) - c * (v.row(a) - v.row(b))).transpose();
        f.row(a) += fa.transpose();
        f.row(b) -= fa.transpose();
    }
}

double SeamElastics::energy(const MatX3& x) const {
    double e = 0;
    for (std::size_t s = 0; s < m_pairs.size(); ++s) {
        const double k = 0.5 * m_reducedMass[s] / (m_tau * m_tau);
        if (m_routed[s] != 0) {
            const Eigen::RowVector3d via = m_via[s].transpose();
            e += k * ((x.row(m_pairs[s].a) - via).squaredNorm() +
                      (x.row(m_pairs[s].b) - via).squaredNorm());
            continue;
        }
        e += k * (x.row(m_pairs[s].a) - x.row(m_pairs[s].b)).squaredNorm();
    }
    return e;
}

void SeamElastics::jacobianPattern(std::vector<std::pair<int, int>>& pairs) const {
    for (const SeamPair& p : m_pairs) {
        pairs.emplace_back(p.a, p.b);
    }
}

void SeamElastics::addJacobian(const MatX3& /*x*/, const MatX3& /*v*/, double kx, double kv,
                               JacobianMode /*mode*/, BlockSparseMatrix& J) const {
    for (std::size_t s = 0; s < m_pairs.size(); ++s) {
        const double mu = m_reducedMass[s];
        const double d = kx * mu / (m_tau * m_tau) + kv * 2.0 * mu / m_tau;
        const Mat3 B = d * Mat3::Identity();
        const int a = m_pairs[s].a;
        const int b = m_pairs[s].b;
        J.add(a, a, -B);
        J.add(b, b, -B);
        if (m_routed[s] == 0) {
            J.add(a, b, B);
            J.add(b, a, B);
        }
    }
}

} // namespace atelier::sim
