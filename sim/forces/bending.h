#pragma once
/// Discrete-shells dihedral-angle bending of cloth.

#include "sim/forces/element_gather.h"
#include "sim/forces/force_model.h"
#include "sim/material.h"
#include "sim/mesh/cloth_mesh.h"

#include <array>
#include <functional>
#include <string>
#include <string_view>
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

/// Hinges over global vertex indices with what each one's energy needs (`DihedralBending`).
struct HingeSet {
    using Corners = Eigen::Matrix<int, Eigen::Dynamic, 4, Eigen::RowMajor>;
    Corners corners;  ///< (|H|×4) global (edge v0, edge v1, opposite 0, opposite 1)
    VecX weight;      ///< (|H|) w_h = 3|ē|²/(Ā₀ + Ā₁) [-]
    VecX gradientCap; ///< (|H|) largest |∇θ| a corner may feel [1/m]
    VecX restAngle;   ///< (|H|) θ̄ [rad]
    VecX stiffness;   ///< (|H|) k [N·m]
    VecX damping;     ///< (|H|) τ [s]

    /// Room for `count` hinges, all zero.
    void resize(int count);
    /// Sets hinge h's weight and gradient cap from its squared rest edge length `edgeSquared`
    /// [m²] and the rest areas of its two triangles [m²] (wing heights 2A/|ē|).
    void setRestShape(int h, double edgeSquared, double area0, double area1);
};

