#pragma once
/// The cut line of a panel: its outline offset outward by the seam allowance, as a polyline.
/// The offset of a curve is not a curve of the same kind (the offset of a Bézier is no
/// Bézier), so curves are sampled first; corners get round joins, so that every point of the
/// cut line is the allowance away from the outline (the boundary of the outline's Minkowski
/// sum with a disc, without its self-crossings).

#include "patterns/garment.h"

#include <vector>

namespace atelier::patterns {

/// A closed loop as a polyline [m]: each segment's start, then points inside curved segments
/// at uniform parameter steps, as many as keep every chord within `tolerance` [m] of its curve
/// (at most 4096 pieces a segment). The closing point (the first) is not repeated.
std::vector<Vec2> loopPolyline(const Loop& loop, double tolerance);

/// Which side of a closed polyline the offset goes to.
enum class OffsetSide {
    Outside, ///< away from the region it encloses (a panel's outline: the fabric is inside)
    Inside,  ///< into the region it encloses (a hole: the fabric is outside)
};

/// The closed polylines at `distance` [m] from the closed polyline `loop` on `side`, without
/// the parts that come nearer than `distance` to another part of it (inner corners, darts,
/// narrow necks): the boundary of the points within `distance` of the region's fabric side.
/// Convex corners are rounded by a polygon circumscribing the arc, whose points lie between
/// `distance` and `distance + tolerance` from the corner. Usually one loop; none when an
/// inside offset swallows the whole region, more when a neck pinches it. `distance` = 0
/// returns `loop` itself. The loops keep the orientation of `loop`. Should the crossings not
/// resolve into closed loops (a crossing exactly through a vertex, even after moving the
/// distance in its ninth digit), the untrimmed offset is returned.
std::vector<std::vector<Vec2>> offsetPolyline(const std::vector<Vec2>& loop, double distance,
                                              OffsetSide side, double tolerance);

/// Signed area of a closed polyline, positive when counter-clockwise [m²].
double polylineArea(const std::vector<Vec2>& loop);

/// Whether `p` lies inside the closed polyline (even–odd rule).
bool insidePolyline(const std::vector<Vec2>& loop, const Vec2& p);

/// Distance from `p` to the closed polyline [m].
double distanceToPolyline(const std::vector<Vec2>& loop, const Vec2& p);

} // namespace atelier::patterns
