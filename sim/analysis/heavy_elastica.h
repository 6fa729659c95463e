#pragma once
/// The heavy elastica: a straight strip clamped horizontally at one end and bent by its own
/// weight (Peirce's cantilever, the basis of ASTM D1388), solved exactly as a boundary-value
/// problem. The reference the cantilever benchmark measures the engine against.

namespace atelier::sim {

/// Shape of a heavy cantilever at equilibrium, for λ = ρgL³/B (ρg the weight per area
/// [N/m²], L the overhang [m], B the bending rigidity per width [N·m]). Lengths are in units
/// of L.
struct HeavyElastica {
    double lambda = 0;        ///< ρgL³/B [-]
    double rootCurvature = 0; ///< θ'(0)·L: the clamp's curvature [-]
    double tipSlope = 0;      ///< θ(L): the tip's slope below the horizontal [rad]
    double tipX = 0;          ///< horizontal reach of the tip / L [-]
    double tipDrop = 0;       ///< vertical deflection of the tip / L [-]
    /// Angle below the horizontal of the line from the clamp to the tip [rad] (the angle
    /// ASTM D1388 reads off: 41.5° at λ = 8).
    double tipLineAngle = 0;
    bool converged = false; ///< the shooting found θ'(L) = 0 to 1e-12
};

/// Solves, with θ(s) the slope below the horizontal at arc length s,
/// \f[ \theta''(s) = -\frac{\rho g}{B}(L - s)\cos\theta(s),\qquad \theta(0) = 0,\quad
///     \theta'(L) = 0 \f]
/// (the moment B·θ' balances the weight beyond s), by shooting on θ'(0): fourth-order
/// Runge–Kutta over `steps` intervals for θ, x = ∫cos θ, y = ∫sin θ, and bisection on
/// θ'(0) ∈ [0, λ/2] (θ'(L) grows monotonically with θ'(0) while θ < π/2, and λ/2 is the
/// unbent beam's root moment). λ ≤ 0 or not finite gives the straight strip, not converged
/// when not finite.
HeavyElastica solveHeavyElastica(double lambda, int steps = 2000);

} // namespace atelier::sim
