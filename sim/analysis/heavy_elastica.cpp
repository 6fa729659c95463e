#include "sim/analysis/heavy_elastica.h"

#include <array>
#include <cmath>

namespace atelier::sim {

namespace {

/// State (θ, θ', x, y) in units of L, integrated from u = 0 to 1 for θ'(0) = a.
using State = std::array<double, 4>;

State derivative(const State& s, double u, double lambda) {
    return {s[1], -lambda * (1.0 - u) * std::cos(s[0]), std::cos(s[0]), std::sin(s[0])};
}

State integrate(double lambda, double rootCurvature, int steps) {
    State s{0.0, rootCurvature, 0.0, 0.0};
    const double h = 1.0 / steps;
    const auto axpy = [](const State& a, double t, const State& b) {
        return State{a[0] + t * b[0], a[1] + t * b[1], a[2] + t * b[2], a[3] + t * b[3]};
    };
    for (int i = 0; i < steps; ++i) {
        const double u = i * h;
        const State k1 = derivative(s, u, lambda);
        const State k2 = derivative(axpy(s, 0.5 * h, k1), u + 0.5 * h, lambda);
        const State k3 = derivative(axpy(s, 0.5 * h, k2), u + 0.5 * h, lambda);
        const State k4 = derivative(axpy(s, h, k3), u + h, lambda);
        for (std::size_t c = 0; c < 4; ++c) {
            s[c] += h / 6.0 * (k1[c] + 2.0 * k2[c] + 2.0 * k3[c] + k4[c]);
        }
    }
    return s;
}

} // namespace

HeavyElastica solveHeavyElastica(double lambda, int steps) {
    HeavyElastica r;
    r.lambda = lambda;
    r.tipX = 1.0;
    if (!std::isfinite(lambda) || steps < 1) {
        return r;
    }
    if (!(lambda > 0)) {
        r.converged = true;
        return r;
    }
    double lo = 0.0;
    double hi = 0.5 * lambda;
    State tip = integrate(lambda, hi, steps);
    for (int it = 0; it < 200 && hi - lo > 1e-15 * (1.0 + hi); ++it) {
        const double mid = 0.5 * (lo + hi);
        const State s = integrate(lambda, mid, steps);
        if (s[1] > 0) {
            hi = mid;
            tip = s;
        } else {
            lo = mid;
        }
    }
    r.rootCurvature = hi;
    r.tipSlope = tip[0];
    r.tipX = tip[2];
    r.tipDrop = tip[3];
    r.tipLineAngle = std::atan2(tip[3], tip[2]);
    r.converged = std::abs(tip[1]) < 1e-12 * (1.0 + lambda);
    return r;
}

} // namespace atelier::sim
