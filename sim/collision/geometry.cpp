#include "sim/collision/geometry.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>

namespace atelier::sim {

namespace {

/// Machine epsilon: the spacing of doubles just above 1 (2⁻⁵²).
constexpr double MACHINE_EPS = std::numeric_limits<double>::epsilon();
/// Shewchuk's ε: the largest relative rounding error of one operation (2⁻⁵³).
constexpr double HALF_EPS = 0.5 * MACHINE_EPS;
/// Relative error bound of the floating-point orient3d determinant, as a multiple of its
/// permanent (Shewchuk 1997, "Adaptive Precision Floating-Point Arithmetic and Fast Robust
/// Geometric Predicates", §4.3: o3derrboundA = (7 + 56ε)ε).
constexpr double ORIENT3D_BOUND = (7.0 + 56.0 * HALF_EPS) * HALF_EPS;
/// Same for orient2d (ibid.: ccwerrboundA = (3 + 16ε)ε).
constexpr double ORIENT2D_BOUND = (3.0 + 16.0 * HALF_EPS) * HALF_EPS;

/// Continuous tests: tolerance added to the requested distance, relative to the scale of the
/// primitives (largest vertex offset or motion in the pair).
constexpr double CCD_RELATIVE_TOLERANCE = 1e-9;
/// Continuous tests: resolution of the conservative searches (branch and bound, advancement),
/// relative to the scale: they stop when the distance can change by less than this.
constexpr double CCD_RELATIVE_RESOLUTION = 1e-6;
/// Continuous tests: distance evaluations a branch and bound may spend before it reports a
/// (conservative) hit.
constexpr int CCD_REFINEMENT_BUDGET = 256;
/// Continuous tests with a distance: conservative advancement steps before the search switches
/// to branch and bound (advancement converges only linearly in some grazing configurations).
constexpr int CCD_ADVANCE_STEPS = 12;
/// Bound on the rounding error of the coplanarity cubic, as a multiple of machine epsilon times
/// |x|·|e₁|·|e₂| (8 triple products of at most 3 terms, 3 more roundings in Horner form; the
/// factor leaves a wide margin over the ≈ 20 that a first-order analysis gives).
constexpr double CUBIC_NOISE_FACTOR = 64.0;
/// Root-finding stops when the bracket or the Newton step is this small (fraction of the step).
constexpr double TIME_TOLERANCE = 4.0 * MACHINE_EPS;

bool isFinite(const Vec3& v) {
    return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

// ---------------------------------------------------------------------------------------------
// Closest points
// ---------------------------------------------------------------------------------------------

/// Parameter in [0, 1] of the point of segment (a, b) closest to p; 0 for a zero-length one.
double segmentParameter(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const double len2 = ab.squaredNorm();
    const double dot = (p - a).dot(ab);
    if (!(dot > 0) || !(len2 > 0)) {
        return 0.0;
    }
    if (dot >= len2) {
        return 1.0;
    }
    return dot / len2;
}

/// The triangle point with barycentric weights (u, v, w), made valid (each >= 0, sum 1).
TrianglePoint makeTrianglePoint(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                                double v, double w) {
    v = std::clamp(v, 0.0, 1.0);
    w = std::clamp(w, 0.0, 1.0);
    const double vw = v + w;
    if (vw > 1.0) {
        v /= vw;
        w /= vw;
    }
    const double u = std::max(0.0, (1.0 - v) - w);
    TrianglePoint r;
    r.bary = {u, v, w};
    r.point = u * a + v * b + w * c;
    r.distance = (p - r.point).norm();
    return r;
}

/// Closest point of the triangle's three edges to p (the whole answer for a degenerate one).
TrianglePoint closestPointOnEdges(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const double tab = segmentParameter(p, a, b);
    const double tbc = segmentParameter(p, b, c);
    const double tca = segmentParameter(p, c, a);
    TrianglePoint best = makeTrianglePoint(p, a, b, c, tab, 0.0);
    const TrianglePoint onBc = makeTrianglePoint(p, a, b, c, 1.0 - tbc, tbc);
    if (onBc.distance < best.distance) {
        best = onBc;
    }
    const TrianglePoint onCa = makeTrianglePoint(p, a, b, c, 0.0, 1.0 - tca);
    if (onCa.distance < best.distance) {
        best = onCa;
    }
    return best;
}

/// Ericson's Voronoi-region walk (Real-Time Collision Detection §5.1.5) for a non-degenerate
/// triangle with normal n = (b − a) × (c − a), |n|² = nn > 0. The interior case projects with
/// the cross-product form of the barycentrics, which keeps relative accuracy ≈ ε / sin(angle)
/// on thin triangles (the dot-product form of the book loses ε / sin²).
TrianglePoint closestPointEricson(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                                  const Vec3& n, double nn) {
    const Vec3 ab = b - a;
    const Vec3 ac = c - a;
    const Vec3 ap = p - a;
    const double d1 = ab.dot(ap);
    const double d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0) {
        return makeTrianglePoint(p, a, b, c, 0.0, 0.0); // vertex region a
    }
    const Vec3 bp = p - b;
    const double d3 = ab.dot(bp);
    const double d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3) {
        return makeTrianglePoint(p, a, b, c, 1.0, 0.0); // vertex region b
    }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) { // edge region ab
        const double den = d1 - d3;
        return makeTrianglePoint(p, a, b, c, den > 0 ? d1 / den : 0.0, 0.0);
    }
    const Vec3 cp = p - c;
    const double d5 = ab.dot(cp);
    const double d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6) {
        return makeTrianglePoint(p, a, b, c, 0.0, 1.0); // vertex region c
    }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) { // edge region ac
        const double den = d2 - d6;
        return makeTrianglePoint(p, a, b, c, 0.0, den > 0 ? d2 / den : 0.0);
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) { // edge region bc
        const double num = d4 - d3;
        const double den = num + (d5 - d6);
        const double w = den > 0 ? num / den : 0.0;
        return makeTrianglePoint(p, a, b, c, 1.0 - w, w);
    }
    // Face region: barycentrics of the projection of p onto the plane.
    const double v = ap.cross(ac).dot(n) / nn;
    const double w = ab.cross(ap).dot(n) / nn;
    return makeTrianglePoint(p, a, b, c, v, w);
}

