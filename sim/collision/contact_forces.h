#pragma once
/// Contacts inside the implicit solve: a stiff one-sided spring in a thin layer above each
/// contact's distance, and Coulomb friction linearised as a lagged viscous force.
///
/// Without them, a backward-Euler step solves the cloth as if the body were not there: every
/// vertex resting on the body falls by g·h in the solve, the cloth hanging from it follows,
/// and the corrections after the solve put back only the vertices in contact. The garment
/// never settles (about 4 cm/s remained on a draped skirt, README). With the contacts in the
/// linear system, the solve itself holds the cloth up and the friction sticks it, so backward
/// Euler's fixed point is the resting drape.

#include "sim/collision/collision_stage.h"
#include "sim/core/block_sparse.h"

#include <vector>

namespace atelier::sim {

/// The contacts of one backward-Euler step, linearised at its start: for contact j with
/// relative position \f$ r_j = \sum_k w_k x_k - q_j \f$, normal n, distance d and gap
/// \f$ g = n\cdot r_j \f$:
/// \f[ f_j = \kappa_j\,\big(d(1+\text{margin}) - \max(g, d)\big)_+\,n
///         - c_j\,(I - nn^T)(\dot r_j), \qquad \kappa_j = \kappa\,m_j/h_0^2, \f]
/// with \f$ h_0 \f$ the nominal step, \f$ c_j = \mu\lambda_j / \max(|\dot r_{j,t}|, \varepsilon)
/// \f$ with λ_j the normal force, distributed to the vertices by their weights. Its Jacobian blocks
/// (−κ w_k w_l nnᵀ on positions, −c w_k w_l (I − nnᵀ) on velocities) are negative semi-definite, so
/// the system stays symmetric positive definite for CG. Blocks coupling the two sides of a
/// cloth–cloth contact are dropped (they are outside the Jacobian's pattern): what is kept is a sum
/// of rank-one negative semi-definite blocks per side, so the property holds.
class ContactForces {
  public:
    /// Linearises the contacts at the step's start (x, v) for a backward-Euler step. The
    /// stiffness is set by the nominal step `hNominal`, not by the step taken, so a short step
    /// (one that stops at a frame) does not make the springs stiffer. Contacts with no movable
    /// vertex, or farther than the layer, contribute nothing.
    void prepare(const std::vector<Contact>& contacts, const MatX3& x, const MatX3& v,
                 const VecX& invMass, double hNominal, const ContactSolveOptions& options);

    /// f += the contact forces at the step's start (|V|×3) [N].
    void addForces(MatX3& f) const;
    /// J += kx·∂f/∂x + kv·∂f/∂v for the blocks in J's pattern.
    void addJacobian(double kx, double kv, BlockSparseMatrix& J) const;
    /// out += (kx·∂f/∂x + kv·∂f/∂v)·p with the blocks `addJacobian` adds (|V|×3), without
    /// assembling them.
    void addJacobianProduct(double kx, double kv, const MatX3& p, MatX3& out) const;

    /// Power the obstacles deliver through these forces, Σ f·q̇ over the contacts [W]: moving
    /// obstacles put energy into the cloth (the spring itself stores at most κ(margin·d)²/2
    /// per contact, and friction only takes energy out of the relative motion).
    double obstaclePower() const;

    /// Energy stored in the contact springs at the step's start, Σ λ²/(2κ) [J]: the step may
    /// turn it into motion (a sheet placed inside the layer is lifted to its top).
    double potential() const;

    /// Contacts taking part in the solve.
    std::size_t size() const { return m_terms.size(); }

  private:
    struct Term {
        int vertex[4] = {-1, -1, -1, -1};
        double weight[4] = {0, 0, 0, 0};
        Vec3 normal = Vec3::UnitY();
        double stiffness = 0;                 ///< κ_j [N/m]
        double damping = 0;                   ///< c_j [N·s/m]
        Vec3 force = Vec3::Zero();            ///< on the relative coordinate r [N]
        Vec3 obstacleVelocity = Vec3::Zero(); ///< q̇ [m/s]
    };
    std::vector<Term> m_terms;
};

} // namespace atelier::sim
