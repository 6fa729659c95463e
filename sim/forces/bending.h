#pragma once
/// Discrete-shells dihedral-angle bending of cloth.

#include "sim/forces/element_gather.h"
#include "sim/forces/force_model.h"
#include "sim/material.h"
#include "sim/mesh/cloth_mesh.h"

#include <array>
#include <vector>

namespace atelier::sim {

/// Signed dihedral angle θ [rad] of the hinge (x₀, x₁ | x₂, x₃): edge x₀→x₁, x₂ opposite in
/// triangle 0 = (x₀, x₁, x₂), x₃ opposite in triangle 1 = (x₁, x₀, x₃) (the `ClothMesh::hinges`
/// order). With n₀ = (x₁−x₀)×(x₂−x₀), n₁ = (x₃−x₀)×(x₁−x₀) and ê = (x₁−x₀)/|x₁−x₀|,
/// \f[ \theta = \operatorname{atan2}\big((n_0\times n_1)\cdot\hat e,\; n_0\cdot n_1\big)
///     \in (-\pi, \pi] \f]
/// 0 when flat; positive when both wings fold away from n₀ (x₂ and x₃ move along −n₀ from
/// flat: a ridge seen from the side n₀ points to), negative when they fold towards n₀.
/// Returns 0 for a degenerate hinge.
double dihedralAngle(const Vec3& x0, const Vec3& x1, const Vec3& x2, const Vec3& x3);

/// Gradient ∂θ/∂(x₀, x₁, x₂, x₃), closed form of Bridson, Marino & Fedkiw 2003 ("Simulation of
/// clothing with folds and wrinkles", §4): with h_i the heights of x₂, x₃ over the edge,
/// \f[ \nabla_{x_2}\theta = -\frac{|e|}{|n_0|^2}n_0,\quad
///     \nabla_{x_3}\theta = -\frac{|e|}{|n_1|^2}n_1,\quad \ldots \f]
/// (the signs follow `dihedralAngle`'s). Returns false (and zeros) for a degenerate hinge:
/// an edge shorter than 1e-15 m or a wing whose height is below 1e-12·|e|.
bool dihedralAngleGradient(const std::array<Vec3, 4>& x, std::array<Vec3, 4>& grad);

/// Hessian ∂²θ/∂x² (12×12, vertex-major blocks) by forward-mode differentiation of the
/// closed-form gradient: exact to rounding, symmetrised. Returns false (and zero) when degenerate.
bool dihedralAngleHessian(const std::array<Vec3, 4>& x, Eigen::Matrix<double, 12, 12>& hessian);

/// Bending rigidities per unit width of a material in its frame (weft = x, warp = y), and the
/// plate's stiffness matrix D for the curvature vector (κ_xx, κ_xy, κ_yy) [1/m].
struct BendingRigidity {
    double weft = 0; ///< B₁: moment per width per curvature bending along the weft (κ_xx) [N·m]
    double warp = 0; ///< B₂: the same along the warp (κ_yy) [N·m]
    /// D₆₆: twisting rigidity [N·m]: B_bias − (B₁ + B₂)/4, with B_bias the rigidity of a strip
    /// cut at 45°; ½√(B₁B₂) when no bias value is given (= B/2: isotropic when B₁ = B₂).
    double twist = 0;
};

/// The rigidities `material` asks for: `bending` in every direction unless `bendingWeft`,
/// `bendingWarp` or `bendingBias` (> 0) replace it along their direction. D₆₆ is clamped at 0
/// (scene validation refuses a bias below (B₁ + B₂)/4).
BendingRigidity bendingRigidity(const Material& material);

/// Continuum plate bending on a triangle mesh from its hinge (dihedral) angles, with
/// `material.bending` (`bending_n_m`) the bending rigidity per unit width B [N·m] (moment per
/// width = B·curvature, as cantilever testers report it) and an orthotropic plate energy in the
/// material frame (ν = 0 between the bending directions):
/// \f[ E = \sum_T \bar A_T\,\tfrac12\big(B_1\kappa_{xx}^2 + 4D_{66}\kappa_{xy}^2 +
///     B_2\kappa_{yy}^2\big) \f]
/// with κ_T the constant curvature (second fundamental form, in rest coordinates) of triangle T.
/// ν = 0 makes a free edge carry no moment with zero normal curvature, which is what the border
/// treatment below assumes.
///
/// κ_T is the Grinspun et al. 2006 ("Computing discrete shape operators on general meshes")
/// edge-based shape operator, which is also the curvature of the rotation-free BST plate
/// triangle (Oñate & Zárate 2000): by Green's theorem Ā_T κ_T = ∮ n ⊗ ∇z, with the gradient
/// on each edge interpolated between the centroids of the two triangles it joins, so that the
/// jump θ_h across hinge h counts with h_T/(h_T + h_other):
/// \f[ \kappa_T = \sum_{h \in T} w_h\,\theta_h\,\bar n_h \bar n_h^\top,\qquad
///     w_h = \frac{2}{h_0 + h_1} = \frac{|\bar e_h|}{\bar A_0 + \bar A_1} \f]
/// (n̄_h the edge's in-plane normal, h₀, h₁ the rest heights of the two wings over the edge; a
/// free border adds nothing). The energy is ½(θ−θ̄)ᵀM(θ−θ̄) with M = Σ_T Ā_T GᵀDG, G the 3×3
/// map θ_T ↦ κ_T (positive semi-definite, coupling the hinges of each triangle). w_h stays
/// bounded on slivers, where the plain 1/(2Ā_T) form grows without bound.
/// Measured (bending_test.cpp, docs/decisions/020-continuum-bending.md): exact for any
/// constant curvature on grids whose neighbouring triangles are point reflections across
/// their edge (a cylinder rolled along either axis of makeRectangle's grid stores ½B∫κ² but
/// for the border column); on makeRectangle's criss-cross grid a roll at 45° stores 1.475× that
/// (mirror-image neighbours); a simply supported strip's midspan deflection converges (1.013,
/// 1.003, 1.001 of 5wL⁴/384B at 10, 5, 2.5 mm); the heavy cantilever hangs 1.0–4.9° (Delaunay
/// meshes) and 1.9–7.0° (criss-cross grid) below the exact elastica at 10 mm, mostly from the
/// clamp, and within 1.7° on Delaunay meshes at 5 mm (docs/benchmarks.md).
/// Discrete shells' diagonal weight 3|ē|²/(Ā₀+Ā₁) stored 1.5–4.5× depending on mesh and
/// direction.
///
/// Large folds: with d = θ − θ̄ and ψ = 2 sin(d/2),
/// \f[ E = \tfrac12\psi^\top M\psi \f]
/// = ½dᵀMd + O(d⁴), non-negative, monotone in each |d| up to π and periodic: when a hinge folds
/// through itself θ wraps from π to −π, where its own torque M_hh·2sin(d/2)·cos(d/2) is
/// continuous (0) as discrete shells' M_hh(1 − cos d) was; only the coupling to its neighbours'
/// torques (M_hj·ψ_h) changes sign there. ψ = sin d instead (continuous everywhere) softens past
/// 90° and made the 20 mm tshirt drape restless (not at rest in 4 s; with 2 sin(d/2) it rests
/// at 0.87 s, docs/benchmarks.md).
///
/// Degenerate wings: |∇θ| at a wing tip is 1/height, unbounded as a triangle collapses into a
/// needle (a violently stretched sheet does that), and a force that grows without bound near a
/// configuration stalls any error-controlled step. Each hinge's ∇θ is therefore scaled by
/// s_h = min(1, cap/max_a|∇θ_a|) with cap = 50/(rest wing height): continuous, 1 whenever no
/// wing is below 1/50 of its rest height, and bounded beyond (Grinspun et al. 2003, §2.2.1).
/// The Jacobian uses the same scale.
///
/// Damping is strain-rate (fold-rate) damping with τ = `material.damping` [s] and the
/// stiffness as its matrix: f = −τ Σ_ij M_ij θ̇_j ∇θ_i with θ̇ = ∇θ·v. Jacobian `Exact`: all
/// terms (∇θ∇θᵀ, ∇²θ); `Definite`: ∂f/∂x ≈ −GᵀCMCG with c = cos(d/2) ≥ 0 and G the stacked
/// ∇θ (symmetric, negative semi-definite), ∂f/∂v exact (−τGᵀMG).
///
/// Plasticity (when enabled and `material.plasticYieldAngle` > 0): after each accepted step the
/// rest angle follows the part of θ − θ̄ beyond the yield angle θ_y:
/// \f[ \bar\theta \mathrel{+}= \min(1, r\,\Delta t)\,\operatorname{sign}(d)\,(|d| - \theta_y),
///     \qquad d = \theta - \bar\theta,\ |d| > \theta_y \f]
/// with r = `material.plasticRate` [1/s].
class DihedralBending : public ForceModel {
  public:
    /// `offset`: global index of the mesh's vertex 0. `restAngles`: (|H|) rest fold angles θ̄
    /// [rad] in `dihedralAngle`'s convention, or empty for a flat rest shape.
    DihedralBending(const ClothMesh& mesh, int offset, const Material& material,
                    const VecX& restAngles, bool plasticity);

