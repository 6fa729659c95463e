#include "sim/collision/intersection/triangle_triangle.h"

#include "sim/collision/predicates/orient2d.h"
#include "sim/collision/predicates/orient3d.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cstddef>
#include <utility>

namespace atelier::sim {

namespace {

bool lexLess(const Vec3& p, const Vec3& q) {
    if (p.x() != q.x()) {
        return p.x() < q.x();
    }
    if (p.y() != q.y()) {
        return p.y() < q.y();
    }
    return p.z() < q.z();
}

/// Exactly collinear (or coincident) points: every coordinate projection is degenerate.
bool collinear(const Vec3& a, const Vec3& b, const Vec3& c) {
    return orient2d(a, b, c, 0) == 0 && orient2d(a, b, c, 1) == 0 && orient2d(a, b, c, 2) == 0;
}

/// Overlap of two segments known to lie on one line: along a line, lexicographic order is the
/// order of the points (in one direction or the other).
bool collinearOverlap(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) {
    const auto [p0, p1] = lexLess(q, p) ? std::pair(q, p) : std::pair(p, q);
    const auto [r0, r1] = lexLess(s, r) ? std::pair(s, r) : std::pair(r, s);
    return !lexLess(p1, r0) && !lexLess(r1, p0);
}

/// An axis along which the projection of the non-degenerate triangle (a, b, c) is
/// non-degenerate (so the projection is one-to-one on its plane), the dominant one first.
int projectionAxis(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 n = (b - a).cross(c - a).cwiseAbs();
    std::array<int, 3> order = {0, 1, 2};
    std::sort(order.begin(), order.end(), [&](int l, int r) { return n[l] > n[r]; });
    for (int axis : order) {
        if (orient2d(a, b, c, axis) != 0) {
            return axis;
        }
    }
    return order[0];
}

/// Point p in the closed triangle (a, b, c), all in one plane that `axis` projects one-to-one.
bool pointInTriangle2d(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, int axis) {
    const int o1 = orient2d(a, b, p, axis);
    const int o2 = orient2d(b, c, p, axis);
    const int o3 = orient2d(c, a, p, axis);
    return (o1 >= 0 && o2 >= 0 && o3 >= 0) || (o1 <= 0 && o2 <= 0 && o3 <= 0);
}

/// Closed segments pq and rs (p ≠ q, r ≠ s) in one plane that `axis` projects one-to-one.
bool segmentsIntersect2d(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s, int axis) {
    const int o1 = orient2d(p, q, r, axis);
    const int o2 = orient2d(p, q, s, axis);
    if (o1 == 0 && o2 == 0) {
        return collinearOverlap(p, q, r, s);
    }
    if (o1 * o2 > 0) {
        return false;
    }
    const int o3 = orient2d(r, s, p, axis);
    const int o4 = orient2d(r, s, q, axis);
    return o3 * o4 <= 0;
}

/// Closed segment pq (p ≠ q) and non-degenerate triangle (a, b, c) in one plane.
bool coplanarSegmentTriangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                             const Vec3& c, int axis) {
    return pointInTriangle2d(p, a, b, c, axis) || pointInTriangle2d(q, a, b, c, axis) ||
           segmentsIntersect2d(p, q, a, b, axis) || segmentsIntersect2d(p, q, b, c, axis) ||
           segmentsIntersect2d(p, q, c, a, axis);
}

/// Closed segment pq (p ≠ q) and non-degenerate triangle (a, b, c); op, oq: orient3d(a, b, c, ·)
/// of p and q.
bool segmentTriangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c,
                     int op, int oq) {
    if (op * oq > 0) {
        return false;
    }
    if (op == 0 && oq == 0) {
        return coplanarSegmentTriangle(p, q, a, b, c, projectionAxis(a, b, c));
    }
    if (op == 0 || oq == 0) {
        return pointInTriangle2d(op == 0 ? p : q, a, b, c, projectionAxis(a, b, c));
    }
    // p and q strictly on both sides: the crossing point is inside iff the line pq passes on
    // the same side of (or through) all three edges.
    const int s1 = orient3d(p, q, a, b);
    const int s2 = orient3d(p, q, b, c);
    const int s3 = orient3d(p, q, c, a);
    return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
}

/// Two non-degenerate triangles in one plane.
bool coplanarTriangles(const std::array<Vec3, 3>& t, const std::array<Vec3, 3>& u) {
    const int axis = projectionAxis(t[0], t[1], t[2]);
    for (std::size_t i = 0; i < 3; ++i) {
        for (std::size_t j = 0; j < 3; ++j) {
            if (segmentsIntersect2d(t[i], t[(i + 1) % 3], u[j], u[(j + 1) % 3], axis)) {
                return true;
            }
        }
    }
    return pointInTriangle2d(t[0], u[0], u[1], u[2], axis) ||
           pointInTriangle2d(u[0], t[0], t[1], t[2], axis);
}

