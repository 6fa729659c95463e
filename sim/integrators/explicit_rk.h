#pragma once
/// Explicit Runge–Kutta steps (Euler, midpoint, RK4, Cash–Karp 4(5)) for x' = v, v' = a(t, x, v).

#include "sim/core/types.h"

#include <functional>
#include <vector>

namespace atelier::sim {

/// Butcher tableau of an explicit method, optionally with an embedded lower-order weight row.
struct ButcherTableau {
    std::vector<double> c;              ///< (s) stage times
    std::vector<std::vector<double>> a; ///< (s×s) strictly lower triangular
    std::vector<double> b;              ///< (s) weights of the propagated solution
    std::vector<double> bEmbedded;      ///< (s) weights of the error-estimating solution, or empty
    int order = 1;                      ///< order of the propagated solution

    static const ButcherTableau& euler();
    static const ButcherTableau& midpoint();
    static const ButcherTableau& rk4();
    /// Cash & Karp 1990, as in Numerical Recipes 2nd ed. §16.2: 5th-order solution propagated
    /// (local extrapolation), embedded 4th-order for the error estimate.
    static const ButcherTableau& cashKarp();
};

/// a(t, x, v) → acc, all (|V|×3).
using AccelerationFn = std::function<void(double t, const MatX3& x, const MatX3& v, MatX3& acc)>;

/// One explicit Runge–Kutta step with a reusable workspace (no allocation after the first step
/// at a given size).
class ExplicitRkStepper {
  public:
    explicit ExplicitRkStepper(const ButcherTableau& tableau) : m_tab(tableau) {}

    /// Advances (x, v) from t by h into (xOut, vOut). When the tableau has an embedded row,
    /// returns the error estimate max_i max(|Δx_i|, T·|Δv_i|) [m] (difference of the two
    /// solutions, velocities weighted by the time scale `velocityErrorTime` T [s]); otherwise 0.
    /// `firstAcc`, if non-null, receives the acceleration at (t, x, v).
    double step(double t, double h, const MatX3& x, const MatX3& v, const AccelerationFn& acc,
                MatX3& xOut, MatX3& vOut, MatX3* firstAcc = nullptr,
                double velocityErrorTime = 0.01);

    int stages() const { return static_cast<int>(m_tab.b.size()); }
    const ButcherTableau& tableau() const { return m_tab; }

  private:
    const ButcherTableau& m_tab;
    std::vector<MatX3> m_kx; ///< stage velocities
    std::vector<MatX3> m_kv; ///< stage accelerations
    MatX3 m_xs;
    MatX3 m_vs;
};

} // namespace atelier::sim
