#include "sim/collision/ccd/crossing_tests.h"

#include "sim/collision/ccd/edge_edge_ccd.h"
#include "sim/collision/ccd/point_triangle_ccd.h"
#include "sim/collision/distance/edge_edge.h"
#include "sim/collision/triangle_normal.h"

namespace atelier::sim {

namespace {

/// Whether a segment parameter is strictly inside (not at an end).
bool interior(double s) {
    return s > 1e-9 && s < 1.0 - 1e-9;
}

} // namespace

std::optional<SweptHit> vertexCrosses(const Vec3& p0, const Vec3& p1, const Vec3& a0,
                                      const Vec3& a1, const Vec3& b0, const Vec3& b1,
                                      const Vec3& c0, const Vec3& c1) {
    if (!sweptBoxesNear<2, 6>({&p0, &p1}, {&a0, &a1, &b0, &b1, &c0, &c1}, 0.0)) {
        return std::nullopt;
    }
    return sweptVertexTriangle(p0, p1, a0, a1, b0, b1, c0, c1, 0.0);
}

std::optional<EdgeMeeting> edgesMeet(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1,
                                     const Vec3& c0, const Vec3& c1, const Vec3& d0, const Vec3& d1,
                                     double reach, bool swept) {
    if (!sweptBoxesNear<4, 4>({&a0, &a1, &b0, &b1}, {&c0, &c1, &d0, &d1}, reach)) {
        return std::nullopt;
    }
    const SegmentPoints sp = closestPointsOfSegments(a1, b1, c1, d1);
    if (sp.distance < reach && interior(sp.s) && interior(sp.t)) {
        return EdgeMeeting{sp.s, sp.t, true};
    }
    // The swept test looks for a crossing: the swept boxes must overlap.
    if (!swept || !sweptBoxesNear<4, 4>({&a0, &a1, &b0, &b1}, {&c0, &c1, &d0, &d1}, 0.0)) {
        return std::nullopt;
    }
    const auto hit = sweptEdgeEdge(a0, a1, b0, b1, c0, c1, d0, d1, 0.0);
    if (!hit || !interior(hit->coords[0]) || !interior(hit->coords[1])) {
        return std::nullopt;
    }
    return EdgeMeeting{hit->coords[0], hit->coords[1], false};
}

std::optional<Vec3> edgeSeparation(const Vec3& de, const Vec3& ds, bool near) {
    if (near && de.dot(ds) > 0 && de.norm() > TINY_LENGTH) {
        return de.normalized();
    }
    if (ds.norm() > TINY_LENGTH) {
        return ds.normalized();
    }
    return std::nullopt;
}

} // namespace atelier::sim
