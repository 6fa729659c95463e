#pragma once
/// Continuum plate bending on any triangle mesh: a per-triangle curvature tensor from the
/// hinge angles, with the fabric's orthotropic bending rigidity in the material frame.

#include "sim/forces/element_gather.h"
#include "sim/forces/force_model.h"
#include "sim/material.h"
#include "sim/mesh/cloth_mesh.h"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace atelier::sim {

/// Bending rigidity of an orthotropic fabric in its material frame (weft = x, warp = y), as
/// the plate energy density
/// \f[ \psi = \tfrac12\big(B_1\kappa_{11}^2 + B_2\kappa_{22}^2 + B_t(2\kappa_{12})^2\big) \f]
/// (no bending Poisson coupling: the textile tests measure none). A strip cut at angle φ to the
/// weft, its long edges free, bends with
/// \f[ \frac1{B(\varphi)} = \frac{\cos^4\varphi}{B_1} + \frac{\sin^4\varphi}{B_2}
///     + \frac{\cos^2\varphi\,\sin^2\varphi}{B_t} \f]
/// so B(0) = B₁, B(90°) = B₂ and the bias (45°) value gives 1/B_t = 4/B_bias − 1/B₁ − 1/B₂.
/// Isotropic B: B₁ = B₂ = B, B_t = B/2, and B(φ) = B in every direction.
struct BendingRigidity {
    double weft = 0;  ///< B₁: moment per width per unit curvature along the weft (x) [N·m]
    double warp = 0;  ///< B₂: along the warp (y) [N·m]
    double twist = 0; ///< B_t: against twist 2κ₁₂ [N·m]
};

/// The rigidity a material asks for: `bendingWeft`/`bendingWarp` (0 = `bending`) and
/// `bendingBias` (0 = B_t = √(B₁B₂)/2, Huber's orthotropic plate: isotropic when B₁ = B₂).
/// Returns the reason when the values cannot be a fabric's: negative or non-finite, or a bias
/// rigidity of 4/B_bias ≤ 1/B₁ + 1/B₂ (a strip at 45° stiffer than the plate allows).
std::optional<std::string> bendingRigidity(const Material& material, BendingRigidity& out);

/// Rigidity B(φ) [N·m] of a strip cut at `angle` [rad] to the weft (see BendingRigidity).
double stripRigidity(const BendingRigidity& rigidity, double angle);

/// Continuum plate bending of a cloth: `material.bending` (`bending_n_m`) is the bending
/// rigidity per unit width B [N·m] (moment per width = B·curvature, as cantilever testers
/// report it), orthotropic in the material frame (BendingRigidity), on any mesh:
/// \f[ E = \sum_T \bar A_T\,\tfrac12\,\kappa_T^{\mathsf T} D\,\kappa_T,\qquad
///     D = \operatorname{diag}(B_1, B_2, B_t),\quad \kappa = (\kappa_{11}, \kappa_{22},
///     2\kappa_{12}) \f]
/// with κ_T the constant curvature of triangle T in rest (pattern) coordinates: Grinspun et al.
/// 2006's edge-based shape operator ("Computing discrete shape operators on general meshes"),
/// also the curvature of the rotation-free BST plate triangle (Oñate & Zárate 2000):
/// \f[ \kappa_T = -\sum_{h \in T} w_h\,(\theta_h - \bar\theta_h)\,\bar n_h \bar n_h^{\mathsf T},
///     \qquad w_h = \frac{2}{h_0 + h_1} = \frac{|\bar e_h|}{\bar A_0 + \bar A_1} \f]
/// (n̄_h the edge's in-plane unit normal, h₀, h₁ the rest heights of the wings over the edge: by
/// Green's theorem Ā_T κ_T = ∮ n ⊗ ∇z with the gradient on each edge interpolated between the
/// two triangles' centroids; a free border adds nothing, the vanishing moment of a free edge for
/// a plate without bending Poisson coupling). Summed, E = ½ φᵀWφ with W = Σ_T Ā_T M_TᵀDM_T,
/// M_T the 3×3 map from T's hinge angles to κ_T: symmetric positive semi-definite, coupling the
/// hinges of each triangle. Exact for any constant curvature on grids whose neighbouring
/// triangles are point reflections across their edge; converging on general meshes
/// (docs/decisions/030-continuum-bending.md). An exact per-triangle fit of κ to its three hinges
/// (κ_T = C_T⁻¹θ_T) was measured instead and rejected: it has spurious soft modes (a simply
/// supported strip 1.44× too soft at every mesh size) and ill-conditioned triangles.
///
/// As in `DihedralBending`, each deviation enters as φ = 2 sin((θ − θ̄)/2) (periodic: a hinge
/// folding through ±π keeps a continuous torque; = θ − θ̄ to 1% below 28°), gradients are
/// capped at wing tips collapsing below 1/50 of their rest height, and fold-rate damping with
/// τ = `material.damping` acts on φ̇:
/// \f[ f = -\sum_h \mu_h\,\cos\tfrac{\theta_h-\bar\theta_h}{2}\,\nabla\theta_h,\qquad
///     \mu = W(\varphi + \tau\dot\varphi) \f]
/// Jacobian `Definite`: −Σ_T Gᵀ Q_T G with Q_T = Ā_T M_TᵀDM_T and G the rows cos(Δθ/2)∇θ of T's
/// hinges (Gauss–Newton, negative semi-definite); `Exact` adds the ∇²θ and cos′ terms.
/// ∂f/∂v = −τ Σ_T Gᵀ Q_T G. Plasticity as in `DihedralBending`.
class ContinuumBending : public ForceModel {
  public:
    /// `offset`: global index of the mesh's vertex 0. `restAngles`: (|H|) rest fold angles θ̄
    /// [rad] in `dihedralAngle`'s convention, or empty for a flat rest shape. The material's
    /// rigidity must be valid (`bendingRigidity`); invalid values bend nothing. `held`: per
    /// global vertex, non-zero when pinned at build (empty = none): a triangle whose three
    /// corners are held is rigid, and a hinge between it and a free triangle is a clamped edge,
    /// its whole jump counted in the free triangle (Oñate & Zárate 2000's clamped boundary of the
    /// BST triangle) instead of half in each, where the clamped strip's root was too soft (tip
    /// deflection 1.27× at 10 mm, docs/decisions/020-continuum-bending.md).
    ContinuumBending(const ClothMesh& mesh, int offset, const Material& material,
                     const VecX& restAngles, bool plasticity, const std::vector<char>& held = {});