/// Two non-degenerate triangles. Outside the coplanar case, they meet iff an edge of one
/// meets the other: their intersection lies on the line where the planes meet, and its ends
/// are ends of the chords that each triangle cuts on that line, which are on its edges.
bool triangleTriangle(const std::array<Vec3, 3>& t, const std::array<Vec3, 3>& u) {
    std::array<int, 3> ou{}; // side of u's vertices relative to t's plane
    std::array<int, 3> ot{};
    for (std::size_t i = 0; i < 3; ++i) {
        ou[i] = orient3d(t[0], t[1], t[2], u[i]);
    }
    if ((ou[0] > 0 && ou[1] > 0 && ou[2] > 0) || (ou[0] < 0 && ou[1] < 0 && ou[2] < 0)) {
        return false;
    }
    if (ou[0] == 0 && ou[1] == 0 && ou[2] == 0) {
        return coplanarTriangles(t, u);
    }
    for (std::size_t i = 0; i < 3; ++i) {
        ot[i] = orient3d(u[0], u[1], u[2], t[i]);
    }
    if ((ot[0] > 0 && ot[1] > 0 && ot[2] > 0) || (ot[0] < 0 && ot[1] < 0 && ot[2] < 0)) {
        return false;
    }
    for (std::size_t i = 0; i < 3; ++i) {
        const std::size_t j = (i + 1) % 3;
        if (segmentTriangle(t[i], t[j], u[0], u[1], u[2], ot[i], ot[j]) ||
            segmentTriangle(u[i], u[j], t[0], t[1], t[2], ou[i], ou[j])) {
            return true;
        }
    }
    return false;
}

/// A triangle as the simplex it really is: a point, a segment (the two extreme points of
/// three collinear ones) or a proper triangle.
struct Simplex {
    int dimension = 2; ///< 0 point, 1 segment, 2 triangle
    std::array<Vec3, 3> v;
};

Simplex simplexOf(const Vec3& a, const Vec3& b, const Vec3& c) {
    Simplex s;
    s.v = {a, b, c};
    if (!collinear(a, b, c)) {
        return s;
    }
    std::sort(s.v.begin(), s.v.end(), lexLess);
    s.v[1] = s.v[2]; // extremes of collinear points in lexicographic order
    s.dimension = s.v[0] == s.v[1] ? 0 : 1;
    return s;
}

/// Closed segments pq and rs (p ≠ q, r ≠ s) in 3D.
bool segmentsIntersect(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) {
    if (orient3d(p, q, r, s) != 0) {
        return false;
    }
    const bool rOnLine = collinear(p, q, r);
    const bool sOnLine = collinear(p, q, s);
    if (rOnLine && sOnLine) {
        return collinearOverlap(p, q, r, s);
    }
    const int axis = rOnLine ? projectionAxis(p, q, s) : projectionAxis(p, q, r);
    return segmentsIntersect2d(p, q, r, s, axis);
}

/// Point r on the closed segment pq (p ≠ q).
bool pointOnSegment(const Vec3& r, const Vec3& p, const Vec3& q) {
    return collinear(p, q, r) && collinearOverlap(p, q, r, r);
}

/// Simplices with dimension(s) >= dimension(t).
bool simplicesIntersect(const Simplex& s, const Simplex& t) {
    const auto& a = s.v;
    const auto& b = t.v;
    switch (s.dimension * 3 + t.dimension) {
    case 0: // point, point
        return a[0] == b[0];
    case 3: // segment, point
        return pointOnSegment(b[0], a[0], a[1]);
    case 4: // segment, segment
        return segmentsIntersect(a[0], a[1], b[0], b[1]);
    case 6: // triangle, point
        return orient3d(a[0], a[1], a[2], b[0]) == 0 &&
               pointInTriangle2d(b[0], a[0], a[1], a[2], projectionAxis(a[0], a[1], a[2]));
    case 7: // triangle, segment
        return segmentTriangle(b[0], b[1], a[0], a[1], a[2], orient3d(a[0], a[1], a[2], b[0]),
                               orient3d(a[0], a[1], a[2], b[1]));
    default: // triangle, triangle
        return triangleTriangle(a, b);
    }
}

} // namespace

bool trianglesIntersect(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0,
                        const Vec3& b1, const Vec3& b2) {
    // Cheap rejection on bounding boxes (exact comparisons).
    const Vec3 aLo = a0.cwiseMin(a1).cwiseMin(a2);
    const Vec3 aHi = a0.cwiseMax(a1).cwiseMax(a2);
    const Vec3 bLo = b0.cwiseMin(b1).cwiseMin(b2);
    const Vec3 bHi = b0.cwiseMax(b1).cwiseMax(b2);
    if ((aHi.array() < bLo.array()).any() || (bHi.array() < aLo.array()).any()) {
        return false;
    }
    const Simplex s = simplexOf(a0, a1, a2);
    const Simplex t = simplexOf(b0, b1, b2);
    return s.dimension >= t.dimension ? simplicesIntersect(s, t) : simplicesIntersect(t, s);
}

} // namespace atelier::sim