// ---------------------------------------------------------------------------------------------
// Continuous tests
// ---------------------------------------------------------------------------------------------

/// c₀ + c₁ t + c₂ t² + c₃ t³.
struct Cubic {
    double c0 = 0;
    double c1 = 0;
    double c2 = 0;
    double c3 = 0;
    double value(double t) const { return ((c3 * t + c2) * t + c1) * t + c0; }
    double slope(double t) const { return (3.0 * c3 * t + 2.0 * c2) * t + c1; }
    bool finite() const {
        return std::isfinite(c0) && std::isfinite(c1) && std::isfinite(c2) && std::isfinite(c3);
    }
};

/// f(t) = x(t) · (e₁(t) × e₂(t)) for vectors moving linearly, x(t) = x₀ + t Δx etc.: six times
/// the signed volume of the tetrahedron they span, zero when the four points are coplanar.
Cubic tripleProductCubic(const Vec3& x0, const Vec3& dx, const Vec3& e10, const Vec3& de1,
                         const Vec3& e20, const Vec3& de2) {
    const Vec3 n0 = e10.cross(e20);
    const Vec3 n1 = e10.cross(de2) + de1.cross(e20);
    const Vec3 n2 = de1.cross(de2);
    Cubic f;
    f.c0 = x0.dot(n0);
    f.c1 = dx.dot(n0) + x0.dot(n1);
    f.c2 = dx.dot(n1) + x0.dot(n2);
    f.c3 = dx.dot(n2);
    return f;
}

/// Roots of a t² + b t + c in the open interval (0, 1), ascending; returns their count. Only
/// divides when the quotient is known to lie in [0, 1] (no overflow, no division by zero).
int quadraticRootsInUnit(double a, double b, double c, std::array<double, 2>& roots) {
    std::array<double, 2> found{};
    int count = 0;
    const auto addQuotient = [&](double num, double den) {
        if (den != 0 && std::abs(num) < std::abs(den)) {
            const double r = num / den;
            if (r > 0 && r < 1) {
                found[static_cast<std::size_t>(count++)] = r;
            }
        }
    };
    if (a == 0) {
        addQuotient(-c, b);
    } else {
        const double disc = b * b - 4.0 * a * c;
        if (disc >= 0) {
            const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
            addQuotient(q, a);
            addQuotient(c, q);
        }
    }
    if (count == 2 && found[1] < found[0]) {
        std::swap(found[0], found[1]);
    }
    if (count == 2 && found[1] == found[0]) {
        count = 1;
    }
    roots = found;
    return count;
}

/// Time in [lo, hi] at which f crosses `target`, given that g = f − target changes sign over the
/// bracket (gLo = g(lo)): Newton steps safeguarded by bisection (a step is taken only when it
/// stays in the bracket and at least halves the step before last).
double crossingTime(const Cubic& f, double target, double lo, double hi, double gLo) {
    const bool loNegative = gLo < 0;
    double t = 0.5 * (lo + hi);
    double step = hi - lo;
    double stepBefore = step;
    for (int iteration = 0; iteration < 128; ++iteration) {
        const double g = f.value(t) - target;
        if (g == 0) {
            return t;
        }
        if ((g < 0) == loNegative) {
            lo = t;
        } else {
            hi = t;
        }
        const double dg = f.slope(t);
        double next = 0.5 * (lo + hi);
        if (dg != 0 && std::abs(2.0 * g) <= std::abs(stepBefore * dg)) {
            const double newton = t - g / dg;
            if (newton > lo && newton < hi) {
                next = newton;
            }
        }
        stepBefore = step;
        step = next - t;
        if (std::abs(step) <= TIME_TOLERANCE || hi - lo <= TIME_TOLERANCE) {
            return next;
        }
        t = next;
    }
    return t;
}

