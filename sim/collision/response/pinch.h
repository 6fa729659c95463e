#pragma once
/// A cloth vertex pinched between two obstacles: held by the one that grips harder, sliding
/// freely on the other.

#include "sim/collision/contact.h"
#include "sim/core/types.h"

#include <cstddef>
#include <utility>
#include <vector>

namespace atelier::sim {

/// Sets Contact::grip of the touching vertex–face obstacle contacts of pinched vertices and
/// holds each such vertex where the gripping obstacle carried it over the step (xs → xe, step
/// h [s]). `obstacleCount`: obstacles in the scene (a pinch needs two); `scratch`: reused
/// (vertex, contact) list.
void markPinches(std::vector<Contact>& contacts, std::size_t obstacleCount, const MatX3& xs,
                 MatX3& xe, double h, std::vector<std::pair<int, std::size_t>>& scratch);

} // namespace atelier::sim
