#include "sim/integrators/explicit_rk.h"

#include "sim/core/parallel.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace atelier::sim {

const ButcherTableau& ButcherTableau::euler() {
    static const ButcherTableau t{{0.0}, {{}}, {1.0}, {}, 1};
    return t;
}

const ButcherTableau& ButcherTableau::midpoint() {
    static const ButcherTableau t{{0.0, 0.5}, {{}, {0.5}}, {0.0, 1.0}, {}, 2};
    return t;
}

const ButcherTableau& ButcherTableau::rk4() {
    static const ButcherTableau t{{0.0, 0.5, 0.5, 1.0},
                                  {{}, {0.5}, {0.0, 0.5}, {0.0, 0.0, 1.0}},
                                  {1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6},
                                  {},
                                  4};
    return t;
}

const ButcherTableau& ButcherTableau::cashKarp() {
    static const ButcherTableau t{
        {0.0, 1.0 / 5, 3.0 / 10, 3.0 / 5, 1.0, 7.0 / 8},
        {{},
         {1.0 / 5},
         {3.0 / 40, 9.0 / 40},
         {3.0 / 10, -9.0 / 10, 6.0 / 5},
         {-11.0 / 54, 5.0 / 2, -70.0 / 27, 35.0 / 27},
         {1631.0 / 55296, 175.0 / 512, 575.0 / 13824, 44275.0 / 110592, 253.0 / 4096}},
        {37.0 / 378, 0.0, 250.0 / 621, 125.0 / 594, 0.0, 512.0 / 1771},
        {2825.0 / 27648, 0.0, 18575.0 / 48384, 13525.0 / 55296, 277.0 / 14336, 1.0 / 4},
        5};
    return t;
}

double ExplicitRkStepper::step(double t, double h, const MatX3& x, const MatX3& v,
                               const AccelerationFn& acc, MatX3& xOut, MatX3& vOut, MatX3* firstAcc,
                               double velocityErrorTime) {
    const std::size_t s = m_tab.b.size();
    const Eigen::Index n = x.rows();
    if (m_kx.size() != s || (s > 0 && m_kx[0].rows() != n)) {
        m_kx.assign(s, MatX3::Zero(n, 3));
        m_kv.assign(s, MatX3::Zero(n, 3));
        m_xs.resize(n, 3);
        m_vs.resize(n, 3);
    }
    for (std::size_t i = 0; i < s; ++i) {
        if (i == 0) {
            m_kx[0] = v;
            acc(t, x, v, m_kv[0]);
            if (firstAcc != nullptr) {
                *firstAcc = m_kv[0];
            }
            continue;
        }
        m_xs = x;
        m_vs = v;
        const auto& ai = m_tab.a[i];
        for (std::size_t j = 0; j < ai.size(); ++j) {
            if (ai[j] != 0.0) {
                m_xs.noalias() += (h * ai[j]) * m_kx[j];
                m_vs.noalias() += (h * ai[j]) * m_kv[j];
            }
        }
        m_kx[i] = m_vs;
        acc(t + m_tab.c[i] * h, m_xs, m_vs, m_kv[i]);
    }
    xOut = x;
    vOut = v;
    for (std::size_t j = 0; j < s; ++j) {
        if (m_tab.b[j] != 0.0) {
            xOut.noalias() += (h * m_tab.b[j]) * m_kx[j];
            vOut.noalias() += (h * m_tab.b[j]) * m_kv[j];
        }
    }
    if (m_tab.bEmbedded.empty()) {
        return 0.0;
    }
    // Difference between the two solutions: h Σ (b_j - b*_j) k_j.
    m_xs.setZero();
    m_vs.setZero();
    for (std::size_t j = 0; j < s; ++j) {
        const double db = m_tab.b[j] - m_tab.bEmbedded[j];
        if (db != 0.0) {
            m_xs.noalias() += (h * db) * m_kx[j];
            m_vs.noalias() += (h * db) * m_kv[j];
        }
    }
    const double ex = m_xs.rowwise().norm().maxCoeff();
    const double ev = velocityErrorTime * m_vs.rowwise().norm().maxCoeff();
    const double e = std::max(ex, ev);
    return std::isfinite(e) ? e : std::numeric_limits<double>::infinity();
}

} // namespace atelier::sim
