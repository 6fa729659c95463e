#include "sim/collision/predicates/orient3d.h"

#include "sim/collision/predicates/expansion.h"

#include <cmath>
#include <limits>

namespace atelier::sim {

namespace {

using exact::Expansion;
using exact::product;
using exact::scale;
using exact::sum;
using exact::twoSum;

using exact::HALF_EPS;
/// Relative error bound of the floating-point orient3d determinant, as a multiple of its
/// permanent (Shewchuk 1997, "Adaptive Precision Floating-Point Arithmetic and Fast Robust
/// Geometric Predicates", §4.3: o3derrboundA = (7 + 56ε)ε).
constexpr double ORIENT3D_BOUND = (7.0 + 56.0 * HALF_EPS) * HALF_EPS;

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

} // namespace

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

} // namespace atelier::sim
