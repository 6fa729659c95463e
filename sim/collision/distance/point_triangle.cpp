#include "sim/collision/distance/point_triangle.h"

#include "sim/collision/distance/point_segment.h"

#include <Eigen/Geometry>

#include <algorithm>

namespace atelier::sim {

namespace {

/// The triangle point with barycentric weights (u, v, w), made valid (each >= 0, sum 1).
TrianglePoint makeTrianglePoint(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                                double v, double w) {
    v = std::clamp(v, 0.0, 1.0);
    w = std::clamp(w, 0.0, 1.0);
    const double vw = v + w;
    if (vw > 1.0) {
        v /= vw;
        w /= vw;
    }
    const double u = std::max(0.0, (1.0 - v) - w);
    TrianglePoint r;
    r.bary = {u, v, w};
    r.point = u * a + v * b + w * c;
    r.distance = (p - r.point).norm();
    return r;
}

/// Closest point of the triangle's three edges to p (the whole answer for a degenerate one).
TrianglePoint closestPointOnEdges(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const double tab = closestSegmentParameter(p, a, b);
    const double tbc = closestSegmentParameter(p, b, c);
    const double tca = closestSegmentParameter(p, c, a);
    TrianglePoint best = makeTrianglePoint(p, a, b, c, tab, 0.0);
    const TrianglePoint onBc = makeTrianglePoint(p, a, b, c, 1.0 - tbc, tbc);
    if (onBc.distance < best.distance) {
        best = onBc;
    }
    const TrianglePoint onCa = makeTrianglePoint(p, a, b, c, 0.0, 1.0 - tca);
    if (onCa.distance < best.distance) {
        best = onCa;
    }
    return best;
}

/// Ericson's Voronoi-region walk (Real-Time Collision Detection §5.1.5) for a non-degenerate
/// triangle with normal n = (b − a) × (c − a), |n|² = nn > 0. The interior case projects with
/// the cross-product form of the barycentrics, which keeps relative accuracy ≈ ε / sin(angle)
/// on thin triangles (the dot-product form of the book loses ε / sin²).
TrianglePoint closestPointEricson(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                                  const Vec3& n, double nn) {
    const Vec3 ab = b - a;
    const Vec3 ac = c - a;
    const Vec3 ap = p - a;
    const double d1 = ab.dot(ap);
    const double d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) {
        return makeTrianglePoint(p, a, b, c, 0.0, 0.0); // vertex region a
    }
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp);
    const double d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) {
        return makeTrianglePoint(p, a, b, c, 1.0, 0.0); // vertex region b
    }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) { // edge region ab
        const double den = d1 - d3;
        return makeTrianglePoint(p, a, b, c, den > 0 ? d1 / den : 0.0, 0.0);
    }
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp);
    const double d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) {
        return makeTrianglePoint(p, a, b, c, 0.0, 1.0); // vertex region c
    }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) { // edge region ac
        const double den = d2 - d6;
        return makeTrianglePoint(p, a, b, c, 0.0, den > 0 ? d2 / den : 0.0);
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) { // edge region bc
        const double num = d4 - d3;
        const double den = num + (d5 - d6);
        const double w = den > 0 ? num / den : 0.0;
        return makeTrianglePoint(p, a, b, c, 1.0 - w, w);
    }
    // Face region: barycentrics of the projection of p onto the plane.
    const double v = ap.cross(ac).dot(n) / nn;
    const double w = ab.cross(ap).dot(n) / nn;
    return makeTrianglePoint(p, a, b, c, v, w);
}

} // namespace

TrianglePoint closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 n = (b - a).cross(c - a);
    const double nn = n.squaredNorm();
    const double longest2 =
        std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (c - b).squaredNorm()});
    // sin² of the largest angle is at least nn / longest2²: below 1e-30 (sin 1e-15) the
    // triangle is a segment to the working precision, and thin ones (sin < 1e-3) compare the
    // face answer with the edges' (the walk's region tests lose accuracy there).
    if (!(nn > 1e-30 * longest2 * longest2)) {
        return closestPointOnEdges(p, a, b, c);
    }
    TrianglePoint face = closestPointEricson(p, a, b, c, n, nn); // not const: returned by move
    if (nn < 1e-6 * longest2 * longest2) {
        const TrianglePoint edges = closestPointOnEdges(p, a, b, c);
        return edges.distance < face.distance ? edges : face;
    }
    return face;
}

} // namespace atelier::sim
