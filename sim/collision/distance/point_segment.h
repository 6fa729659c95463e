#pragma once
/// Distance of a point to a segment: the parameter of the segment's closest point.

#include "sim/core/types.h"

namespace atelier::sim {

/// Parameter in [0, 1] of the point of segment (a, b) closest to p; 0 for a zero-length one.
inline double closestSegmentParameter(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const double len2 = ab.squaredNorm();
    const double dot = (p - a).dot(ab);
    if (!(dot > 0) || !(len2 > 0)) {
        return 0.0;
    }
    if (dot >= len2) {
        return 1.0;
    }
    return dot / len2;
}

} // namespace atelier::sim
