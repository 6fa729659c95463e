#include "sim/collision/predicates/orient2d.h"

#include "sim/collision/predicates/expansion.h"

#include <cmath>
#include <limits>

namespace atelier::sim {

namespace {

using exact::Expansion;
using exact::product;
using exact::sum;

using exact::HALF_EPS;
/// Same for orient2d (ibid.: ccwerrboundA = (3 + 16ε)ε).
constexpr double ORIENT2D_BOUND = (3.0 + 16.0 * HALF_EPS) * HALF_EPS;

} // namespace

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

} // namespace atelier::sim
