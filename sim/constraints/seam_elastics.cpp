#include "sim/constraints/seam_elastics.h"

#include <algorithm>
#include <cmath>

namespace atelier::sim {

namespace {

/// The spring's pull on an extension r: r itself up to the reach L, then L r̂ (constant
/// force beyond it). 0 = no reach (linear everywhere).
Vec3 pulled(const Vec3& r, double reach) {
    const double length = r.norm();
    return reach > 0 && length > reach ? Vec3(reach / length * r) : r;
}

/// Energy of the spring per unit stiffness: r²/2 up to L, then L(|r| − L/2).
double potential(const Vec3& r, double reach) {
    const double length = r.norm();
    return reach > 0 && length > reach ? reach * (length - 0.5 * reach) : 0.5 * r.squaredNorm();
}

/// ∂pulled/∂r: I up to L, then (L/|r|)(I − r̂r̂ᵀ) (symmetric, positive semi-definite).
Mat3 pullDerivative(const Vec3& r, double reach) {
    const double length = r.norm();
    if (!(reach > 0 && length > reach)) {
        return Mat3::Identity();
    }
    const Vec3 u = r / length;
    return reach / length * (Mat3::Identity() - u * u.transpose());
}

} // namespace

SeamElastics::SeamElastics(const std::vector<SeamPair>& pairs, const VecX& masses,
                           double timeConstant, double reach, double stiffnessPerLength)
    : m_pairs(pairs), m_tau(timeConstant), m_reach(reach) {
    m_stiffness.reserve(pairs.size());
    for (const SeamPair& p : pairs) {
        const double ma = masses[p.a];
        const double mb = masses[p.b];
        const double mu = ma + mb > 0 ? ma * mb / (ma + mb) : 0.0;
        m_stiffness.push_back(mu / (timeConstant * timeConstant) +
                              stiffnessPerLength * std::max(0.0, p.length));
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
    for (std::size_t s = 0; s < m_pairs.size(); ++s) {
        const int a = m_pairs[s].a;
        const int b = m_pairs[s].b;
        const double k = m_stiffness[s];
        const double c = 2.0 * m_tau * k;
        if (m_routed[s] != 0) {
            for (const int i : {a, b}) {
                const Vec3 r = x.row(i).transpose() - m_via[s];
                f.row(i) += (-k * pulled(r, m_reach) - c * v.row(i).transpose()).transpose();
            }
            continue;
        }
        const Vec3 r = (x.row(a) - x.row(b)).transpose();
        const Vec3 rv = (v.row(a) - v.row(b)).transpose();
        const Vec3 fa = -k * pulled(r, m_reach) - c * rv;
        f.row(a) += fa.transpose();
        f.row(b) -= fa.transpose();
    }
}

double SeamElastics::energy(const MatX3& x) const {
    double e = 0;
    for (std::size_t s = 0; s < m_pairs.size(); ++s) {
        const double k = m_stiffness[s];
        const int a = m_pairs[s].a;
        const int b = m_pairs[s].b;
        if (m_routed[s] != 0) {
            e += k * (potential(x.row(a).transpose() - m_via[s], m_reach) +
                      potential(x.row(b).transpose() - m_via[s], m_reach));
            continue;
        }
        e += k * potential((x.row(a) - x.row(b)).transpose(), m_reach);
    }
    return e;
}

void SeamElastics::jacobianPattern(std::vector<std::pair<int, int>>& pairs) const {
    for (const SeamPair& p : m_pairs) {
        pairs.emplace_back(p.a, p.b);
    }
}

void SeamElastics::addJacobian(const MatX3& x, const MatX3& /*v*/, double kx, double kv,
                               JacobianMode /*mode*/, BlockSparseMatrix& J) const {
    // The pull's derivative is symmetric positive semi-definite, so the exact Jacobian is
    // already the definite one.
    for (std::size_t s = 0; s < m_pairs.size(); ++s) {
        const double stiffness = kx * m_stiffness[s];
        const Mat3 damping = kv * 2.0 * m_tau * m_stiffness[s] * Mat3::Identity();
        const int a = m_pairs[s].a;
        const int b = m_pairs[s].b;
        if (m_routed[s] != 0) {
            for (const int i : {a, b}) {
                const Vec3 r = x.row(i).transpose() - m_via[s];
                J.add(i, i, -(stiffness * pullDerivative(r, m_reach) + damping));
            }
            continue;
        }
        const Mat3 B =
            stiffness * pullDerivative((x.row(a) - x.row(b)).transpose(), m_reach) + damping;
        J.add(a, a, -B);
        J.add(a, b, B);
        J.add(b, a, B);
        J.add(b, b, -B);
    }
}

} // namespace atelier::sim
