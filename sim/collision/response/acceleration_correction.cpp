#include "sim/collision/response/acceleration_correction.h"

#include "sim/collision/response/contact_correction.h"

namespace atelier::sim {

double correctContactAccelerations(const std::vector<Contact>& contacts, const MatX3& vs, MatX3& a,
                                   const VecX& mass, const VecX& invMass, double h) {
    double power = 0;
    for (const Contact& c : contacts) {
        if (!c.active) {
            continue;
        }
        const double w = effectiveInverseMass(c, invMass);
        if (!(w > 0)) {
            continue;
        }
        const Vec3 arel = combination(c, a);
        const double an = c.normal.dot(arel);
        if (an >= 0) {
            continue; // separating: the contact does not pull
        }
        const double pressure = -an; // normal acceleration the contact must supply [m/s²]
        Vec3 delta = pressure * c.normal;
        const Vec3 u = combination(c, vs) - c.obstacleVelocity;
        const Vec3 ut = u - c.normal.dot(u) * c.normal;
        const double utn = ut.norm();
        if (utn > c.kineticFriction * pressure * h && utn > 0) {
            // Sliding: kinetic friction against the relative tangential velocity.
            delta -= (c.kineticFriction * pressure / utn) * ut;
        } else {
            // At rest (or stopping within this step): cancel the tangential acceleration and the
            // remaining slip if the static cone allows, else kinetic friction against it.
            const Vec3 at = arel - an * c.normal;
            const Vec3 need = -(at + (h > 0 ? Vec3(ut / h) : Vec3::Zero()));
            const double needN = need.norm();
            if (needN <= c.staticFriction * pressure) {
                delta += need;
            } else if (needN > 0) {
                delta += (c.kineticFriction * pressure / needN) * need;
            }
        }
        for (int k = 0; k < 4; ++k) {
            const int i = c.vertex[k];
            if (i >= 0 && invMass[i] > 0) {
                const Vec3 dai = c.weight[k] * invMass[i] / w * delta;
                a.row(i) += dai.transpose();
                power += mass[i] * dai.dot(row(vs, i));
            }
        }
    }
    return power;
}

} // namespace atelier::sim
