#include "sim/integrators/linear_solver.h"

namespace atelier::sim {

std::string_view linearSolverName(LinearSolver kind) {
    switch (kind) {
    case LinearSolver::BlockJacobi:
        return "block-jacobi";
    case LinearSolver::BlockIncompleteCholesky:
        return "block-ic0";
    }
    return "?";
}

std::optional<LinearSolver> linearSolverFromName(std::string_view name) {
    for (const LinearSolver k :
         {LinearSolver::BlockJacobi, LinearSolver::BlockIncompleteCholesky}) {
        if (linearSolverName(k) == name) {
            return k;
        }
    }
    return std::nullopt;
}

} // namespace atelier::sim
