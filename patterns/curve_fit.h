#pragma once
/// Curves through digitised points: a chain of points as few lines and cubic Béziers as stay
/// within a tolerance of every point, and the nearest point of a loop of segments. The pattern
/// importers use them (io/dxf_aama.cpp: cut lines digitised every millimetre or two).

#include "patterns/curve.h"
#include "patterns/garment.h"

#include <limits>
#include <vector>

namespace atelier::patterns {

/// Appends to `out` the points p[first..last] (a chain of straight spans) as a line where every
/// point is within `tol` of the chord, else as cubic Béziers fitted by least squares with
/// chord-length parameters refined by Newton steps (Schneider's method), split at the worst
/// point (kept in the middle half, so the depth stays logarithmic) until each is within `tol`
/// of its points and no longer than 1.02 times their polyline. `error` takes the largest
/// distance of a point from its fitted piece (an upper bound of the distance to the curve) [m].
void fitPolyline(const std::vector<Vec2>& p, std::size_t first, std::size_t last, double tol,
                 Loop& out, double& error, int depth = 0);

/// The point of `loop` nearest to q: segment index, curve parameter and distance (sampled at
/// 32 points per segment, refined by golden-section search; a segment whose bounding box is
/// farther than the best so far is skipped).
struct NearestPoint {
    int segment = -1;
    double t = 0;
    double distance = std::numeric_limits<double>::infinity();
};
NearestPoint nearestPoint(const Loop& loop, const Vec2& q);

} // namespace atelier::patterns
