#pragma once
/// Position-level response (A): the contacts' violations are projected out of the end-of-step
/// positions by inverse mass, a few Gauss–Seidel passes, obstacles last (they are hard).

#include "sim/collision/contact.h"
#include "sim/core/types.h"
#include "sim/scene.h"

#include <cstddef>
#include <vector>

namespace atelier::sim {

/// Corrects positions xe so that every contact keeps its distance (scene.collision.iterations
/// passes, cloth–cloth pushes bounded per pass, then a last pass over the obstacle contacts),
/// and sets Contact::active on the touching ones. Returns the number of contacts touching or
/// resting in the implicit solve's contact layer (CollisionFigures::contacts).
long projectPositions(std::vector<Contact>& contacts, const SceneSpec& scene, MatX3& xe,
                      const VecX& invMass);

/// The contacts from index `first` on, found again against the obstacles after the cloth–cloth
/// corrections (ObstaclePass::Again): each violated one is projected out of xe, and the
/// touching ones are made active and stop approaching (ve, with friction). Returns the number
/// of them made active.
long correctRedetected(std::vector<Contact>& contacts, std::size_t first, MatX3& xe, MatX3& ve,
                       const VecX& invMass);

} // namespace atelier::sim
