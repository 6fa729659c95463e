#include "sim/collision/distance/edge_edge.h"

#include "sim/collision/distance/point_segment.h"

#include <Eigen/Geometry>

namespace atelier::sim {

SegmentPoints closestPointsOfSegments(const Vec3& p0, const Vec3& p1, const Vec3& q0,
                                      const Vec3& q1) {
    const auto make = [&](double s, double t) {
        SegmentPoints r;
        r.s = s;
        r.t = t;
        r.onP = (1.0 - s) * p0 + s * p1;
        r.onQ = (1.0 - t) * q0 + t * q1;
        r.distance = (r.onP - r.onQ).norm();
        return r;
    };
    const Vec3 d1 = p1 - p0;
    const Vec3 d2 = q1 - q0;
    const Vec3 n = d1.cross(d2);
    const double nn = n.squaredNorm();
    // Interior critical point of the (convex) squared distance on [0, 1]², from the
    // cross-product form of the normal equations (well conditioned down to small angles):
    // s = ((q0 − p0) × d2)·n / |n|², t = ((q0 − p0) × d1)·n / |n|².
    if (nn > 0) {
        const Vec3 w = q0 - p0;
        const double sNum = w.cross(d2).dot(n);
        const double tNum = w.cross(d1).dot(n);
        if (sNum >= 0 && sNum <= nn && tNum >= 0 && tNum <= nn) {
            SegmentPoints inner = make(sNum / nn, tNum / nn); // not const: returned by move
            // Clearly non-parallel: the critical point is the minimum.
            if (nn > 1e-8 * d1.squaredNorm() * d2.squaredNorm()) {
                return inner;
            }
            SegmentPoints best = inner;
            for (const SegmentPoints& r : {make(0.0, closestSegmentParameter(p0, q0, q1)),
                                           make(1.0, closestSegmentParameter(p1, q0, q1)),
                                           make(closestSegmentParameter(q0, p0, p1), 0.0),
                                           make(closestSegmentParameter(q1, p0, p1), 1.0)}) {
                if (r.distance < best.distance) {
                    best = r;
                }
            }
            return best;
        }
    }
    // Otherwise the minimum is on the boundary of [0, 1]²: one endpoint against the other
    // segment.
    SegmentPoints best = make(0.0, closestSegmentParameter(p0, q0, q1));
    for (const SegmentPoints& r : {make(1.0, closestSegmentParameter(p1, q0, q1)),
                                   make(closestSegmentParameter(q0, p0, p1), 0.0),
                                   make(closestSegmentParameter(q1, p0, p1), 1.0)}) {
        if (r.distance < best.distance) {
            best = r;
        }
    }
    return best;
}

} // namespace atelier::sim
