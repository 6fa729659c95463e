#pragma once
/// Distance of a point to a triangle: its closest point, robust for thin and degenerate
/// triangles.

#include "sim/core/types.h"

#include <array>

namespace atelier::sim {

/// Closest point of triangle (a, b, c) to p.
struct TrianglePoint {
    Vec3 point;                   ///< closest point on the triangle [m]
    std::array<double, 3> bary{}; ///< barycentric weights of a, b, c (sum 1, each >= 0)
    double distance = 0;          ///< |p − point| [m]
};
/// Closest point of a triangle (Ericson, Real-Time Collision Detection §5.1.5). Degenerate
/// triangles (zero area) fall back to the closest of their edges; never NaN.
TrianglePoint closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

} // namespace atelier::sim