/// Tolerances of the searches of a continuous test.
struct SweepBounds {
    double lipschitz = 0;  ///< bound on |d(distance)/dt| over the step [m per step]
    double threshold = 0;  ///< a time is a hit when the distance is <= this [m]
    double tolerance = 0;  ///< absolute tolerance included in `threshold` [m]
    double resolution = 0; ///< searches stop when the distance can change less than this [m]
};

/// Point of a linear motion at fraction t of the step (exact at t = 0 and t = 1).
Vec3 lerp(const Vec3& start, const Vec3& end, double t) {
    return (1.0 - t) * start + t * end;
}

/// Distance of a swept pair at one time, with the unit direction from the second primitive's
/// closest point to the first's (zero when they touch).
struct Probe {
    double distance = 0;
    Vec3 direction = Vec3::Zero();
};

/// Vertex p against triangle (a, b, c), all moving linearly over the step.
struct VertexTriangleSweep {
    Vec3 p0, p1, a0, a1, b0, b1, c0, c1;

    TrianglePoint closest(double t) const {
        return closestPointOnTriangle(lerp(p0, p1, t), lerp(a0, a1, t), lerp(b0, b1, t),
                                      lerp(c0, c1, t));
    }
    Probe probe(double t) const {
        const TrianglePoint cp = closest(t);
        Probe r;
        r.distance = cp.distance;
        if (cp.distance > 0) {
            r.direction = (lerp(p0, p1, t) - cp.point) / cp.distance;
        }
        return r;
    }
    /// n·(p − v) at t for the triangle's vertices v (the last one twice), each linear in t:
    /// their minimum bounds the distance from below for a unit n.
    std::array<double, 4> gaps(const Vec3& n, double t) const {
        const double np = n.dot(lerp(p0, p1, t));
        const double gc = np - n.dot(lerp(c0, c1, t));
        return {np - n.dot(lerp(a0, a1, t)), np - n.dot(lerp(b0, b1, t)), gc, gc};
    }
};

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

/// Tolerances of a continuous test: `offsets` are the vectors whose largest norm is the scale
/// (vertex offsets at both ends of the step and their changes) [m], `lipschitz` the largest
/// relative vertex speed [m per step].
SweepBounds sweepBounds(const std::array<Vec3, 9>& offsets, double lipschitz, double distance) {
    double scale = 0;
    for (const Vec3& v : offsets) {
        scale = std::max(scale, v.norm());
    }
    SweepBounds b;
    b.lipschitz = lipschitz;
    b.tolerance = CCD_RELATIVE_TOLERANCE * scale;
    b.threshold = distance + b.tolerance;
    // With a distance below the resolution, resolve to the distance.
    const double resolution = CCD_RELATIVE_RESOLUTION * scale;
    b.resolution =
        std::max(b.tolerance, distance > 0 ? std::min(resolution, distance) : resolution);
    return b;
}

/// Bound on the rounding error of the coplanarity cubic x(t)·(e₁(t)×e₂(t)) over t ∈ [0, 1].
double coplanarityNoise(const Vec3& x0, const Vec3& dx, const Vec3& e10, const Vec3& de1,
                        const Vec3& e20, const Vec3& de2) {
    return CUBIC_NOISE_FACTOR * MACHINE_EPS * (x0.norm() + dx.norm()) * (e10.norm() + de1.norm()) *
           (e20.norm() + de2.norm());
}

// ---------------------------------------------------------------------------------------------
// Exact predicates: expansion arithmetic (Shewchuk 1997, §2)
// ---------------------------------------------------------------------------------------------

/// x + y = a + b exactly with x = fl(a + b) (Knuth's Two-Sum; Shewchuk Theorem 7).
inline void twoSum(double a, double b, double& x, double& y) {
    x = a + b;
    const double bVirtual = x - a;
    const double aVirtual = x - bVirtual;
    y = (a - aVirtual) + (b - bVirtual);
}

/// Same as twoSum when |a| >= |b| (Dekker's Fast-Two-Sum; Shewchuk Theorem 6).
inline void fastTwoSum(double a, double b, double& x, double& y) {
    x = a + b;
    y = b - (x - a);
}

/// x + y = a · b exactly with x = fl(a · b) (the error term by a fused multiply-add).
inline void twoProduct(double a, double b, double& x, double& y) {
    x = a * b;
    y = std::fma(a, b, -x);
}

