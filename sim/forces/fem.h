#pragma once
/// Orthotropic St. Venant–Kirchhoff constant-strain triangles for the in-plane (stretch and
/// shear) behaviour of cloth.

#include "sim/forces/element_gather.h"
#include "sim/forces/force_model.h"
#include "sim/material.h"
#include "sim/mesh/cloth_mesh.h"

#include <vector>

namespace atelier::sim {

/// Plane-stress orthotropic stiffness in Voigt notation (E_xx, E_yy, 2E_xy) [N/m]:
/// \f[ C = \frac{1}{1-\nu_{12}\nu_{21}}\begin{pmatrix} E_1 & \nu_{21}E_1 & 0
///        \\ \nu_{12}E_2 & E_2 & 0
///        \\ 0 & 0 & (1-\nu_{12}\nu_{21})G_{12}\end{pmatrix},\qquad
///     \nu_{21} = \nu_{12}\,E_2/E_1 \f]
/// with E₁ = `stretchWeft`, E₂ = `stretchWarp`, ν₁₂ = `poisson`, G₁₂ = `shear`. C is symmetric;
/// 1 − ν₁₂ν₂₁ is clamped to ≥ 1e-6 so an unphysical ν never divides by zero.
Mat3 orthotropicStiffness(const Material& material);

/// Orthotropic St. Venant–Kirchhoff membrane (Volino et al. 2009 "A simple approach to
/// nonlinear tensile stiffness for accurate cloth simulation"; Bonet & Wood, "Nonlinear
/// continuum mechanics", §6.4) on constant-strain triangles, in the material frame of the
/// pattern (x = weft, y = warp).
///
/// Per triangle with rest edge matrix D_m = [X₁−X₀, X₂−X₀] (2×2), rest area A₀ and current
/// edge matrix D_s = [x₁−x₀, x₂−x₀] (3×2):
/// \f[ F = D_s D_m^{-1},\quad E = \tfrac12(F^\top F - I),\quad
///     W = A_0\,\tfrac12\,\varepsilon^\top C\,\varepsilon,\quad
///     \varepsilon = (E_{xx}, E_{yy}, 2E_{xy}) \f]
/// so that at small strain uniaxial weft tension gives stress E₁·strain and lateral strain
/// −ν₁₂·strain. Second Piola–Kirchhoff stress S = C:E plus the strain-rate damping stress
/// \f[ S_d = \tau\,C:\dot E,\qquad \dot E = \mathrm{sym}(F^\top \dot F),\quad
///     \dot F = \dot D_s D_m^{-1} \f]
/// (τ = `material.damping` [s]), and the node forces
/// \f[ f_a = -A_0\,F\,(S + S_d)\,b_a \f]
/// where b_a is the gradient of the linear shape function of node a in the pattern
/// (rows of D_m⁻¹ for nodes 1, 2; b₀ = −b₁ − b₂).
///
/// Stiffening (`material.stretchKnee` > 0 with `stretchWeftBeyond` or `stretchWarpBeyond` above
/// the small-strain modulus): beyond the knee strain κ the normal strains add
/// \f[ W_s = A_0 \sum_{i \in \{xx, yy\}} \tfrac12 \Delta_i \max(0, E_{ii} - \kappa)^2,
///     \qquad \Delta_{xx} = E_1^{\mathrm{beyond}} - E_1,\ \Delta_{yy} = E_2^{\mathrm{beyond}} - E_2
///     \f]
/// so S_ii gains Δ_i·max(0, E_ii − κ) and the tangent modulus along weft (warp) rises by Δ_i
/// past κ: a biphasic law (the uniaxial tangent beyond the knee is exactly E^beyond when
/// ν = 0, and within ν₁₂ν₂₁·Δ of it otherwise). The damping stress stays linear (C:Ė).
///
/// Jacobian: `Exact` holds all terms of ∂f/∂x (material, geometric with S + S_d, and the
/// x-dependence of Ė) and ∂f/∂v = τ·(material term). `Definite` keeps the material term
/// −A₀ Jᵀ C J with J = ∂ε/∂x (NSD for a valid material) and the geometric term with the eigenvalues
/// of S + S_d clamped at ≥ 0, and drops the non-symmetric damping x-term.
class FemStretch : public ForceModel {
  public:
    /// `offset`: global index of the mesh's vertex 0.
    FemStretch(const ClothMesh& mesh, int offset, const Material& material);

    std::string_view name() const override { return "stretch.fem"; }
    void addForces(const MatX3& x, const MatX3& v, MatX3& f) const override;
    bool hasEnergy() const override { return true; }
    double energy(const MatX3& x) const override;
    void jacobianPattern(std::vector<std::pair<int, int>>& pairs) const override;
    void addJacobian(const MatX3& x, const MatX3& v, double kx, double kv, JacobianMode mode,
                     BlockSparseMatrix& J) const override;

    /// Green strain (E_xx, E_yy, 2E_xy) of triangle t at x (for tests and reports).
    Vec3 greenStrain(const MatX3& x, int t) const;
    /// Second Piola–Kirchhoff elastic stress (S_xx, S_yy, S_xy) [N/m] of triangle t at x.
    Vec3 stress(const MatX3& x, int t) const;

  private:
    /// F (3×2) of triangle t from the rows of `x`.
    Eigen::Matrix<double, 3, 2> deformationGradient(const MatX3& x, int t) const;

    int m_offset;
    MatX3i m_triangles; ///< (|F|×3) local indices
    /// (|F|) shape-function gradients b_a in the pattern, one 2×3 matrix per triangle
    /// (column a = b_a) [1/m].
    std::vector<Eigen::Matrix<double, 2, 3>> m_shapeGradient;
    VecX m_restArea;  ///< (|F|) A₀ [m²]; 0 for a degenerate rest triangle
    Mat3 m_stiffness; ///< C [N/m]
    /// Stiffening beyond the knee: Δ_xx, Δ_yy [N/m] (zero when the law is linear).
    Vec2 m_stiffening = Vec2::Zero();
    double m_knee = 0;       ///< κ [-]
    bool m_biphasic = false; ///< some Δ > 0 with κ > 0
    /// max(0, E_ii − κ) for the weft and warp normal strains of e.
    Vec2 beyondKnee(const Vec3& e) const;
    /// Stress S_ii added beyond the knee at Green strain e (Voigt; zero shear).
    Vec3 stiffeningStress(const Vec3& e) const;
    /// The tangent of stiffeningStress at e (diagonal: Δ_i where E_ii > κ).
    Vec2 stiffeningTangent(const Vec3& e) const;
    double m_damping; ///< τ [s]
    ElementGather m_gather;
    mutable std::vector<Mat3>
        m_blocks; ///< (|F|·9) Jacobian blocks; one assembling thread per model
};

} // namespace atelier::sim