    std::string_view name() const override { return "bending"; }
    void addForces(const MatX3& x, const MatX3& v, MatX3& f) const override;
    bool hasEnergy() const override { return true; }
    double energy(const MatX3& x) const override;
    void jacobianPattern(std::vector<std::pair<int, int>>& pairs) const override;
    void addJacobian(const MatX3& x, const MatX3& v, double kx, double kv, JacobianMode mode,
                     BlockSparseMatrix& J) const override;
    void acceptStep(const MatX3& x, double dt) override;

    /// (|H|) current rest angles θ̄ [rad] (they change with plasticity).
    const VecX& restAngles() const { return m_restAngle; }
    /// M_hh: the stiffness of hinge h alone, ∂²E/∂θ_h² at rest [N·m].
    double hingeStiffness(int h) const { return m_value[static_cast<std::size_t>(m_start[h])]; }
    /// Dihedral angle of hinge h at x [rad].
    double angle(const MatX3& x, int h) const;

  private:
    std::array<Vec3, 4> corners(const MatX3& x, int h) const;
    /// Per-hinge state at (x, v): ψ, cos d, scaled gradients, θ̇ (and ∇²θ·v when `hessianV`).
    void evaluateHinges(const MatX3& x, const MatX3& v, bool hessianV) const;
    /// Σ_j M_hj·values_j over the hinges coupled to h.
    double coupled(int h, const VecX& values) const;