/// A floating-point expansion: the exact value is the sum of the components, which are
/// nonoverlapping, ordered by increasing magnitude and nonzero (at most N of them).
template <std::size_t N> struct Expansion {
    std::array<double, N> c; // only the first n are set (no zero fill: this is a hot path)
    std::size_t n = 0;
    /// Appends x unless it is zero (branch-free: zeros come unpredictably).
    void push(double x) {
        c[n] = x;
        n += x != 0 ? 1 : 0;
    }
    /// Sign of the exact value: that of the largest component.
    int sign() const { return n == 0 ? 0 : (c[n - 1] > 0 ? 1 : -1); }
};

/// Exact product of two doubles.
Expansion<2> product(double a, double b) {
    double hi = 0;
    double lo = 0;
    twoProduct(a, b, hi, lo);
    Expansion<2> e;
    e.push(lo);
    e.push(hi);
    return e;
}

/// Exact sum of two expansions (Fast-Expansion-Sum with zero elimination, Shewchuk Theorem 13:
/// merge by magnitude, then one Two-Sum pass; needs round-to-nearest-even, the IEEE default).
template <std::size_t A, std::size_t B>
Expansion<A + B> sum(const Expansion<A>& e, const Expansion<B>& f) {
    std::array<double, A + B> g; // merged components, the first m set
    std::size_t m = 0;
    std::size_t i = 0;
    std::size_t j = 0;
    while (i < e.n && j < f.n) { // branch-free merge: the comparisons are unpredictable
        const double x = e.c[i];
        const double y = f.c[j];
        const bool takeE = std::abs(x) < std::abs(y);
        g[m++] = takeE ? x : y;
        i += takeE ? 1 : 0;
        j += takeE ? 0 : 1;
    }
    while (i < e.n) {
        g[m++] = e.c[i++];
    }
    while (j < f.n) {
        g[m++] = f.c[j++];
    }
    Expansion<A + B> h;
    if (m == 0) {
        return h;
    }
    if (m == 1) {
        h.push(g[0]);
        return h;
    }
    double q = 0;
    double err = 0;
    fastTwoSum(g[1], g[0], q, err);
    h.push(err);
    for (std::size_t k = 2; k < m; ++k) {
        twoSum(q, g[k], q, err);
        h.push(err);
    }
    h.push(q);
    return h;
}

/// Exact product of an expansion and a double (Scale-Expansion with zero elimination,
/// Shewchuk Theorem 19).
template <std::size_t A> Expansion<2 * A> scale(const Expansion<A>& e, double b) {
    Expansion<2 * A> h;
    if (e.n == 0) {
        return h;
    }
    double q = 0;
    double err = 0;
    twoProduct(e.c[0], b, q, err);
    h.push(err);
    for (std::size_t i = 1; i < e.n; ++i) {
        double hi = 0;
        double lo = 0;
        twoProduct(e.c[i], b, hi, lo);
        double s = 0;
        twoSum(q, lo, s, err);
        h.push(err);
        fastTwoSum(hi, s, q, err);
        h.push(err);
    }
    h.push(q);
    return h;
}

/// Exact `sign` · det[x; y; z] (rows) as the sum of its six products of three coordinates.
Expansion<24> det3Exact(const Vec3& x, const Vec3& y, const Vec3& z, double sign) {
    const auto term = [&](int i, int j, int k, double s) {
        return scale(product(x[i], y[j]), s * sign * z[k]);
    };
    const Expansion<8> s01 = sum(term(0, 1, 2, 1.0), term(0, 2, 1, -1.0));
    const Expansion<8> s23 = sum(term(1, 2, 0, 1.0), term(1, 0, 2, -1.0));
    const Expansion<8> s45 = sum(term(2, 0, 1, 1.0), term(2, 1, 0, -1.0));
    return sum(sum(s01, s23), s45);
}

/// Exact sign of det[b − a, c − a, d − a]. When the nine differences are exact in floating
/// point (nearby coordinates: Sterbenz), the determinant of the differences (24 components);
/// otherwise [b,c,d] − [a,c,d] + [a,b,d] − [a,b,c] (the cofactor expansion of the 4×4
/// determinant with a column of ones, so that no subtraction of inputs is rounded; 96).
int orient3dExact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    Vec3 u;
    Vec3 v;
    Vec3 w;
    bool exact = true;
    for (int i = 0; i < 3; ++i) {
        double tail = 0;
        twoSum(b[i], -a[i], u[i], tail);
        exact = exact && tail == 0;
        twoSum(c[i], -a[i], v[i], tail);
        exact = exact && tail == 0;
        twoSum(d[i], -a[i], w[i], tail);
        exact = exact && tail == 0;
    }
    if (exact) {
        return det3Exact(u, v, w, 1.0).sign();
    }
    const Expansion<48> first = sum(det3Exact(b, c, d, 1.0), det3Exact(a, c, d, -1.0));
    const Expansion<48> second = sum(det3Exact(a, b, d, 1.0), det3Exact(a, b, c, -1.0));
    return sum(first, second).sign();
}

