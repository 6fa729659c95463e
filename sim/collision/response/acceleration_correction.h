#pragma once
/// Acceleration-level response (B): during a step, active contacts do not re-approach, with
/// Coulomb friction (stick below the static threshold, kinetic above).

#include "sim/collision/contact.h"
#include "sim/core/types.h"

#include <vector>

namespace atelier::sim {

/// Corrects the accelerations `a` at stage velocities `vs` so the active contacts do not
/// re-approach, with Coulomb friction. `h` is the step [s]. Returns the power of the corrections
/// on the cloth Σ m Δa·v [W].
double correctContactAccelerations(const std::vector<Contact>& contacts, const MatX3& vs, MatX3& a,
                                   const VecX& mass, const VecX& invMass, double h);

} // namespace atelier::sim
