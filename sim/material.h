#pragma once
/// Fabric mechanical parameters, SI.

#include <string>

namespace atelier::sim {

/// Mechanical parameters of one fabric. The material frame is the pattern's: weft = x, warp = y.
struct Material {
    std::string name = "custom";
    double density = 0.15;     ///< areal density [kg/m²]
    double stretchWeft = 2000; ///< 2D Young's modulus along weft (x) [N/m]
    double stretchWarp = 2000; ///< 2D Young's modulus along warp (y) [N/m]
    double shear = 500;        ///< in-plane shear modulus [N/m]
    double poisson =
        0.3; ///< Poisson ratio ν_weft,warp (contraction along warp per weft strain) [-]
    /// Bending rigidity per unit width B [N·m]: moment per width = B × curvature, as a
    /// cantilever tester (ASTM D1388) or KES-FB2 reports it, with the continuum bending model
    /// (BendingModel::Continuum) on any mesh; with the hinge model (the default for now) it is
    /// a per-hinge coefficient (sim/forces/bending.h). Isotropic unless the per-direction values
    /// are set (the hinge model ignores them).
    double bending = 1e-5;
    /// B of a strip cut along the weft (curvature along x) [N·m]; 0 = `bending`.
    double bendingWeft = 0;
    /// B of a strip cut along the warp (curvature along y) [N·m]; 0 = `bending`.
    double bendingWarp = 0;
    /// B of a strip cut on the bias (45°) [N·m]; 0 = as an isotropic plate would be between
    /// weft and warp (sim/forces/continuum_bending.h, BendingRigidity).
    double bendingBias = 0;
    /// Stiffening stretch law (model `fem` only): the Green strain along weft or warp beyond
    /// which the fabric's tangent modulus rises to `stretchWeftBeyond` / `stretchWarpBeyond`
    /// (yarns straightening out of their crimp) [-]; 0 = linear.
    double stretchKnee = 0;
    /// Tangent 2D modulus along weft beyond the knee [N/m]; 0 = `stretchWeft` (no stiffening).
    double stretchWeftBeyond = 0;
    /// Tangent 2D modulus along warp beyond the knee [N/m]; 0 = `stretchWarp` (no stiffening).
    double stretchWarpBeyond = 0;
    double damping =
        2e-4; ///< strain-rate damping: time constant of stiffness-proportional viscosity [s]
    double staticFriction = 0.4;  ///< Coulomb static friction coefficient [-]
    double kineticFriction = 0.3; ///< Coulomb kinetic friction coefficient [-]
    /// Bending plasticity: fold-angle deviation beyond which the rest angle yields [rad];
    /// <= 0 disables plasticity.
    double plasticYieldAngle = 0.0;
    /// Bending plasticity: rate at which the rest angle follows beyond the yield [1/s].
    double plasticRate = 1.0;
};

} // namespace atelier::sim
