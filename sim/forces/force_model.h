#pragma once
/// Interface of a force model: internal forces of the cloth and their Jacobians.

#include "sim/core/block_sparse.h"
#include "sim/core/types.h"

#include <string_view>
#include <utility>
#include <vector>

namespace atelier::sim {

/// What a Jacobian is assembled for.
enum class JacobianMode {
    Exact,    ///< the true derivatives (tests compare it with finite differences)
    Definite, ///< a symmetric negative semi-definite approximation of ∂f/∂x (compressive
              ///< geometric terms dropped, symmetrised) so that implicit solves use CG
};

/// A force model acting on a set of vertices given by global indices. Models are stateless
/// during a step: `addForces` may be called on trial states (Runge–Kutta stages) and must
/// never throw; degenerate elements contribute zero.
class ForceModel {
  public:
    virtual ~ForceModel() = default;
    /// Stage name used in reports and timing scopes (e.g. "stretch.volino", "bending").
    virtual std::string_view name() const = 0;

    /// f += forces at state (x, v) [N]; x, v, f are (|V|×3) over all simulated vertices.
    virtual void addForces(const MatX3& x, const MatX3& v, MatX3& f) const = 0;

    /// Whether `energy` is defined (conservative part derives from a potential).
    virtual bool hasEnergy() const { return false; }
    /// Potential energy of the conservative part [J]. 0 when `hasEnergy()` is false.
    virtual double energy(const MatX3& x) const {
        (void)x;
        return 0.0;
    }

    /// Vertex pairs (i, j) whose Jacobian block may be non-zero, to build the sparsity pattern.
    virtual void jacobianPattern(std::vector<std::pair<int, int>>& pairs) const = 0;
    /// J += kx·∂f/∂x + kv·∂f/∂v at (x, v). J's pattern holds `jacobianPattern`.
    virtual void addJacobian(const MatX3& x, const MatX3& v, double kx, double kv,
                             JacobianMode mode, BlockSparseMatrix& J) const = 0;

    /// f += (∂f/∂v)·v with Definite-mode ∂f/∂v, as `addJacobian` assembles it (the implicit
    /// step's (∂f/∂x)·v comes from one assembly and this). Default: f(x, v) − f(x, 0), exact
    /// for damping linear in v whose Definite ∂f/∂v is not projected (checked per model).
    virtual void addDampingProduct(const MatX3& x, const MatX3& v, MatX3& f) const {
        // Reused per thread: called every implicit step, for every model.
        thread_local MatX3 zero, atRest;
        zero.setZero(x.rows(), 3);
        atRest.setZero(x.rows(), 3);
        addForces(x, zero, atRest);
        addForces(x, v, f);
        f -= atRest;
    }

    /// Called once per accepted step for models with internal state (plasticity). Default: none.
    virtual void acceptStep(const MatX3& x, double dt) {
        (void)x;
        (void)dt;
    }
};

} // namespace atelier::sim
