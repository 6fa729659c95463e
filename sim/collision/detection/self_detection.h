#pragma once
/// Cloth–cloth contacts of the self-colliding cloths: candidate pairs from the cloth hierarchy
/// with curvature culling, then vertex–face (both ways) and edge–edge proximity and swept tests
/// per pair, each vertex–face contact on the side remembered from the last step or taken where
/// the vertex started.

#include "sim/collision/detection/contact_regions.h"
#include "sim/collision/detection/detection_chunk.h"
#include "sim/collision/detection/detection_context.h"
#include "sim/core/types.h"

namespace atelier::sim {

/// Detects the self contacts of the cloth moving from xs to xe (swept tests only when they are
/// different arrays) into the pieces of `scratch`, with their memory keys, sides and
/// reliability. `memory`: the sides of the pairs in contact after the last step
/// (ContactRegions::memory). `watched`: triangle pairs tested whatever the curvature culling
/// says (CrossingFailSafe::watchedPairs), sorted, each (smaller, larger) once.
DetectionResult detectSelfContacts(const DetectionContext& ctx, const ContactMemory& memory,
                                   const MatX3& xs, const MatX3& xe, DetectionScratch& scratch,
                                   const std::vector<std::pair<int, int>>& watched = {});

} // namespace atelier::sim
