#pragma once
/// The exact 2D orientation predicate on a coordinate projection of 3D points.

#include "sim/core/types.h"

namespace atelier::sim {

/// Exact sign of the 2D orientation of (a, b, c) projected along `axis` (the coordinates
/// (axis + 1) % 3 and (axis + 2) % 3 are kept): positive when counter-clockwise.
int orient2d(const Vec3& a, const Vec3& b, const Vec3& c, int axis);

} // namespace atelier::sim