/// Discrete-shells bending (Grinspun, Hirani, Desbrun & Schröder 2003 "Discrete shells";
/// Bridson et al. 2003) on every interior edge (hinge) h:
/// \f[ E_h = k\,w_h\,\big(1 - \cos(\theta_h - \bar\theta_h)\big)
///     \approx \tfrac12\,k\,w_h\,(\theta_h - \bar\theta_h)^2,\qquad
///     w_h = \frac{3\,|\bar e_h|^2}{\bar A_0 + \bar A_1} \f]
/// with k = `material.bending` [N·m], |ē| the rest edge length and Ā₀, Ā₁ the rest areas of the
/// two triangles, i.e. \f$ E_h = \tfrac32 k (\theta-\bar\theta)^2 |\bar e|^2/(\bar A_0+\bar A_1)
/// \f$. This is the continuum plate energy ½·k·(2H)² over the hinge's share A_h = (Ā₀+Ā₁)/3 of the
/// surface, with the hinge's integrated mean curvature ∫H dA = ½·θ·|ē| (Grinspun et al. 2003,
/// 2006): per hinge the standard discrete-shells scaling, so k is the continuum stiffness of
/// each hinge's fold. Summed over a mesh, discrete shells is mesh-dependent; the effective
/// stiffness measured against the continuum ½k∫κ² (ν = 0) is ≈1.5·k on equilateral meshes
/// (isotropic), ≈2.9·k for weft/warp cylinders and ≈4.5·k at 45° on makeRectangle's regular
/// grid, and much more on meshes with slivers (see bending_test.cpp).
///
/// The cosine form (= ½ k w (2 sin(Δθ/2))²) equals the quadratic discrete-shells energy to
/// within 5% in torque for |θ − θ̄| < 30° and, unlike it, is periodic: when a hinge folds
/// through itself θ wraps from π to −π, and the quadratic energy's force would jump there
/// (from −k w π ∇θ to +k w π ∇θ), which no error-controlled integrator can step across (a
/// jerked sheet folds that way). With the cosine the torque k w sin(θ − θ̄) is continuous.
///
/// Degenerate wings: |∇θ| at a wing tip is 1/height, unbounded as a triangle collapses into a
/// needle (a violently stretched sheet does that), and a force that grows without bound near a
/// configuration stalls any error-controlled step. The force is therefore scaled by
/// min(1, cap/max_a|∇θ_a|) with cap = 50/(rest wing height): continuous, equal to the
/// energy's gradient whenever no wing is below 1/50 of its rest height, and bounded beyond
/// (the seed paper, §2.2.1: "remove all the singular configurations where the forces are
/// infinite"). The Jacobian uses the same scale.
///
/// Damping is strain-rate (fold-rate) damping with τ = `material.damping` [s]:
/// \f[ f = -k\,w_h\,\big(\sin(\theta - \bar\theta) + \tau\,\dot\theta\big)\,\nabla\theta,\qquad
///     \dot\theta = \nabla\theta\cdot v \f]
/// Jacobian `Exact`: ∂f/∂x = −k w (cos Δθ ∇θ∇θᵀ + (sin Δθ + τθ̇)∇²θ + τ∇θ(∇²θ v)ᵀ),
/// ∂f/∂v = −k w τ ∇θ∇θᵀ. `Definite`: ∂f/∂x ≈ −k w max(cos Δθ, 0) ∇θ∇θᵀ (Gauss–Newton, NSD),
/// same ∂f/∂v.
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
    /// Hinges given by global vertex indices, each with its own stiffness and damping (the
    /// hinges across welded seams, sim/forces/seam_bending.h); no plasticity. `name` is the
    /// stage name.
    DihedralBending(HingeSet hinges, std::string_view name);

    std::string_view name() const override { return m_name; }
    void addForces(const MatX3& x, const MatX3& v, MatX3& f) const override;
    bool hasEnergy() const override { return true; }
    double energy(const MatX3& x) const override;
    void jacobianPattern(std::vector<std::pair<int, int>>& pairs) const override;
    void addJacobian(const MatX3& x, const MatX3& v, double kx, double kv, JacobianMode mode,
                     BlockSparseMatrix& J) const override;
    void acceptStep(const MatX3& x, double dt) override;

    int hingeCount() const { return static_cast<int>(m_set.corners.rows()); }
    /// (|H|×4) global vertex indices of the hinges, in `dihedralAngle`'s order.
    const HingeSet::Corners& hinges() const { return m_set.corners; }
    /// (|H|) current rest angles θ̄ [rad] (they change with plasticity).
    const VecX& restAngles() const { return m_set.restAngle; }
    /// (|H|) weights w_h [-] (see the class comment).
    const VecX& weights() const { return m_set.weight; }
    /// Dihedral angle of hinge h at x [rad].
    double angle(const MatX3& x, int h) const;

    /// Which hinges act (non-zero) and which give nothing (zero); empty = all act. The Jacobian
    /// pattern keeps every hinge, so that switching one on needs no new pattern.
    void setActive(std::vector<char> active) { m_active = std::move(active); }
    bool active(int h) const {
        return m_active.empty() || m_active[static_cast<std::size_t>(h)] != 0;
    }

  protected:
    /// The hinges' stiffness k [N·m], for a subclass that changes it between steps.
    VecX& stiffness() { return m_set.stiffness; }

  private:
    std::array<Vec3, 4> corners(const MatX3& x, int h) const;
    /// Force scale that keeps |∇θ| ≤ the hinge's gradient cap (1 when it is not degenerate).
    double gradientScale(const std::array<Vec3, 4>& g, int h) const;

    HingeSet m_set;
    std::string m_name;
    std::vector<char> m_active; ///< (|H|) or empty, see setActive
    mutable MatX3 m_buffer; ///< (|H|·4 × 3) per-corner forces; one evaluating thread per model
    mutable std::vector<Mat3>
        m_blocks; ///< (|H|·16) Jacobian blocks; one assembling thread per model
    bool m_plasticity;
    double m_yieldAngle;  ///< [rad]
    double m_plasticRate; ///< [1/s]
    ElementGather m_gather;
};

/// Plastic flow of hinge rest angles, shared by both bending models: where a hinge's fold θ
/// departs from its rest angle θ̄ by more than `yieldAngle` [rad], θ̄ moves towards θ by
/// min(1, rate·dt) of the excess (`rate` [1/s], `dt` [s]). `foldOf(h)` is hinge h's current fold
/// [rad]; a non-finite fold leaves its rest angle alone.
void flowRestAngles(VecX& restAngle, double yieldAngle, double rate, double dt,
                    const std::function<double(int)>& foldOf);

} // namespace atelier::sim