    std::string_view name() const override { return "bending"; }
    void addForces(const MatX3& x, const MatX3& v, MatX3& f) const override;
    bool hasEnergy() const override { return true; }
    double energy(const MatX3& x) const override;
    void jacobianPattern(std::vector<std::pair<int, int>>& pairs) const override;
    void addJacobian(const MatX3& x, const MatX3& v, double kx, double kv, JacobianMode mode,
                     BlockSparseMatrix& J) const override;
    void acceptStep(const MatX3& x, double dt) override;

    /// (|H|) current rest angles θ̄ [rad].
    const VecX& restAngles() const { return m_restAngle; }
    /// Curvature (κ₁₁, κ₂₂, 2κ₁₂) [1/m] of triangle t at x in the material frame (κ_T above,
    /// with θ − θ̄ for φ).
    Vec3 curvature(const MatX3& x, int t) const;

  private:
    /// Per hinge at x: φ, φ̇, cos(Δθ/2), the capped gradient (4 corners) and whether it is
    /// non-degenerate.
    struct HingeState {
        double phi = 0;
        double phiDot = 0;
        double c = 1;
        double s = 0; ///< sin(Δθ/2)
        double thetaDot = 0;
        double scale = 1; ///< gradient cap factor (1 unless a wing has collapsed)
        std::array<Vec3, 4> grad{};
        bool ok = false;
    };
    void evaluateHinges(const MatX3& x, const MatX3* v) const;
    std::array<Vec3, 4> corners(const MatX3& x, int h) const;

    int m_offset;
    Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor> m_hinges; ///< (|H|×4) local
    VecX m_gradientCap; ///< (|H|) largest |∇θ| a corner may feel [1/m]
    static constexpr double GRADIENT_CAP = 50.0;
    VecX m_restAngle; ///< (|H|) θ̄ [rad]

    // W = Σ_T Q_T as CSR over hinges.
    std::vector<int> m_wStart;    ///< (|H|+1)
    std::vector<int> m_wColumn;   ///< hinge j of each entry
    std::vector<double> m_wValue; ///< W_hj [N·m]

    // Per triangle: its hinges (−1 where the edge is a border), Q_T, and the stencil of six
    // vertices (its three, then the three opposite across its edges, −1 on a border).
    Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> m_triHinges;
    std::vector<Mat3> m_q;                         ///< (|F|) Q_T over (hinge slot i, slot j) [N·m]
    std::vector<Mat3> m_curvatureMap;              ///< (|F|) M_T: κ_T = M_T φ_T [1/m]
    std::vector<std::array<int, 12>> m_cornerSlot; ///< (|F|) stencil slot of hinge i's corner a

    double m_damping; ///< τ [s]
    bool m_plasticity;
    double m_yieldAngle;            ///< [rad]
    double m_plasticRate;           ///< [1/s]
    ElementGather m_hingeGather;    ///< k = 4 over hinges (forces, Hessian terms)
    ElementGather m_triangleGather; ///< k = 6 over triangle stencils (Gauss–Newton terms)

    mutable std::vector<HingeState> m_state; ///< (|H|) one evaluating thread per model
    mutable MatX3 m_buffer;                  ///< (|H|·4 × 3) per-corner forces
    mutable std::vector<Mat3> m_hingeBlocks; ///< (|H|·16)
    mutable std::vector<Mat3> m_triBlocks;   ///< (|F|·36)
    mutable std::vector<Eigen::Matrix<double, 12, 1>> m_hessianV; ///< (|H|) ∇²θ_h·v (Exact)
};

} // namespace atelier::sim
