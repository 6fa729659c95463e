#pragma once
/// Lower bounds of the distance of a swept pair over an interval of the step, and the branch and
/// bound on them that the continuous tests share. A `Pair` (VertexTriangleSweep,
/// EdgeEdgeSweep) gives `probe(t)` (Probe) and `gaps(n, t)`: four gaps along a unit direction,
/// each linear in t, whose minimum bounds the distance from below.

#include "sim/collision/ccd/ccd_tolerances.h"
#include "sim/core/types.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <optional>

namespace atelier::sim::ccd {

/// Whether every coordinate is finite.
inline bool isFinite(const Vec3& v) {
    return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

/// Tolerances of the searches of a continuous test.
struct SweepBounds {
    double lipschitz = 0;  ///< bound on |d(distance)/dt| over the step [m per step]
    double threshold = 0;  ///< a time is a hit when the distance is <= this [m]
    double tolerance = 0;  ///< absolute tolerance included in `threshold` [m]
    double resolution = 0; ///< searches stop when the distance can change less than this [m]
};

/// Tolerances of a continuous test: `offsets` are the vectors whose largest norm is the scale
/// (vertex offsets at both ends of the step and their changes) [m], `lipschitz` the largest
/// relative vertex speed [m per step].
SweepBounds sweepBounds(const std::array<Vec3, 9>& offsets, double lipschitz, double distance);

/// Point of a linear motion at fraction t of the step (exact at t = 0 and t = 1).
inline Vec3 lerp(const Vec3& start, const Vec3& end, double t) {
    return (1.0 - t) * start + t * end;
}

/// Distance of a swept pair at one time, with the unit direction from the second primitive's
/// closest point to the first's (zero when they touch).
struct Probe {
    double distance = 0;
    Vec3 direction = Vec3::Zero();
};

/// Gap between the pair's projections on the unit direction n at t: a lower bound of the
/// distance, and a minimum of functions linear in t (the vertices move linearly), hence concave.
template <class Pair> double separation(const Pair& pair, const Vec3& n, double t) {
    const std::array<double, 4> g = pair.gaps(n, t);
    return std::min({g[0], g[1], g[2], g[3]});
}

/// First time in [t, 1] at which the separation along n may be <= threshold (each linear gap
/// crosses it at most once), or 2 when it stays above until the end of the step.
template <class Pair>
double separationExit(const Pair& pair, const Vec3& n, double t, double threshold) {
    const std::array<double, 4> g0 = pair.gaps(n, t);
    const std::array<double, 4> g1 = pair.gaps(n, 1.0);
    double exit = 2.0;
    for (std::size_t k = 0; k < 4; ++k) {
        if (g1[k] > threshold) {
            continue;
        }
        if (g0[k] <= threshold) {
            return t;
        }
        // g0 > threshold >= g1: the quotient lies in (0, 1].
        exit = std::min(exit, t + (g0[k] - threshold) / (g0[k] - g1[k]) * (1.0 - t));
    }
    return exit;
}

/// Lower bound of the distance over [lo, hi], from the probes at both ends. Two bounds:
///  * Lipschitz: the distance changes at most L·|Δt|, so min >= (dLo + dHi − L (hi − lo)) / 2;
///  * separating direction: for a fixed unit n, the distance is at least the gap between the
///    primitives' projections on n, a minimum of functions linear in t (vertices move linearly),
///    hence concave: its minimum over [lo, hi] is at an end. n is the closest-point direction at
///    either end (tight for primitives sliding past each other).
template <class Pair>
double lowerBound(const Pair& pair, const SweepBounds& b, double lo, double hi, const Probe& pLo,
                  const Probe& pHi) {
    double bound = 0.5 * (pLo.distance + pHi.distance - b.lipschitz * (hi - lo));
    for (const Probe* p : {&pLo, &pHi}) {
        if (p->distance > 0) {
            bound = std::max(bound, std::min(separation(pair, p->direction, lo),
                                             separation(pair, p->direction, hi)));
        }
    }
    return bound;
}

/// Earliest time in [lo, hi] at which the distance may be <= threshold, or nullopt when it is
/// certainly above on the whole interval (precondition: pLo.distance > threshold). Branch and
/// bound on lowerBound, earliest half first. An interval that cannot be decided at the
/// resolution (or once the budget is spent) is reported as a hit at its start: conservative.
template <class Pair>
std::optional<double> refineInterval(const Pair& pair, const SweepBounds& b, int& budget, double lo,
                                     double hi, const Probe& pLo, const Probe& pHi) {
    if (lowerBound(pair, b, lo, hi, pLo, pHi) > b.threshold) {
        return std::nullopt;
    }
    const double width = hi - lo;
    if (b.lipschitz * width <= b.resolution || width <= TIME_TOLERANCE || budget <= 0) {
        return lo;
    }
    --budget;
    const double mid = 0.5 * (lo + hi);
    const Probe pMid = pair.probe(mid);
    if (const auto left = refineInterval(pair, b, budget, lo, mid, pLo, pMid)) {
        return left;
    }
    if (pMid.distance <= b.threshold) {
        return mid;
    }
    return refineInterval(pair, b, budget, mid, hi, pMid, pHi);
}

} // namespace atelier::sim::ccd
