#pragma once
/// Tolerances, budgets and rounding bounds of the continuous tests (sweptVertexTriangle,
/// sweptEdgeEdge); internal to ccd/.

#include <limits>

namespace atelier::sim::ccd {

/// Machine epsilon: the spacing of doubles just above 1 (2⁻⁵²).
inline constexpr double MACHINE_EPS = std::numeric_limits<double>::epsilon();
/// Continuous tests: tolerance added to the requested distance, relative to the scale of the
/// primitives (largest vertex offset or motion in the pair).
inline constexpr double CCD_RELATIVE_TOLERANCE = 1e-9;
/// Continuous tests: resolution of the conservative searches (branch and bound, advancement),
/// relative to the scale: they stop when the distance can change by less than this.
inline constexpr double CCD_RELATIVE_RESOLUTION = 1e-6;
/// Continuous tests: distance evaluations a branch and bound may spend before it reports a
/// (conservative) hit.
inline constexpr int CCD_REFINEMENT_BUDGET = 256;
/// Continuous tests with a distance: conservative advancement steps before the search switches
/// to branch and bound (advancement converges only linearly in some grazing configurations).
inline constexpr int CCD_ADVANCE_STEPS = 12;
/// Bound on the rounding error of the coplanarity cubic, as a multiple of machine epsilon times
/// |x|·|e₁|·|e₂| (8 triple products of at most 3 terms, 3 more roundings in Horner form; the
/// factor leaves a wide margin over the ≈ 20 that a first-order analysis gives).
inline constexpr double CUBIC_NOISE_FACTOR = 64.0;
/// Root-finding stops when the bracket or the Newton step is this small (fraction of the step).
inline constexpr double TIME_TOLERANCE = 4.0 * MACHINE_EPS;

} // namespace atelier::sim::ccd
