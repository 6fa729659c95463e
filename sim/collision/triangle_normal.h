#pragma once
/// The unit normal of a triangle, the orientation every collision test agrees on.

#include "sim/core/types.h"

#include <Eigen/Geometry>

namespace atelier::sim {

/// Below this length [m] a direction is taken as undefined.
inline constexpr double TINY_LENGTH = 1e-12;

/// Unit normal of triangle (a, b, c) by the right-hand rule, or zero for a degenerate one.
inline Vec3 triangleNormal(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 n = (b - a).cross(c - a);
    const double len = n.norm();
    return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

} // namespace atelier::sim
