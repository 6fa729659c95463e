#pragma once
/// Continuous (swept) edge–edge test: the first time in a step at which two moving edges come
/// within a distance of each other.

#include "sim/collision/ccd/swept_hit.h"
#include "sim/core/types.h"

#include <optional>

namespace atelier::sim {

/// Continuous edge–edge test: segments p (p0→p1 over the step at endpoints) and q, same
/// conventions. Edge p is (pa, pb), edge q is (qa, qb), each endpoint moving start→end.
std::optional<SweptHit> sweptEdgeEdge(const Vec3& pa0, const Vec3& pa1, const Vec3& pb0,
                                      const Vec3& pb1, const Vec3& qa0, const Vec3& qa1,
                                      const Vec3& qb0, const Vec3& qb1, double distance);

} // namespace atelier::sim
