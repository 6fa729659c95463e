#pragma once
/// Linear aerodynamic drag on the normal relative velocity of cloth triangles.

#include "sim/forces/element_gather.h"
#include "sim/forces/force_model.h"
#include "sim/mesh/cloth_mesh.h"
#include "sim/scene.h"

namespace atelier::sim {

/// Per triangle, with n = (x₁−x₀)×(x₂−x₀), current area A = |n|/2, n̂ = n/|n|, mean velocity
/// v̄ = (v₀+v₁+v₂)/3 and wind w:
/// \f[ f_{tri} = -c\,A\,\big((\bar v - w)\cdot\hat n\big)\,\hat n
///             = -\frac{c}{2}\,\frac{(\bar v - w)\cdot n}{|n|}\,n \f]
/// split equally over the three vertices (c = `AirOptions::dragCoefficient` [N·s/m³]).
/// The drag acts only on the normal component, so it does not depend on the orientation sign
/// of the triangle. Not conservative (no energy); not internal (the net force is the drag).
///
/// Jacobian: ∂f/∂v is exact in both modes, −(c/18)·n nᵀ/|n| for every vertex pair (NSD).
/// `Exact` ∂f/∂x differentiates n (∂n/∂x₀ = [x₂−x₁]_×, cyclic);
/// `Definite` drops ∂f/∂x (zero, trivially symmetric NSD).
/// A triangle with |n| ≤ 1e-20 m² contributes nothing.
class AirDrag : public ForceModel {
  public:
    /// `offset`: global index of the mesh's vertex 0.
    AirDrag(const ClothMesh& mesh, int offset, const AirOptions& air);

    std::string_view name() const override { return "air"; }
    void addForces(const MatX3& x, const MatX3& v, MatX3& f) const override;
    void jacobianPattern(std::vector<std::pair<int, int>>& pairs) const override;
    void addJacobian(const MatX3& x, const MatX3& v, double kx, double kv, JacobianMode mode,
                     BlockSparseMatrix& J) const override;

  private:
    int m_offset;
    MatX3i m_triangles;   ///< (|F|×3) local
    double m_coefficient; ///< c [N·s/m³]
    Vec3 m_wind;          ///< [m/s]
    ElementGather m_gather;
};

} // namespace atelier::sim
