#include "sim/collision/contact_forces.h"

#include <algorithm>
#include <cmath>

namespace atelier::sim {

void ContactForces::prepare(const std::vector<Contact>& contacts, const MatX3& x, const MatX3& v,
                            const VecX& invMass, double hNominal,
                            const ContactSolveOptions& options) {
    m_terms.clear();
    if (!(hNominal > 0)) {
        return;
    }
    for (const Contact& c : contacts) {
        if (c.obstacle < 0 && !options.selfContacts) {
            continue;
        }
        double w = 0; // Σ w_k² / m_k: inverse of the contact's effective mass
        Vec3 r = -c.obstaclePoint;
        Vec3 u = -c.obstacleVelocity;
        for (int k = 0; k < 4; ++k) {
            const int i = c.vertex[k];
            if (i >= 0) {
                w += c.weight[k] * c.weight[k] * invMass[i];
                r += c.weight[k] * x.row(i).transpose();
                u += c.weight[k] * v.row(i).transpose();
            }
        }
        if (!(w > 0)) {
            continue;
        }
        const double target = c.distance * (1.0 + options.margin);
        // Deeper than the distance is the corrections' business (they move positions without
        // adding velocity); the spring's force is at most κ·margin·d.
        const double gap = std::max(c.normal.dot(r), c.distance);
        // The layer is where the obstacle is at the step's start: moving it with the obstacle
        // over the step (+ h n·q̇) pumped cloth outwards on a spinning faceted sphere (4% of
        // strain in 2 s, measured); the corrections after the step follow the obstacle.
        const double depth = target - gap;
        if (!(depth > 0)) {
            continue;
        }
        Term t;
        for (int k = 0; k < 4; ++k) {
            t.vertex[k] = c.vertex[k];
            t.weight[k] = c.weight[k];
        }
        t.normal = c.normal;
        t.stiffness = options.stiffness / (w * hNominal * hNominal);
        const double lambda = t.stiffness * depth;
        const Vec3 slip = u - c.normal.dot(u) * c.normal;
        const double speed = slip.norm();
        const double mu = speed < options.slipSpeed ? c.staticFriction : c.kineticFriction;
        t.damping = mu * lambda / std::max(speed, options.slipSpeed);
        t.force = lambda * c.normal - t.damping * slip;
        t.obstacleVelocity = c.obstacleVelocity;
        m_terms.push_back(t);
    }
}

void ContactForces::addForces(MatX3& f) const {
    for (const Term& t : m_terms) {
        for (int k = 0; k < 4; ++k) {
            if (t.vertex[k] >= 0) {
                f.row(t.vertex[k]) += (t.weight[k] * t.force).transpose();
            }
        }
    }
}

double ContactForces::obstaclePower() const {
    double p = 0;
    for (const Term& t : m_terms) {
        p += t.force.dot(t.obstacleVelocity);
    }
    return p;
}

double ContactForces::potential() const {
    double e = 0;
    for (const Term& t : m_terms) {
        const double lambda = t.force.dot(t.normal);
        e += 0.5 * lambda * lambda / t.stiffness;
    }
    return e;
}

void ContactForces::addJacobian(double kx, double kv, BlockSparseMatrix& J) const {
    for (const Term& t : m_terms) {
        const Mat3 nn = t.normal * t.normal.transpose();
        const Mat3 block = -kx * t.stiffness * nn - kv * t.damping * (Mat3::Identity() - nn);
        for (int a = 0; a < 4; ++a) {
            if (t.vertex[a] < 0) {
                continue;
            }
            for (int b = 0; b < 4; ++b) {
                // Only pairs on the same side of the contact (cloth–cloth weights are negative on
                // the far side): each side is a vertex, an edge or a triangle, whose blocks are
                // all in the pattern, so what is kept is negative semi-definite.
                if (t.vertex[b] < 0 || (t.weight[a] < 0) != (t.weight[b] < 0)) {
                    continue;
                }
                const int slot = J.slot(t.vertex[a], t.vertex[b]);
                if (slot >= 0) {
                    J.addAt(slot, (t.weight[a] * t.weight[b]) * block);
                }
            }
        }
    }
}

void ContactForces::addJacobianProduct(double kx, double kv, const MatX3& p, MatX3& out) const {
    for (const Term& t : m_terms) {
        const Mat3 nn = t.normal * t.normal.transpose();
        const Mat3 block = -kx * t.stiffness * nn - kv * t.damping * (Mat3::Identity() - nn);
        // Per side (the sign of the weights), as in addJacobian: Σ_b w_b p_b over the side,
        // then w_a·block times it for each vertex a of that side.
        Vec3 side[2] = {Vec3::Zero(), Vec3::Zero()};
        for (int b = 0; b < 4; ++b) {
            if (t.vertex[b] >= 0) {
                side[t.weight[b] < 0 ? 1 : 0] += t.weight[b] * p.row(t.vertex[b]).transpose();
            }
        }
        const Vec3 product[2] = {block * side[0], block * side[1]};
        for (int a = 0; a < 4; ++a) {
            if (t.vertex[a] >= 0) {
                out.row(t.vertex[a]) +=
                    (t.weight[a] * product[t.weight[a] < 0 ? 1 : 0]).transpose();
            }
        }
    }
}

} // namespace atelier::sim
