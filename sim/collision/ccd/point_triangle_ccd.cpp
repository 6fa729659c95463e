#include "sim/collision/ccd/point_triangle_ccd.h"

#include "sim/collision/ccd/coplanarity_cubic.h"
#include "sim/collision/ccd/earliest_contact.h"
#include "sim/collision/ccd/first_proximity.h"
#include "sim/collision/ccd/sweep_bounds.h"
#include "sim/collision/distance/point_triangle.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace atelier::sim {

namespace {

using ccd::coplanarityNoise;
using ccd::earliestContact;
using ccd::firstProximity;
using ccd::isFinite;
using ccd::lerp;
using ccd::Probe;
using ccd::SweepBounds;
using ccd::sweepBounds;
using ccd::tripleProductCubic;

/// Vertex p against triangle (a, b, c), all moving linearly over the step.
struct VertexTriangleSweep {
    Vec3 p0, p1, a0, a1, b0, b1, c0, c1;

    TrianglePoint closest(double t) const {
        return closestPointOnTriangle(lerp(p0, p1, t), lerp(a0, a1, t), lerp(b0, b1, t),
                                      lerp(c0, c1, t));
    }
    Probe probe(double t) const {
        const TrianglePoint cp = closest(t);
        Probe r;
        r.distance = cp.distance;
        if (cp.distance > 0) {
            r.direction = (lerp(p0, p1, t) - cp.point) / cp.distance;
        }
        return r;
    }
    /// n·(p − v) at t for the triangle's vertices v (the last one twice), each linear in t:
    /// their minimum bounds the distance from below for a unit n.
    std::array<double, 4> gaps(const Vec3& n, double t) const {
        const double np = n.dot(lerp(p0, p1, t));
        const double gc = np - n.dot(lerp(c0, c1, t));
        return {np - n.dot(lerp(a0, a1, t)), np - n.dot(lerp(b0, b1, t)), gc, gc};
    }
};

} // namespace

// Continuous tests. Positions move linearly over the step. `scale` is the largest vertex offset
// from the first vertex (a, resp. pa) at either end of the step, or the largest change of one
// over the step; tol = 1e-9 · scale; res = 1e-6 · scale (for distance > 0: min(res, distance),
// and at least tol); L = the largest relative speed of a vertex pair [m per step], which bounds
// how fast the distance can change. What is guaranteed:
//  * Never a missed contact: if the distance is <= `distance` at some τ in [0, 1] (for
//    distance 0: the vertex is in the closed triangle, the closed segments meet), a hit is
//    reported with time <= τ (+ 1e-15, the root finding's accuracy).
//  * Never a hit far from proximity: at the reported time the distance is <= `distance` + tol,
//    or <= `distance` + tol + res where a search stopped at its resolution (below). Only after
//    a search spends its budget (256 evaluations; not seen in the randomized tests) can a hit
//    be farther: a conservative answer.
//  * Nothing earlier: with distance > 0, the distance exceeds `distance` + tol at every time
//    before the reported one; with distance 0 the same holds up to 1e-15 in time.
// How:
//  * distance 0: contact needs coplanarity, so τ is a root of the cubic f(t) = x(t)·(e₁(t) ×
//    e₂(t)) (six times the signed volume of the four points). f is split into monotone pieces
//    at the roots of f'; on each piece, the band of times where |f| <= 2 × (a bound on its
//    rounding error) is examined in time order: when the primitives move less than tol/2
//    across it (a well-conditioned root), by one distance evaluation at its start; otherwise
//    (motion in the plane, nearly parallel edges, grazing motion, degenerate primitives) by
//    branch and bound on lower bounds of the distance (the Lipschitz bound L and a separating
//    direction, see lowerBound), to the resolution res.
//  * distance > 0: conservative advancement from t = 0 (each step jumps to the first time at
//    which the distance may have dropped to `distance` + tol, by the same lower bounds),
//    stopping within res of it; after 12 steps, branch and bound on the rest of the step.
std::optional<SweptHit> sweptVertexTriangle(const Vec3& p0, const Vec3& p1, const Vec3& a0,
                                            const Vec3& a1, const Vec3& b0, const Vec3& b1,
                                            const Vec3& c0, const Vec3& c1, double distance) {
    if (!(isFinite(p0) && isFinite(p1) && isFinite(a0) && isFinite(a1) && isFinite(b0) &&
          isFinite(b1) && isFinite(c0) && isFinite(c1))) {
        return std::nullopt;
    }
    distance = distance > 0 && std::isfinite(distance) ? distance : 0.0;
    const Vec3 x0 = p0 - a0;
    const Vec3 x1 = p1 - a1;
    const Vec3 e10 = b0 - a0;
    const Vec3 e11 = b1 - a1;
    const Vec3 e20 = c0 - a0;
    const Vec3 e21 = c1 - a1;
    const Vec3 dx = x1 - x0;
    const Vec3 de1 = e11 - e10;
    const Vec3 de2 = e21 - e20;
    // The speed of p relative to any point of the triangle is at most that relative to one of
    // its vertices.
    const double lipschitz = std::max({dx.norm(), (dx - de1).norm(), (dx - de2).norm()});
    const SweepBounds bounds =
        sweepBounds({x0, x1, e10, e11, e20, e21, dx, de1, de2}, lipschitz, distance);
    const VertexTriangleSweep pair{p0, p1, a0, a1, b0, b1, c0, c1};
    const std::optional<double> time =
        distance > 0 ? firstProximity(pair, bounds)
                     : earliestContact(pair, tripleProductCubic(x0, dx, e10, de1, e20, de2),
                                       coplanarityNoise(x0, dx, e10, de1, e20, de2), bounds);
    if (!time) {
        return std::nullopt;
    }
    return SweptHit{*time, pair.closest(*time).bary};
}

} // namespace atelier::sim
