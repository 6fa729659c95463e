#pragma once
/// The distance 0 case of the continuous tests: the earliest contact of a swept pair, at a root
/// of its coplanarity cubic, examined where rounding leaves the root uncertain.

#include "sim/collision/ccd/ccd_tolerances.h"
#include "sim/collision/ccd/coplanarity_cubic.h"
#include "sim/collision/ccd/sweep_bounds.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <optional>

namespace atelier::sim::ccd {

/// Contacts in one piece [lo, hi] of [0, 1] on which the cubic is monotone: the only place where
/// the exact f can vanish is the band of times where the computed |f| <= `band` (twice its
/// rounding error bound). A well-conditioned root (the primitives move less than tol / 2 across
/// its band) is checked at the start of its band; otherwise the whole band is searched.
template <class Pair>
std::optional<double> pieceContact(const Pair& pair, const Cubic& f, double band,
                                   const SweepBounds& b, int& budget, double lo, double hi,
                                   double fLo, double fHi) {
    if (std::min(fLo, fHi) > band || std::max(fLo, fHi) < -band) {
        return std::nullopt;
    }
    // Fast path: the band is about band / slope on either side of the computed root. If f is
    // beyond ±band (on the right sides) at twice that, the band lies inside [t1, t2]: every
    // exact root does (f is monotone and |f − computed f| <= band / 2), and one distance
    // evaluation at t1 decides when the primitives move <= tol / 2 across it. |f'| on the
    // piece is largest at an end or at the inflection point: when even that is too small, f is
    // flat to the noise and the root is not worth finding.
    const auto steepEnough = [&](double slope) {
        return 8.0 * b.lipschitz * band <= b.tolerance * slope && band < slope;
    };
    double maxSlope = std::max(std::abs(f.slope(lo)), std::abs(f.slope(hi)));
    if (std::abs(f.c2) < std::abs(3.0 * f.c3)) {
        const double inflection = -f.c2 / (3.0 * f.c3);
        if (inflection > lo && inflection < hi) {
            maxSlope = std::max(maxSlope, std::abs(f.slope(inflection)));
        }
    }
    if (((fLo < 0 && fHi > 0) || (fLo > 0 && fHi < 0)) && steepEnough(maxSlope)) {
        const double root = crossingTime(f, 0.0, lo, hi, fLo);
        const double slope = std::abs(f.slope(root));
        if (steepEnough(slope)) {
            const double halfWidth = band / slope;
            const double t1 = std::max(lo, root - 2.0 * halfWidth);
            const double t2 = std::min(hi, root + 2.0 * halfWidth);
            const double f1 = f.value(t1);
            const double f2 = f.value(t2);
            const bool before = t1 == lo || (std::abs(f1) > band && (f1 < 0) == (fLo < 0));
            const bool after = t2 == hi || (std::abs(f2) > band && (f2 < 0) == (fHi < 0));
            if (before && after && b.lipschitz * (t2 - t1) <= 0.5 * b.tolerance) {
                if (pair.probe(t1).distance <= b.threshold) {
                    return t1;
                }
                return std::nullopt;
            }
        }
    }
    // Otherwise the band [u0, u1] where |f| <= band.
    double u0 = lo;
    double u1 = hi;
    if (fHi >= fLo) {
        if (fLo < -band) {
            u0 = crossingTime(f, -band, lo, hi, fLo + band);
        }
        if (fHi > band) {
            u1 = crossingTime(f, band, lo, hi, fLo - band);
        }
    } else {
        if (fLo > band) {
            u0 = crossingTime(f, band, lo, hi, fLo - band);
        }
        if (fHi < -band) {
            u1 = crossingTime(f, -band, lo, hi, fLo + band);
        }
    }
    u1 = std::max(u0, u1);
    const Probe p0 = pair.probe(u0);
    if (p0.distance <= b.threshold) {
        return u0;
    }
    if (b.lipschitz * (u1 - u0) <= 0.5 * b.tolerance) {
        return std::nullopt;
    }
    return refineInterval(pair, b, budget, u0, u1, p0, pair.probe(u1));
}

/// Earliest contact (the distance 0 case) of a pair whose coplanarity cubic is f, computed with
/// rounding error <= noise: f is split into monotone pieces at the roots of f', and the pieces'
/// ends (where |f| is within the band) and bands are examined in time order. See the comment
/// above sweptVertexTriangle.
template <class Pair>
std::optional<double> earliestContact(const Pair& pair, const Cubic& f, double noise,
                                      const SweepBounds& b) {
    if (!f.finite() || !std::isfinite(noise)) {
        return std::nullopt;
    }
    std::array<double, 4> splits{};
    std::size_t count = 0;
    splits[count++] = 0.0;
    std::array<double, 2> extrema{};
    const int extremaCount = quadraticRootsInUnit(3.0 * f.c3, 2.0 * f.c2, f.c1, extrema);
    for (int i = 0; i < extremaCount; ++i) {
        splits[count++] = extrema[static_cast<std::size_t>(i)];
    }
    splits[count++] = 1.0;
    std::array<double, 4> values{};
    for (std::size_t i = 0; i < count; ++i) {
        values[i] = f.value(splits[i]);
    }
    const double band = 2.0 * noise;
    const auto splitHit = [&](std::size_t i) {
        return std::abs(values[i]) <= band && pair.probe(splits[i]).distance <= b.threshold;
    };
    int budget = CCD_REFINEMENT_BUDGET;
    for (std::size_t k = 0; k + 1 < count; ++k) {
        if (splitHit(k)) {
            return splits[k];
        }
        if (const auto t = pieceContact(pair, f, band, b, budget, splits[k], splits[k + 1],
                                        values[k], values[k + 1])) {
            return t;
        }
    }
    if (splitHit(count - 1)) {
        return 1.0;
    }
    return std::nullopt;
}

} // namespace atelier::sim::ccd