/// Exact sign of the 2D orientation of (a, b, c) projected along `axis` (the coordinates
/// (axis + 1) % 3 and (axis + 2) % 3 are kept): positive when counter-clockwise.
int orient2d(const Vec3& a, const Vec3& b, const Vec3& c, int axis) {
    const int i = (axis + 1) % 3;
    const int j = (axis + 2) % 3;
    const double left = (b[i] - a[i]) * (c[j] - a[j]);
    const double right = (b[j] - a[j]) * (c[i] - a[i]);
    const double det = left - right;
    const double bound = ORIENT2D_BOUND * (std::abs(left) + std::abs(right));
    if (det > bound) {
        return 1;
    }
    if (-det > bound) {
        return -1;
    }
    if (std::abs(left) + std::abs(right) == 0) {
        return 0; // every product has an exactly zero factor
    }
    // a_i b_j − a_i c_j − a_j b_i + a_j c_i + b_i c_j − b_j c_i
    const Expansion<4> s0 = sum(product(a[i], b[j]), product(-a[i], c[j]));
    const Expansion<4> s1 = sum(product(-a[j], b[i]), product(a[j], c[i]));
    const Expansion<4> s2 = sum(product(b[i], c[j]), product(-b[j], c[i]));
    return sum(sum(s0, s1), s2).sign();
}

// ---------------------------------------------------------------------------------------------
// Exact triangle–triangle intersection
// ---------------------------------------------------------------------------------------------

bool lexLess(const Vec3& p, const Vec3& q) {
    if (p.x() != q.x()) {
        return p.x() < q.x();
    }
    if (p.y() != q.y()) {
        return p.y() < q.y();
    }
    return p.z() < q.z();
}

/// Exactly collinear (or coincident) points: every coordinate projection is degenerate.
bool collinear(const Vec3& a, const Vec3& b, const Vec3& c) {
    return orient2d(a, b, c, 0) == 0 && orient2d(a, b, c, 1) == 0 && orient2d(a, b, c, 2) == 0;
}

/// Overlap of two segments known to lie on one line: along a line, lexicographic order is the
/// order of the points (in one direction or the other).
bool collinearOverlap(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) {
    const auto [p0, p1] = lexLess(q, p) ? std::pair(q, p) : std::pair(p, q);
    const auto [r0, r1] = lexLess(s, r) ? std::pair(s, r) : std::pair(r, s);
    return !lexLess(p1, r0) && !lexLess(r1, p0);
}

/// An axis along which the projection of the non-degenerate triangle (a, b, c) is
/// non-degenerate (so the projection is one-to-one on its plane), the dominant one first.
int projectionAxis(const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 n = (b - a).cross(c - a).cwiseAbs();
    std::array<int, 3> order = {0, 1, 2};
    std::sort(order.begin(), order.end(), [&](int l, int r) { return n[l] > n[r]; });
    for (int axis : order) {
        if (orient2d(a, b, c, axis) != 0) {
            return axis;
        }
    }
    return order[0];
}

/// Point p in the closed triangle (a, b, c), all in one plane that `axis` projects one-to-one.
bool pointInTriangle2d(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, int axis) {
    const int o1 = orient2d(a, b, p, axis);
    const int o2 = orient2d(b, c, p, axis);
    const int o3 = orient2d(c, a, p, axis);
    return (o1 >= 0 && o2 >= 0 && o3 >= 0) || (o1 <= 0 && o2 <= 0 && o3 <= 0);
}

/// Closed segments pq and rs (p ≠ q, r ≠ s) in one plane that `axis` projects one-to-one.
bool segmentsIntersect2d(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s, int axis) {
    const int o1 = orient2d(p, q, r, axis);
    const int o2 = orient2d(p, q, s, axis);
    if (o1 == 0 && o2 == 0) {
        return collinearOverlap(p, q, r, s);
    }
    if (o1 * o2 > 0) {
        return false;
    }
    const int o3 = orient2d(r, s, p, axis);
    const int o4 = orient2d(r, s, q, axis);
    return o3 * o4 <= 0;
}

/// Closed segment pq (p ≠ q) and non-degenerate triangle (a, b, c) in one plane.
bool coplanarSegmentTriangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                             const Vec3& c, int axis) {
    return pointInTriangle2d(p, a, b, c, axis) || pointInTriangle2d(q, a, b, c, axis) ||
           segmentsIntersect2d(p, q, a, b, axis) || segmentsIntersect2d(p, q, b, c, axis) ||
           segmentsIntersect2d(p, q, c, a, axis);
}

