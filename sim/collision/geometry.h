#pragma once
/// Narrow-phase geometry of collisions: closest points, continuous (swept) tests, exact
/// triangle–triangle intersection. Free functions over points; no state.

#include "sim/core/types.h"

#include <Eigen/Geometry>

#include <array>
#include <optional>

namespace atelier::sim {

/// Closest point of triangle (a, b, c) to p.
struct TrianglePoint {
    Vec3 point;            ///< closest point on the triangle [m]
    std::array<double, 3> bary{}; ///< barycentric weights of a, b, c (sum 1, each >= 0)
    double distance = 0;   ///< |p − point| [m]
};
/// Closest point of a triangle (Ericson, Real-Time Collision Detection §5.1.5). Degenerate
/// triangles (zero area) fall back to the closest of their edges; never NaN.
TrianglePoint closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

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

/// A hit of a continuous test: the first time in [0, 1] (fraction of the step, positions
/// moving linearly from start to end) at which the primitives are within the distance.
struct SweptHit {
    double time = 0; ///< fraction of the step in [0, 1]
    /// Vertex–triangle: barycentric weights of the triangle's vertices at `time`.
    /// Edge–edge: (s, t, unused) segment parameters at `time`.
    std::array<double, 3> coords{};
};

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

/// Continuous edge–edge test: segments p (p0→p1 over the step at endpoints) and q, same
/// conventions. Edge p is (pa, pb), edge q is (qa, qb), each endpoint moving start→end.
std::optional<SweptHit> sweptEdgeEdge(const Vec3& pa0, const Vec3& pa1, const Vec3& pb0,
                                      const Vec3& pb1, const Vec3& qa0, const Vec3& qa1,
                                      const Vec3& qb0, const Vec3& qb1, double distance);

/// Sign of the orientation determinant det[b − a, c − a, d − a], computed exactly (adaptive
/// floating-point filter with an exact expansion fallback): +1, 0 or −1.
int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Exact test of whether two closed triangles share a point (touching counts). Degenerate
/// triangles are handled (treated as segments or points). Uses only `orient3d`-type exact
/// predicates, so the answer does not depend on rounding.
bool trianglesIntersect(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0,
                        const Vec3& b1, const Vec3& b2);

/// Unit normal of triangle (a, b, c) by the right-hand rule, or zero for a degenerate one.
inline Vec3 triangleNormal(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 n = (b - a).cross(c - a);
    const double len = n.norm();
    return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

} // namespace atelier::sim
