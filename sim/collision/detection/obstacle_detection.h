#pragma once
/// Cloth–obstacle contacts: candidate pairs from the hierarchies, then per pair the proximity
/// tests at the step's end and the swept tests over it, for cloth vertex–obstacle face,
/// obstacle vertex–cloth face and edge–edge features.

#include "sim/collision/collision_obstacle.h"
#include "sim/collision/detection/detection_chunk.h"
#include "sim/collision/detection/detection_context.h"
#include "sim/core/types.h"

#include <cstddef>
#include <vector>

namespace atelier::sim {

/// First: the step's detection against an obstacle, proximity at xe and swept tests over
/// xs → xe; with self-collision on, remembered for Again.
/// Again (after the corrections, xs == xe): proximity contacts where the cloth is now. Same
/// contacts in the same order as testing every candidate pair at xe, but only the cloth
/// triangles that moved since First are tested; the others' are First's proximity contacts,
/// those whose normal depends on where the cloth started taken again at xe.
enum class ObstaclePass { First, Again };

/// Detects the contacts of the cloth (xs at the step's start, xe at its end; h the step [s])
/// with obstacle k (o), into the pieces of `scratch` (DetectionScratch::inChunks). `trapped`:
/// per cloth vertex, the obstacle it is inside or -1 (TrappedCloth::obstacleOf). Sets the
/// open-side of the cloth vertices it meets first (o.openSide) and, in the First pass with
/// self-collision on, what Again reuses (o.first…).
DetectionResult detectObstacleContacts(const DetectionContext& ctx, std::size_t k,
                                       CollisionObstacle& o, const std::vector<int>& trapped,
                                       double h, const MatX3& xs, const MatX3& xe,
                                       ObstaclePass which, DetectionScratch& scratch);

} // namespace atelier::sim