/// Closed segment pq (p ≠ q) and non-degenerate triangle (a, b, c); op, oq: orient3d(a, b, c, ·)
/// of p and q.
bool segmentTriangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c,
                     int op, int oq) {
    if (op * oq > 0) {
        return false;
    }
    if (op == 0 && oq == 0) {
        return coplanarSegmentTriangle(p, q, a, b, c, projectionAxis(a, b, c));
    }
    if (op == 0 || oq == 0) {
        return pointInTriangle2d(op == 0 ? p : q, a, b, c, projectionAxis(a, b, c));
    }
    // p and q strictly on both sides: the crossing point is inside iff the line pq passes on
    // the same side of (or through) all three edges.
    const int s1 = orient3d(p, q, a, b);
    const int s2 = orient3d(p, q, b, c);
    const int s3 = orient3d(p, q, c, a);
    return (s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0);
}

/// Two non-degenerate triangles in one plane.
bool coplanarTriangles(const std::array<Vec3, 3>& t, const std::array<Vec3, 3>& u) {
    const int axis = projectionAxis(t[0], t[1], t[2]);
    for (std::size_t i = 0; i < 3; ++i) {
        for (std::size_t j = 0; j < 3; ++j) {
            if (segmentsIntersect2d(t[i], t[(i + 1) % 3], u[j], u[(j + 1) % 3], axis)) {
                return true;
            }
        }
    }
    return pointInTriangle2d(t[0], u[0], u[1], u[2], axis) ||
           pointInTriangle2d(u[0], t[0], t[1], t[2], axis);
}

/// Two non-degenerate triangles. Outside the coplanar case, they meet iff an edge of one
/// meets the other: their intersection lies on the line where the planes meet, and its ends
/// are ends of the chords that each triangle cuts on that line, which are on its edges.
bool triangleTriangle(const std::array<Vec3, 3>& t, const std::array<Vec3, 3>& u) {
    std::array<int, 3> ou{}; // side of u's vertices relative to t's plane
    std::array<int, 3> ot{};
    for (std::size_t i = 0; i < 3; ++i) {
        ou[i] = orient3d(t[0], t[1], t[2], u[i]);
    }
    if ((ou[0] > 0 && ou[1] > 0 && ou[2] > 0) || (ou[0] < 0 && ou[1] < 0 && ou[2] < 0)) {
        return false;
    }
    if (ou[0] == 0 && ou[1] == 0 && ou[2] == 0) {
        return coplanarTriangles(t, u);
    }
    for (std::size_t i = 0; i < 3; ++i) {
        ot[i] = orient3d(u[0], u[1], u[2], t[i]);
    }
    if ((ot[0] > 0 && ot[1] > 0 && ot[2] > 0) || (ot[0] < 0 && ot[1] < 0 && ot[2] < 0)) {
        return false;
    }
    for (std::size_t i = 0; i < 3; ++i) {
        const std::size_t j = (i + 1) % 3;
        if (segmentTriangle(t[i], t[j], u[0], u[1], u[2], ot[i], ot[j]) ||
            segmentTriangle(u[i], u[j], t[0], t[1], t[2], ou[i], ou[j])) {
            return true;
        }
    }
    return false;
}

/// A triangle as the simplex it really is: a point, a segment (the two extreme points of
/// three collinear ones) or a proper triangle.
struct Simplex {
    int dimension = 2; ///< 0 point, 1 segment, 2 triangle
    std::array<Vec3, 3> v;
};

Simplex simplexOf(const Vec3& a, const Vec3& b, const Vec3& c) {
    Simplex s;
    s.v = {a, b, c};
    if (!collinear(a, b, c)) {
        return s;
    }
    std::sort(s.v.begin(), s.v.end(), lexLess);
    s.v[1] = s.v[2]; // extremes of collinear points in lexicographic order
    s.dimension = s.v[0] == s.v[1] ? 0 : 1;
    return s;
}

/// Closed segments pq and rs (p ≠ q, r ≠ s) in 3D.
bool segmentsIntersect(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) {
    if (orient3d(p, q, r, s) != 0) {
        return false;
    }
    const bool rOnLine = collinear(p, q, r);
    const bool sOnLine = collinear(p, q, s);
    if (rOnLine && sOnLine) {
        return collinearOverlap(p, q, r, s);
    }
    const int axis = rOnLine ? projectionAxis(p, q, s) : projectionAxis(p, q, r);
    return segmentsIntersect2d(p, q, r, s, axis);
}

/// Point r on the closed segment pq (p ≠ q).
bool pointOnSegment(const Vec3& r, const Vec3& p, const Vec3& q) {
    return collinear(p, q, r) && collinearOverlap(p, q, r, r);
}

