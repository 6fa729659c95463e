#pragma once
/// Basic array types of the engine. SI units throughout (m, kg, s, N).

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace atelier::sim {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat2 = Eigen::Matrix2d;
using Mat3 = Eigen::Matrix3d;

/// Per-vertex 3D state, one row per vertex: (|V|×3), row-major so a row is contiguous.
using MatX3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// Per-vertex 2D rest (pattern) coordinates [m]: (|V|×2).
using MatX2 = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;
/// Triangle vertex indices: (|F|×3).
using MatX3i = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// Edge vertex indices: (|E|×2).
using MatX2i = Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor>;
using VecX = Eigen::VectorXd;
using VecXi = Eigen::VectorXi;

/// Standard gravity [m/s²].
inline constexpr double STANDARD_GRAVITY = 9.80665;

/// The z component of the cross product of two plane vectors: a.x·b.y − a.y·b.x (twice the
/// signed area of the triangle they span; > 0 when b turns counter-clockwise from a).
inline double cross2d(const Vec2& a, const Vec2& b) {
    return a.x() * b.y() - a.y() * b.x();
}

} // namespace atelier::sim
