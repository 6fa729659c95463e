#pragma once
/// The exact 3D orientation predicate: on which side of the plane through three points a
/// fourth one lies.

#include "sim/core/types.h"

namespace atelier::sim {

/// Sign of the orientation determinant det[b − a, c − a, d − a], computed exactly (adaptive
/// floating-point filter with an exact expansion fallback): +1, 0 or −1.
int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

} // namespace atelier::sim