/// Simplices with dimension(s) >= dimension(t).
bool simplicesIntersect(const Simplex& s, const Simplex& t) {
    const auto& a = s.v;
    const auto& b = t.v;
    switch (s.dimension * 3 + t.dimension) {
    case 0: // point, point
        return a[0] == b[0];
    case 3: // segment, point
        return pointOnSegment(b[0], a[0], a[1]);
    case 4: // segment, segment
        return segmentsIntersect(a[0], a[1], b[0], b[1]);
    case 6: // triangle, point
        return orient3d(a[0], a[1], a[2], b[0]) == 0 &&
               pointInTriangle2d(b[0], a[0], a[1], a[2], projectionAxis(a[0], a[1], a[2]));
    case 7: // triangle, segment
        return segmentTriangle(b[0], b[1], a[0], a[1], a[2], orient3d(a[0], a[1], a[2], b[0]),
                               orient3d(a[0], a[1], a[2], b[1]));
    default: // triangle, triangle
        return triangleTriangle(a, b);
    }
}

} // namespace

// ---------------------------------------------------------------------------------------------
// Public functions
// ---------------------------------------------------------------------------------------------

TrianglePoint closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 n = (b - a).cross(c - a);
    const double nn = n.squaredNorm();
    const double longest2 =
        std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), (c - b).squaredNorm()});
    // sin² of the largest angle is at least nn / longest2²: below 1e-30 (sin 1e-15) the
    // triangle is a segment to the working precision, and thin ones (sin < 1e-3) compare the
    // face answer with the edges' (the walk's region tests lose accuracy there).
    if (!(nn > 1e-30 * longest2 * longest2)) {
        return closestPointOnEdges(p, a, b, c);
    }
    const TrianglePoint face = closestPointEricson(p, a, b, c, n, nn);
    if (nn < 1e-6 * longest2 * longest2) {
        const TrianglePoint edges = closestPointOnEdges(p, a, b, c);
        return edges.distance < face.distance ? edges : face;
    }
    return face;
}

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
            const SegmentPoints inner = make(sNum / nn, tNum / nn);
            // Clearly non-parallel: the critical point is the minimum.
            if (nn > 1e-8 * d1.squaredNorm() * d2.squaredNorm()) {
                return inner;
            }
            SegmentPoints best = inner;
            for (const SegmentPoints& r :
                 {make(0.0, segmentParameter(p0, q0, q1)), make(1.0, segmentParameter(p1, q0, q1)),
                  make(segmentParameter(q0, p0, p1), 0.0),
                  make(segmentParameter(q1, p0, p1), 1.0)}) {
                if (r.distance < best.distance) {
                    best = r;
                }
            }
            return best;
        }
    }
    // Otherwise the minimum is on the boundary of [0, 1]²: one endpoint against the other
    // segment.
    SegmentPoints best = make(0.0, segmentParameter(p0, q0, q1));
    for (const SegmentPoints& r :
         {make(1.0, segmentParameter(p1, q0, q1)), make(segmentParameter(q0, p0, p1), 0.0),
          make(segmentParameter(q1, p0, p1), 1.0)}) {
        if (r.distance < best.distance) {
            best = r;
        }
    }
    return best;
}

