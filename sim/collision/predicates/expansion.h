#pragma once
/// Floating-point expansion arithmetic (Shewchuk 1997, "Adaptive Precision Floating-Point
/// Arithmetic and Fast Robust Geometric Predicates", §2): sums and products of doubles kept
/// exactly as a sum of nonoverlapping doubles, for the exact fallbacks of the predicates.

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

namespace atelier::sim::exact {

/// Shewchuk's ε: the largest relative rounding error of one operation (2⁻⁵³).
inline constexpr double HALF_EPS = 0.5 * std::numeric_limits<double>::epsilon();

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
inline Expansion<2> product(double a, double b) {
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

} // namespace atelier::sim::exact
