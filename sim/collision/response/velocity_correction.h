#pragma once
/// Velocity-level response (A, and the implicit integrators' end-of-step velocities): touching
/// contacts stop approaching, with Coulomb friction; contacts still apart approach no faster than
/// closes their gap within a step.

#include "sim/collision/contact.h"
#include "sim/core/types.h"

#include <vector>

namespace atelier::sim {

/// The velocity-level contact and Coulomb friction of one contact on velocities v: raises the
/// relative normal velocity to at least `minNormal` [m/s] (0: no approach), then, if
/// `friction`, cancels the tangential velocity when it is within the static cone of that
/// impulse, or reduces it by the kinetic friction.
void velocityCorrection(const Contact& c, const VecX& invMass, MatX3& v, double minNormal,
                        bool friction);

/// After the position correction (positions xe, step h [s]), two passes over the contacts on
/// velocities ve: touching contacts stop approaching, with friction; contacts still apart may
/// approach only as fast as closes their gap within a step of the same length, so the next
/// step does not carry them into each other (no friction until they touch).
void correctContactVelocities(const std::vector<Contact>& contacts, const MatX3& xe, MatX3& ve,
                              const VecX& invMass, double h);

/// Two passes of the touching contacts' velocity correction, with friction, on v.
void correctActiveVelocities(const std::vector<Contact>& contacts, MatX3& v, const VecX& invMass);

} // namespace atelier::sim
