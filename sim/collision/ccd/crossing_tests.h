#pragma once
/// The collision stage's continuous tests of feature pairs: a cheap swept-box test first, then
/// the exact swept tests (crossings, distance 0), and where two edges meet.

#include "sim/collision/ccd/swept_hit.h"
#include "sim/core/types.h"

#include <array>
#include <cstddef>
#include <optional>

namespace atelier::sim {

/// Whether the boxes swept by two groups of moving points (start/end pairs) come within d:
/// a cheap test before the continuous ones.
template <std::size_t N, std::size_t M>
bool sweptBoxesNear(const std::array<const Vec3*, N>& a, const std::array<const Vec3*, M>& b,
                    double d) {
    Vec3 alo = *a[0], ahi = *a[0], blo = *b[0], bhi = *b[0];
    for (const Vec3* p : a) {
        alo = alo.cwiseMin(*p);
        ahi = ahi.cwiseMax(*p);
    }
    for (const Vec3* p : b) {
        blo = blo.cwiseMin(*p);
        bhi = bhi.cwiseMax(*p);
    }
    return (alo.array() <= bhi.array() + d).all() && (blo.array() <= ahi.array() + d).all();
}

/// When a point moving p0 → p1 passes through the triangle (a, b, c), each corner moving
/// …0 → …1, during the step (first contact), if it does; only where the swept boxes overlap.
std::optional<SweptHit> vertexCrosses(const Vec3& p0, const Vec3& p1, const Vec3& a0,
                                      const Vec3& a1, const Vec3& b0, const Vec3& b1,
                                      const Vec3& c0, const Vec3& c1);

/// Where edge (a, b) meets edge (c, d), each end moving from …0 to …1 over the step: the
/// closest points at the end when interior to both and closer than `reach` (`near`), else, if
/// `swept`, interior points that meet during the step. Where the closest points are an end, the
/// vertex–face tests cover it, and the direction between them is not a surface normal.
struct EdgeMeeting {
    double s = 0, t = 0; ///< parameters along (a, b) and (c, d)
    bool near = false;
};
std::optional<EdgeMeeting> edgesMeet(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1,
                                     const Vec3& c0, const Vec3& c1, const Vec3& d0, const Vec3& d1,
                                     double reach, bool swept);

/// The direction in which two meeting edges must stay apart: the one between their meeting
/// points at the end (de) where they are near and have not turned over since the start (ds),
/// else the one at the start; none when both are too short to tell.
std::optional<Vec3> edgeSeparation(const Vec3& de, const Vec3& ds, bool near);

} // namespace atelier::sim
