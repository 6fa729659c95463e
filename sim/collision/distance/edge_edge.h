#pragma once
/// Distance between two segments: their closest points, robust for parallel and degenerate
/// segments.

#include "sim/core/types.h"

namespace atelier::sim {

/// Closest points of segments p0p1 and q0q1: point s on the first = p0 + s (p1 − p0),
/// t on the second, s, t ∈ [0, 1].
struct SegmentPoints {
    double s = 0;
    double t = 0;
    Vec3 onP;
    Vec3 onQ;
    double distance = 0; ///< |onP − onQ| [m]
};
/// Robust for parallel and degenerate (zero-length) segments; never NaN.
SegmentPoints closestPointsOfSegments(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                      const Vec3& q1);

} // namespace atelier::sim
