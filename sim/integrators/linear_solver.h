#pragma once
/// Choice of the implicit solve's preconditioner (sim::IntegratorOptions, sim::FilteredCg).

#include <array>
#include <optional>
#include <string_view>

namespace atelier::sim {

/// The preconditioner of the implicit solve's conjugate gradients
/// (docs/decisions/019-linear-solver.md).
enum class LinearSolver {
    /// Inverse of each unknown's 3×3 diagonal block: cheap per iteration, but the iterations
    /// grow with the stiffness-to-mass ratio (about 290 a step on the 20 mm cotton skirt).
    BlockJacobi,
    /// Block incomplete LDLᵀ, IC(0) on 3×3 blocks (BlockIncompleteCholesky), renewed before
    /// every solve: 3–9× fewer iterations a step than block-Jacobi on cotton (the 64×64 sheet:
    /// the solve 5× faster, converged where block-Jacobi stopped at its cap).
    BlockIncompleteCholesky,
};

/// Every linear solver, in the order messages list them.
inline constexpr std::array<LinearSolver, 2> LINEAR_SOLVERS = {
    LinearSolver::BlockJacobi, LinearSolver::BlockIncompleteCholesky};

/// "block-jacobi", "block-ic0".
std::string_view linearSolverName(LinearSolver kind);
std::optional<LinearSolver> linearSolverFromName(std::string_view name);

} // namespace atelier::sim