// Continuous tests. Positions move linearly over the step. `scale` is the largest vertex offset
// from the first vertex (a, resp. pa) at either end of the step, or the largest change of one
// over the step; tol = 1e-9 · scale; res = 1e-6 · scale (for distance > 0: min(res, distance),
// and at least tol); L = the largest relative speed of a vertex pair [m per step], which bounds
// how fast the distance can change. What is guaranteed:
//  * Never a missed contact: if the distance is <= `distance` at some τ in [0, 1] (for
//    distance 0: the vertex is in the closed triangle, the closed segments meet), a hit is
//    reported with time <= τ (+ 1e-15, the root finding's accuracy).
//  * Never a hit far from proximity: at the reported time the distance is <= `distance` + tol,
//    or <= `distance` + tol + res where a search stopped at its resolution (below). Only after
//    a search spends its budget (256 evaluations; not seen in the randomized tests) can a hit
//    be farther: a conservative answer.
//  * Nothing earlier: with distance > 0, the distance exceeds `distance` + tol at every time
//    before the reported one; with distance 0 the same holds up to 1e-15 in time.
// How:
//  * distance 0: contact needs coplanarity, so τ is a root of the cubic f(t) = x(t)·(e₁(t) ×
//    e₂(t)) (six times the signed volume of the four points). f is split into monotone pieces
//    at the roots of f'; on each piece, the band of times where |f| <= 2 × (a bound on its
//    rounding error) is examined in time order: when the primitives move less than tol/2
//    across it (a well-conditioned root), by one distance evaluation at its start; otherwise
//    (motion in the plane, nearly parallel edges, grazing motion, degenerate primitives) by
//    branch and bound on lower bounds of the distance (the Lipschitz bound L and a separating
//    direction, see lowerBound), to the resolution res.
//  * distance > 0: conservative advancement from t = 0 (each step jumps to the first time at
//    which the distance may have dropped to `distance` + tol, by the same lower bounds),
//    stopping within res of it; after 12 steps, branch and bound on the rest of the step.
std::optional<SweptHit> sweptVertexTriangle(const Vec3& p0, const Vec3& p1, const Vec3& a0,
                                            const Vec3& a1, const Vec3& b0, const Vec3& b1,
                                            const Vec3& c0, const Vec3& c1, double distance) {
    if (!(isFinite(p0) && isFinite(p1) && isFinite(a0) && isFinite(a1) && isFinite(b0) &&
          isFinite(b1) && isFinite(c0) && isFinite(c1))) {
        return std::nullopt;
    }
    distance = distance > 0 && std::isfinite(distance) ? distance : 0.0;
    const Vec3 x0 = p0 - a0;
    const Vec3 x1 = p1 - a1;
    const Vec3 e10 = b0 - a0;
    const Vec3 e11 = b1 - a1;
    const Vec3 e20 = c0 - a0;
    const Vec3 e21 = c1 - a1;
    const Vec3 dx = x1 - x0;
    const Vec3 de1 = e11 - e10;
    const Vec3 de2 = e21 - e20;
    // The speed of p relative to any point of the triangle is at most that relative to one of
    // its vertices.
    const double lipschitz = std::max({dx.norm(), (dx - de1).norm(), (dx - de2).norm()});
    const SweepBounds bounds =
        sweepBounds({x0, x1, e10, e11, e20, e21, dx, de1, de2}, lipschitz, distance);
    const VertexTriangleSweep pair{p0, p1, a0, a1, b0, b1, c0, c1};
    const std::optional<double> time =
        distance > 0 ? firstProximity(pair, bounds)
                     : earliestContact(pair, tripleProductCubic(x0, dx, e10, de1, e20, de2),
                                       coplanarityNoise(x0, dx, e10, de1, e20, de2), bounds);
    if (!time) {
        return std::nullopt;
    }
    return SweptHit{*time, pair.closest(*time).bary};
}

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

int orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    // Stage A of Shewchuk's adaptive predicate: the rounded determinant decides when it exceeds
    // the error bound, a multiple of the permanent (same products, absolute values).
    const double ux = b.x() - a.x();
    const double uy = b.y() - a.y();
    const double uz = b.z() - a.z();
    const double vx = c.x() - a.x();
    const double vy = c.y() - a.y();
    const double vz = c.z() - a.z();
    const double wx = d.x() - a.x();
    const double wy = d.y() - a.y();
    const double wz = d.z() - a.z();
    const double vywz = vy * wz;
    const double vzwy = vz * wy;
    const double vzwx = vz * wx;
    const double vxwz = vx * wz;
    const double vxwy = vx * wy;
    const double vywx = vy * wx;
    const double det = ux * (vywz - vzwy) + uy * (vzwx - vxwz) + uz * (vxwy - vywx);
    const double permanent = std::abs(ux) * (std::abs(vywz) + std::abs(vzwy)) +
                             std::abs(uy) * (std::abs(vzwx) + std::abs(vxwz)) +
                             std::abs(uz) * (std::abs(vxwy) + std::abs(vywx));
    const double bound = ORIENT3D_BOUND * permanent;
    if (det > bound) {
        return 1;
    }
    if (-det > bound) {
        return -1;
    }
    if (permanent == 0) {
        // Each product has a factor that is exactly zero (a rounded difference is zero only
        // when the inputs are equal), so the exact determinant is zero.
        return 0;
    }
    return orient3dExact(a, b, c, d);
}

bool trianglesIntersect(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0,
                        const Vec3& b1, const Vec3& b2) {
    // Cheap rejection on bounding boxes (exact comparisons).
    const Vec3 aLo = a0.cwiseMin(a1).cwiseMin(a2);
    const Vec3 aHi = a0.cwiseMax(a1).cwiseMax(a2);
    const Vec3 bLo = b0.cwiseMin(b1).cwiseMin(b2);
    const Vec3 bHi = b0.cwiseMax(b1).cwiseMax(b2);
    if ((aHi.array() < bLo.array()).any() || (bHi.array() < aLo.array()).any()) {
        return false;
    }
    const Simplex s = simplexOf(a0, a1, a2);
    const Simplex t = simplexOf(b0, b1, b2);
    return s.dimension >= t.dimension ? simplicesIntersect(s, t) : simplicesIntersect(t, s);
}

} // namespace atelier::sim
