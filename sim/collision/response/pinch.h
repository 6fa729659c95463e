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

/// Removes, from contacts[first, end), the face–vertex obstacle contacts of cloth faces pierced
/// from both sides of a crease of one obstacle at positions x: two of the face's contacts with
/// the same obstacle whose normals oppose, whose obstacle points lie closer together along them
/// than the two contact distances, and each of whose obstacle points is through the face (a
/// cloth triangle wedged between the arm and the torso at the armpit). Projected one after the
/// other they rocked the face, pushing one of its vertices 25 mm into the body in four passes;
/// the face's vertices keep their own contacts. Returns how many contacts were removed.
std::size_t dropSqueezedFaces(std::vector<Contact>& contacts, std::size_t first, const MatX3& x);

} // namespace atelier::sim
