#pragma once
/// The seed paper's triangle elastic model (Volino & Magnenat-Thalmann 1997, §3.1).

#include "sim/forces/element_gather.h"
#include "sim/forces/force_model.h"
#include "sim/material.h"
#include "sim/mesh/cloth_mesh.h"

#include <array>

namespace atelier::sim {

/// Corrected-elongation triangle model.
///
/// In triangle (P_0, P_1, P_2) edge I is opposite P_I, with rest length L_I and current
/// length l_I. An elongation d_J of edge J (joining P_I and P_k) moves P_k along J by
/// \f$ d_J M_k/(M_I + M_k) \f$ (M = inverse mass), which lengthens edge I by that times
/// \f$ c_k \f$, the cosine of the triangle's angle at P_k. Asking the three edges' contributions
/// to add up to each edge's actual elongation gives the 3×3 system of the paper
/// \f[ d_I + \sum_{J \ne I} \frac{M_k}{M_I + M_k}\, c_k\, d_J = l_I - L_I . \f]
/// The paper linearises with the angles held fixed; we hold them at the rest shape, so the
/// matrix is constant per triangle and inverted once (this makes the model as cheap as springs
/// per evaluation and its Jacobian exact). The masses are the lumped masses (pins ignored).
///
/// Stiffness (the paper gives none): edge I carries the tension
/// \f$ T_I = k_I d_I \f$ with \f$ k_I = 2\mu\, A / L_I^2 \f$, \f$ 2\mu = Y/(1+\nu) \f$,
/// Y the weft/warp modulus interpolated at the edge's rest direction. For an equilateral
/// triangle with equal masses this is exactly an isotropic membrane of shear modulus μ and
/// no Poisson effect (derivation in README). The Poisson coefficient, which the paper says
/// the model represents but does not say how, enters as an area-change term carried by the
/// same edges: \f$ T_I \mathrel{+}= \lambda A\, \mathrm{tr}\,\varepsilon\; \beta_I / L_I \f$
/// with \f$ \lambda = Y\nu/(1-\nu^2) \f$ and \f$ \mathrm{tr}\,\varepsilon = \sum_I \beta_I
/// (l_I - L_I)/L_I \f$ the trace of the triangle's small-strain tensor from its edge strains.
/// Together the tensions are \f$ T = G\,(l - L + \tau \dot l) \f$ with a constant 3×3 G per
/// triangle (τ = damping time constant). Forces act along the edges:
/// \f$ f = -\sum_I T_I\, \partial l_I / \partial x \f$. G is not symmetric in general, so
/// there is no energy; the Definite Jacobian uses the PSD part of sym(G).
class VolinoStretch : public ForceModel {
  public:
    /// `localMasses`: (|V|) lumped masses of this cloth's vertices [kg] (the paper's M_i are
    /// their inverses).
    VolinoStretch(const ClothMesh& mesh, int offset, const Material& material,
                  const VecX& localMasses);

    std::string_view name() const override { return "stretch.volino"; }
    void addForces(const MatX3& x, const MatX3& v, MatX3& f) const override;
    void jacobianPattern(std::vector<std::pair<int, int>>& pairs) const override;
    void addJacobian(const MatX3& x, const MatX3& v, double kx, double kv, JacobianMode mode,
                     BlockSparseMatrix& J) const override;
    /// Definite ∂f/∂v uses the projected coupling matrix, so it is not the damping force.
    void addDampingProduct(const MatX3& x, const MatX3& v, MatX3& f) const override;

  private:
    struct Element {
        std::array<int, 3> v;       ///< global vertex indices
        std::array<double, 3> rest; ///< L_I, edge I opposite vertex I [m]
        Mat3 G;                     ///< tension per elongation [N/m]
        Mat3 Gdefinite;             ///< PSD part of sym(G)
    };
    std::vector<Element> m_elements;
    double m_damping = 0;
    ElementGather m_gather;
    mutable MatX3 m_buffer; ///< (|F|·3 × 3) per-corner forces; one evaluating thread per model
};

} // namespace atelier::sim
