#pragma once
/// The obstacle velocity of contacts with moving obstacles, taken over the coming step.

#include "sim/collision/collision_obstacle.h"
#include "sim/collision/contact.h"

#include <vector>

namespace atelier::sim {

/// Before a step [t, t + h] of an implicit integrator: the contacts with moving obstacles take
/// the velocity their obstacle point has over this step (obstacles' xNext are set to their
/// positions at t + h). Detection gave them the last step's: on a spinning body that chord is
/// turned by ωh from this step's, and cloth carried along it drifts outwards by rω²h² a step
/// (measured: 10% strain in 2 s on the fast-rotating-sphere scene).
void predictObstacleVelocities(std::vector<CollisionObstacle>& obstacles,
                               std::vector<Contact>& contacts, double t, double h);

} // namespace atelier::sim
