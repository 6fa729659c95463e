#include "sim/collision/ccd/coplanarity_cubic.h"

#include "sim/collision/ccd/ccd_tolerances.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cstddef>
#include <utility>

namespace atelier::sim::ccd {

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

double coplanarityNoise(const Vec3& x0, const Vec3& dx, const Vec3& e10, const Vec3& de1,
                        const Vec3& e20, const Vec3& de2) {
    return CUBIC_NOISE_FACTOR * MACHINE_EPS * (x0.norm() + dx.norm()) * (e10.norm() + de1.norm()) *
           (e20.norm() + de2.norm());
}

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

} // namespace atelier::sim::ccd
