#pragma once
/// Geometry of pattern curves: lines, quadratic and cubic Béziers, circular arcs (by bulge).

#include "patterns/garment.h"

#include <vector>

namespace atelier::patterns {

/// Point at curve parameter t ∈ [0, 1] [m].
Vec2 pointAt(const Segment& s, double t);
/// Derivative d(point)/dt at t [m].
Vec2 tangentAt(const Segment& s, double t);
/// Arc length from parameter t0 to t1 (t0 ≤ t1 or not; the result is ≥ 0) [m]. Gauss–Legendre
/// quadrature on 16 pieces: exact to rounding for lines and Béziers of moderate bend.
double arcLength(const Segment& s, double t0 = 0.0, double t1 = 1.0);
/// The parameter at arc length `length` from t0 toward t1 (clamped to the range).
double parameterAtLength(const Segment& s, double t0, double t1, double length);
/// Arc geometry: centre, radius and start angle of an arc segment; false for a straight one
/// (bulge 0 or a zero chord).
bool arcGeometry(const Segment& s, Vec2& centre, double& radius, double& startAngle, double& sweep);
/// Signed area enclosed by a closed loop (Green's theorem over each segment), positive when
/// counter-clockwise [m²].
double loopArea(const Loop& loop);
/// Largest distance between the curve on [t0, t1] and the chord joining its ends [m]
/// (sampled at 9 interior points).
double chordDeviation(const Segment& s, double t0, double t1);
/// Whether `p` lies inside the closed polygon `poly` (even-odd rule, crossings of a horizontal
/// ray; a point on an edge may count either way).
bool insidePolygon(const std::vector<Vec2>& poly, const Vec2& p);
/// Points along a segment at n + 1 parameters of equal arc length from t0 to t1.
std::vector<double> equalLengthParameters(const Segment& s, double t0, double t1, int n);

} // namespace atelier::patterns
