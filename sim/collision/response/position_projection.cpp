#include "sim/collision/response/position_projection.h"

#include "sim/collision/response/contact_correction.h"
#include "sim/collision/response/velocity_correction.h"
#include "sim/collision/triangle_normal.h"

#include <algorithm>

namespace atelier::sim {

namespace {

/// Contacts whose gap is within this fraction of the contact distance count as touching.
constexpr double TOUCH = 0.01;

} // namespace

long projectPositions(std::vector<Contact>& contacts, const SceneSpec& scene, MatX3& xe,
                      const VecX& invMass) {
    for (Contact& c : contacts) {
        c.active = false;
    }
    const int iterations = std::max(1, scene.collision.iterations);
    for (int it = 0; it < iterations; ++it) {
        bool moved = false;
        for (Contact& c : contacts) {
            const double w = effectiveInverseMass(c, invMass);
            if (!(w > 0)) {
                continue;
            }
            const double gap = c.normal.dot(combination(c, xe) - c.obstaclePoint);
            double violation = c.distance - gap;
            if (c.obstacle < 0) {
                // Cloth–cloth pushes are bounded per pass: a large one means a side decided
                // wrongly, and pushing a layer far (through an obstacle behind it) is worse than
                // letting the fail-safe hold the vertices back.
                violation = std::min(violation, c.distance);
            }
            if (violation > 0) {
                distribute(c, invMass, w, violation * c.normal, xe);
                c.active = true; // it pushed: it is a touching contact
                moved = true;
            }
        }
        if (!moved) {
            break;
        }
    }
    // Obstacles are hard: a last pass over their contacts, so a cloth–cloth correction made after
    // them cannot leave a vertex inside an obstacle (where the proximity test would lose it).
    for (Contact& c : contacts) {
        if (c.obstacle < 0) {
            continue;
        }
        const double w = effectiveInverseMass(c, invMass);
        const double violation = c.distance - c.normal.dot(combination(c, xe) - c.obstaclePoint);
        if (w > 0 && violation > 0) {
            distribute(c, invMass, w, violation * c.normal, xe);
            c.active = true;
        }
    }
    // Contacts resting in the solve's layer (ContactForces) touch too, for the figures.
    const double layer =
        scene.collision.solveContacts && scene.integrator.kind == IntegratorKind::ImplicitEuler
            ? std::max(TOUCH, scene.collision.solve.margin)
            : TOUCH;
    long active = 0;
    for (Contact& c : contacts) {
        const double gap = c.normal.dot(combination(c, xe) - c.obstaclePoint);
        c.active = c.active || gap <= c.distance * (1.0 + TOUCH) + TINY_LENGTH;
        active += c.active || gap <= c.distance * (1.0 + layer) + TINY_LENGTH ? 1 : 0;
    }
    return active;
}

long correctRedetected(std::vector<Contact>& contacts, std::size_t first, MatX3& xe, MatX3& ve,
                       const VecX& invMass) {
    long active = 0;
    for (std::size_t i = first; i < contacts.size(); ++i) {
        Contact& c = contacts[i];
        const double w = effectiveInverseMass(c, invMass);
        const double violation = c.distance - c.normal.dot(combination(c, xe) - c.obstaclePoint);
        if (w > 0 && violation > 0) {
            distribute(c, invMass, w, violation * c.normal, xe);
        }
        c.active = c.distance - c.normal.dot(combination(c, xe) - c.obstaclePoint) >=
                   -c.distance * TOUCH - TINY_LENGTH;
        if (c.active) {
            velocityCorrection(c, invMass, ve, 0.0, true);
            ++active;
        }
    }
    return active;
}

} // namespace atelier::sim
