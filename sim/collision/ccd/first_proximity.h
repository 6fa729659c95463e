#pragma once
/// The distance > 0 case of the continuous tests: conservative advancement to the first time a
/// swept pair may come within the distance.

#include "sim/collision/ccd/ccd_tolerances.h"
#include "sim/collision/ccd/sweep_bounds.h"

#include <algorithm>
#include <optional>

namespace atelier::sim::ccd {

/// First time at which the distance may be <= threshold (the distance > 0 case), by
/// conservative advancement: from a probe at t with gap g = distance − threshold, no proximity
/// can happen before max(t + g / L, the time at which the separation along the probe's
/// direction reaches the threshold). Stops at a time whose distance is within the resolution
/// above the threshold (a hit, conservative by at most the resolution); after
/// CCD_ADVANCE_STEPS steps the rest of the step is searched by branch and bound. nullopt when
/// the step ends first.
template <class Pair> std::optional<double> firstProximity(const Pair& pair, const SweepBounds& b) {
    double t = 0.0;
    Probe p = pair.probe(t);
    for (int step = 0; step < CCD_ADVANCE_STEPS; ++step) {
        const double gap = p.distance - b.threshold;
        if (gap <= b.resolution) {
            return t;
        }
        double next = b.lipschitz * (1.0 - t) > gap ? t + gap / b.lipschitz : 2.0;
        next = std::max(next, separationExit(pair, p.direction, t, b.threshold));
        if (next > 1.0) {
            return std::nullopt;
        }
        t = next;
        p = pair.probe(t);
    }
    if (p.distance - b.threshold <= b.resolution) {
        return t;
    }
    int budget = CCD_REFINEMENT_BUDGET;
    return refineInterval(pair, b, budget, t, 1.0, p, pair.probe(1.0));
}

} // namespace atelier::sim::ccd
