#include "sim/collision/response/velocity_correction.h"

#include "sim/collision/response/contact_correction.h"

namespace atelier::sim {

void velocityCorrection(const Contact& c, const VecX& invMass, MatX3& v, double minNormal,
                        bool friction) {
    const double w = effectiveInverseMass(c, invMass);
    if (!(w > 0)) {
        return;
    }
    const Vec3 u = combination(c, v) - c.obstacleVelocity;
    const double un = c.normal.dot(u);
    if (un >= minNormal) {
        return;
    }
    const double jn = minNormal - un;
    Vec3 delta = jn * c.normal;
    if (friction && c.grip != Contact::Grip::Slip) {
        const Vec3 ut = u - un * c.normal;
        const double utn = ut.norm();
        if ((c.grip == Contact::Grip::Stick && c.staticFriction > 0) ||
            utn <= c.staticFriction * jn) {
            delta -= ut;
        } else if (utn > 0) {
            delta -= (c.kineticFriction * jn / utn) * ut;
        }
    }
    distribute(c, invMass, w, delta, v);
}

void correctContactVelocities(const std::vector<Contact>& contacts, const MatX3& xe, MatX3& ve,
                              const VecX& invMass, double h) {
    for (int pass = 0; pass < 2; ++pass) {
        for (const Contact& c : contacts) {
            if (c.active) {
                velocityCorrection(c, invMass, ve, 0.0, true);
            } else if (h > 0) {
                const double gap = c.normal.dot(combination(c, xe) - c.obstaclePoint);
                velocityCorrection(c, invMass, ve, -(gap - c.distance) / h, false);
            }
        }
    }
}

void correctActiveVelocities(const std::vector<Contact>& contacts, MatX3& v, const VecX& invMass) {
    for (int pass = 0; pass < 2; ++pass) {
        for (const Contact& c : contacts) {
            if (c.active) {
                velocityCorrection(c, invMass, v, 0.0, true);
            }
        }
    }
}

} // namespace atelier::sim
