#pragma once
/// Continuous (swept) vertex–triangle test: the first time in a step at which a moving vertex
/// comes within a distance of a moving triangle.

#include "sim/collision/ccd/swept_hit.h"
#include "sim/core/types.h"

#include <optional>

namespace atelier::sim {

/// Continuous vertex–triangle test: vertex p moves p0→p1, triangle vertices a0→a1, b0→b1,
/// c0→c1 linearly over the step. Returns the earliest time at which the distance of p to the
/// triangle is <= `distance` [m] (0: an exact crossing), or nullopt. Guarantees (see the .cpp):
/// no miss — if the distance reaches `distance` at τ, a hit at a time <= τ is returned; before
/// the returned time the distance stays above `distance` + 1e-9·scale. Distance 0 solves the
/// coplanarity cubic with all its roots in [0, 1]; distance > 0 uses a conservative forward
/// search that also finds near passes without a plane crossing. Never NaN.
std::optional<SweptHit> sweptVertexTriangle(const Vec3& p0, const Vec3& p1, const Vec3& a0,
                                            const Vec3& a1, const Vec3& b0, const Vec3& b1,
                                            const Vec3& c0, const Vec3& c1, double distance);

} // namespace atelier::sim