    int m_offset;
    Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor> m_hinges; ///< (|H|×4) local
    /// Force scale that keeps |∇θ| ≤ m_gradientCap[h] (1 when the hinge is not degenerate).
    double gradientScale(const std::array<Vec3, 4>& g, int h) const;
    VecX m_gradientCap; ///< (|H|) largest |∇θ| a corner may feel [1/m]
    static constexpr double GRADIENT_CAP = 50.0;
    /// M in CSR by hinge: the diagonal first in each row [N·m].
    std::vector<int> m_start;    ///< (|H|+1)
    std::vector<int> m_column;   ///< hinge of each entry
    std::vector<double> m_value; ///< M_hj
    /// Triangles holding two or more hinges: their 6-vertex stencils (the triangle's corners,
    /// then the vertex across each edge, −1 on a border) carry the cross-hinge Jacobian blocks.
    std::vector<std::array<int, 3>> m_stencilHinges; ///< hinge on each edge, −1 on a border
    /// Stencil slot of each hinge corner: (triangle, edge, corner) → 0..5.
    std::vector<std::array<std::array<int, 4>, 3>> m_stencilSlot;
    std::vector<std::array<double, 9>> m_stencilM; ///< M_T between the triangle's edges
    mutable MatX3 m_buffer; ///< (|H|·4 × 3) per-corner forces; one evaluating thread per model
    mutable std::vector<Mat3> m_blocks;        ///< (|H|·16) Jacobian blocks of each hinge
    mutable std::vector<Mat3> m_stencilBlocks; ///< (|T₂|·36) cross-hinge blocks
    /// Per-hinge state of the last evaluation: one evaluating thread per model.
    mutable VecX m_psi, m_cos, m_rate; ///< 2sin(d/2), cos(d/2), θ̇ with the scaled gradient [1/s]
    mutable std::vector<std::array<Vec3, 4>> m_grad;              ///< s_h∇θ_h
    mutable std::vector<Eigen::Matrix<double, 12, 1>> m_hessianV; ///< s_h∇²θ_h·v
    VecX m_restAngle;                                             ///< (|H|) θ̄ [rad]
    double m_damping;                                             ///< τ [s]
    bool m_plasticity;
    double m_yieldAngle;  ///< [rad]
    double m_plasticRate; ///< [1/s]
    ElementGather m_gather;
    ElementGather m_stencilGather;
};

} // namespace atelier::sim
