#pragma once
/// The coplanarity cubic of four linearly moving points and its roots: where a vertex–triangle
/// or edge–edge pair can touch (distance 0), up to a bound on its rounding error.

#include "sim/core/types.h"

#include <array>
#include <cmath>

namespace atelier::sim::ccd {

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
                         const Vec3& e20, const Vec3& de2);

/// Bound on the rounding error of the coplanarity cubic x(t)·(e₁(t)×e₂(t)) over t ∈ [0, 1].
double coplanarityNoise(const Vec3& x0, const Vec3& dx, const Vec3& e10, const Vec3& de1,
                        const Vec3& e20, const Vec3& de2);

/// Roots of a t² + b t + c in the open interval (0, 1), ascending; returns their count. Only
/// divides when the quotient is known to lie in [0, 1] (no overflow, no division by zero).
int quadraticRootsInUnit(double a, double b, double c, std::array<double, 2>& roots);

/// Time in [lo, hi] at which f crosses `target`, given that g = f − target changes sign over the
/// bracket (gLo = g(lo)): Newton steps safeguarded by bisection (a step is taken only when it
/// stays in the bracket and at least halves the step before last).
double crossingTime(const Cubic& f, double target, double lo, double hi, double gLo);

} // namespace atelier::sim::ccd
