#include "sim/collision/ccd/edge_edge_ccd.h"

#include "sim/collision/ccd/coplanarity_cubic.h"
#include "sim/collision/ccd/earliest_contact.h"
#include "sim/collision/ccd/first_proximity.h"
#include "sim/collision/ccd/sweep_bounds.h"
#include "sim/collision/distance/edge_edge.h"

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

/// Edge (pa, pb) against edge (qa, qb), all moving linearly over the step.
struct EdgeEdgeSweep {
    Vec3 pa0, pa1, pb0, pb1, qa0, qa1, qb0, qb1;

    SegmentPoints closest(double t) const {
        return closestPointsOfSegments(lerp(pa0, pa1, t), lerp(pb0, pb1, t), lerp(qa0, qa1, t),
                                       lerp(qb0, qb1, t));
    }
    Probe probe(double t) const {
        const SegmentPoints sp = closest(t);
        Probe r;
        r.distance = sp.distance;
        if (sp.distance > 0) {
            r.direction = (sp.onQ - sp.onP) / sp.distance;
        }
        return r;
    }
    /// n·(q − p) at t for the four endpoint pairs, each linear in t: their minimum bounds the
    /// distance from below for a unit n.
    std::array<double, 4> gaps(const Vec3& n, double t) const {
        const double qa = n.dot(lerp(qa0, qa1, t));
        const double qb = n.dot(lerp(qb0, qb1, t));
        const double pa = n.dot(lerp(pa0, pa1, t));
        const double pb = n.dot(lerp(pb0, pb1, t));
        return {qa - pa, qa - pb, qb - pa, qb - pb};
    }
};

} // namespace

// The guarantees and the method are those of sweptVertexTriangle (ccd/point_triangle_ccd.cpp).
std::optional<SweptHit> sweptEdgeEdge(const Vec3& pa0, const Vec3& pa1, const Vec3& pb0,
                                      const Vec3& pb1, const Vec3& qa0, const Vec3& qa1,
                                      const Vec3& qb0, const Vec3& qb1, double distance) {
    if (!(isFinite(pa0) && isFinite(pa1) && isFinite(pb0) && isFinite(pb1) && isFinite(qa0) &&
          isFinite(qa1) && isFinite(qb0) && isFinite(qb1))) {
        return std::nullopt;
    }
    distance = distance > 0 && std::isfinite(distance) ? distance : 0.0;
    // Coplanarity of (pa, pb, qa, qb): (qa − pa) · ((pb − pa) × (qb − qa)).
    const Vec3 x0 = qa0 - pa0;
    const Vec3 x1 = qa1 - pa1;
    const Vec3 e10 = pb0 - pa0;
    const Vec3 e11 = pb1 - pa1;
    const Vec3 e20 = qb0 - qa0;
    const Vec3 e21 = qb1 - qa1;
    const Vec3 dx = x1 - x0;
    const Vec3 de1 = e11 - e10;
    const Vec3 de2 = e21 - e20;
    // The relative speeds of the four endpoint pairs bound that of any pair of points.
    const double lipschitz =
        std::max({dx.norm(), (dx + de2).norm(), (dx - de1).norm(), (dx + de2 - de1).norm()});
    const SweepBounds bounds =
        sweepBounds({x0, x1, e10, e11, e20, e21, dx, de1, de2}, lipschitz, distance);
    const EdgeEdgeSweep pair{pa0, pa1, pb0, pb1, qa0, qa1, qb0, qb1};
    const std::optional<double> time =
        distance > 0 ? firstProximity(pair, bounds)
                     : earliestContact(pair, tripleProductCubic(x0, dx, e10, de1, e20, de2),
                                       coplanarityNoise(x0, dx, e10, de1, e20, de2), bounds);
    if (!time) {
        return std::nullopt;
    }
    const SegmentPoints sp = pair.closest(*time);
    return SweptHit{*time, {sp.s, sp.t, 0.0}};
}

} // namespace atelier::sim
