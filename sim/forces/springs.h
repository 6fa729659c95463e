#pragma once
/// The plain spring-mass model: the baseline the seed paper compares against.

#include "sim/forces/element_gather.h"
#include "sim/forces/force_model.h"
#include "sim/material.h"
#include "sim/mesh/cloth_mesh.h"

#include <array>

namespace atelier::sim {

/// Below this length [m] an edge's direction is taken as undefined.
inline constexpr double LENGTH_EPS = 1e-12;

/// Young's modulus [N/m] of the fabric along the in-plane direction d (material frame, any
/// length): E_weft·cos²φ + E_warp·sin²φ, the mean of the two for d = 0. The stretch models'
/// (springs', Volino's) stiffness of one edge.
double directionalModulus(const Material& m, const Vec2& d);

/// Linear edge springs with strain-rate damping.
///
/// Each edge e of rest length L_e is a spring of stiffness
/// \f$ k_e = Y(\theta_e)\, A_e / L_e^2 \f$ [N/m], where \f$ A_e \f$ is a third of the rest
/// area of the triangles beside the edge and \f$ Y(\theta) = Y_w\cos^2\theta + Y_p\sin^2\theta \f$
/// interpolates the weft/warp moduli by the edge's rest angle to the weft. So a spring stores
/// \f$ \tfrac12 Y A_e \varepsilon^2 \f$, the 1D share of the membrane energy of its area; the
/// network's effective modulus and Poisson ratio depend on the mesh and are measured by
/// `atelier-cli bench material` (see README). Optional cross springs join the two opposite
/// vertices of each hinge, with \f$ k = G\,(A_0 + A_1)/3 / L^2 \f$ (G = shear modulus); they
/// resist shear and, weakly, bending.
///
/// Force on i from spring (i, j): \f$ f_i = k(l - L)\,u + c\,k\,((v_j - v_i)\cdot u)\,u \f$,
/// \f$ u = (x_j - x_i)/l \f$, c = material damping time constant [s].
class SpringStretch : public ForceModel {
  public:
    SpringStretch(const ClothMesh& mesh, int offset, const Material& material, bool crossSprings);

    std::string_view name() const override {
        return m_cross ? "stretch.springs+cross" : "stretch.springs";
    }
    void addForces(const MatX3& x, const MatX3& v, MatX3& f) const override;
    bool hasEnergy() const override { return true; }
    double energy(const MatX3& x) const override;
    void jacobianPattern(std::vector<std::pair<int, int>>& pairs) const override;
    void addJacobian(const MatX3& x, const MatX3& v, double kx, double kv, JacobianMode mode,
                     BlockSparseMatrix& J) const override;

    int springCount() const { return static_cast<int>(m_rest.size()); }

  private:
    std::vector<std::array<int, 2>> m_ends; ///< global vertex indices
    std::vector<double> m_rest;             ///< rest lengths [m]
    std::vector<double> m_stiffness;        ///< [N/m]
    double m_damping = 0;                   ///< [s]
    bool m_cross = false;
    ElementGather m_gather;
    mutable MatX3 m_buffer; ///< (|S|·2 × 3) per-end forces; one evaluating thread per model
};

} // namespace atelier::sim
