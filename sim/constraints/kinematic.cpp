#include "sim/constraints/kinematic.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace atelier::sim {

PathSample samplePath(const Drive& d, double t) {
    const std::size_t n = d.times.size();
    if (n == 0) {
        return {Vec3::Zero(), Vec3::Zero()};
    }
    if (n == 1 || t < d.times.front()) {
        return {d.positions.front(), Vec3::Zero()};
    }
    if (t >= d.times.back()) {
        return {d.positions.back(), Vec3::Zero()};
    }
    // Segment k with times[k] <= t < times[k+1].
    const auto it = std::upper_bound(d.times.begin(), d.times.end(), t);
    const std::size_t k = static_cast<std::size_t>(it - d.times.begin()) - 1;
    const double t0 = d.times[k];
    const double t1 = d.times[k + 1];
    const double span = t1 - t0;
    const Vec3 vel = span > 0 ? Vec3((d.positions[k + 1] - d.positions[k]) / span) : Vec3::Zero();
    const double s = span > 0 ? (t - t0) / span : 1.0;
    return {d.positions[k] + s * (d.positions[k + 1] - d.positions[k]), vel};
}

double nextPathEvent(const Drive& d, double t) {
    double next = std::numeric_limits<double>::infinity();
    for (double key : d.times) {
        if (key > t) {
            next = key;
            break;
        }
    }
    if (d.releaseTime > t) {
        next = std::min(next, d.releaseTime);
    }
    return next;
}

void applyHighDamping(const std::vector<std::array<int, 2>>& edges, const VecX& invMass, double h,
                      double timeConstant, MatX3& v) {
    if (timeConstant <= 0) {
        return;
    }
    const double keep = std::exp(-h / timeConstant);
    for (const auto& e : edges) {
        const double wi = invMass[e[0]];
        const double wj = invMass[e[1]];
        const double w = wi + wj;
        if (w <= 0) {
            continue;
        }
        const Vec3 r = v.row(e[1]) - v.row(e[0]);
        const Vec3 dr = (1.0 - keep) * r; // remove this much relative velocity
        // Impulse p along dr: Δv_i = w_i p, Δv_j = -w_j p, with (w_i + w_j) p = dr.
        const Vec3 p = dr / w;
        v.row(e[0]) += (wi * p).transpose();
        v.row(e[1]) -= (wj * p).transpose();
    }
}

} // namespace atelier::sim
