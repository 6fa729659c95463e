#pragma once
/// Exact triangle–triangle intersection test.

#include "sim/core/types.h"

namespace atelier::sim {

/// Exact test of whether two closed triangles share a point (touching counts). Degenerate
/// triangles are handled (treated as segments or points). Uses only `orient3d`-type exact
/// predicates, so the answer does not depend on rounding.
bool trianglesIntersect(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0,
                        const Vec3& b1, const Vec3& b2);

} // namespace atelier::sim
