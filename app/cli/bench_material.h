#pragma once
/// `atelier-cli bench tensile` (also `bench material`): a quasi-static uniaxial tension test of a
/// stretch model on a rectangular strip cut along the weft, the warp or the bias, measuring its
/// effective stretch stiffness and Poisson ratio.
/// Plain C++ (no CLI11): the parsing is in bench_command.cpp.

#include "patterns/fabric_fit.h"

#include "sim/material.h"
#include "sim/mesh/cloth_mesh.h"
#include "sim/scene.h"

#include <limits>
#include <string>

namespace atelier::app {

/// Which material axis the strip is pulled along.
enum class PullDirection {
    Weft, ///< along x
    Warp, ///< along y
    Bias, ///< at 45° between them: along (1, 1)/√2
};

/// What an orthotropic plate of `material` (E₁ = stretchWeft, E₂ = stretchWarp, G = shear,
/// ν₁₂ = poisson) shows in uniaxial tension along `direction`: along the weft E₁ and ν₁₂, along
/// the warp E₂ and ν₂₁ = ν₁₂·E₂/E₁, on the bias patterns::biasTensile.
patterns::StripResponse orthotropicResponse(const sim::Material& material, PullDirection direction);

/// Options of the uniaxial tension test.
struct TensionTestOptions {
    sim::StretchModel model = sim::StretchModel::Fem;
    sim::Triangulation triangulation = sim::Triangulation::Regular;
    PullDirection direction = PullDirection::Weft;
    /// Fabric; only stretchWeft, stretchWarp, shear, poisson and the stiffening law (fem) matter
    /// (the test is static).
    sim::Material material;
    double strain = 0.01;      ///< imposed engineering strain of the strip along the pull [-]
    double length = 0.5;       ///< strip length along the pull [m]
    double width = 0.25;       ///< strip width across the pull [m]
    int cellsLong = 20;        ///< cells along the pull
    int cellsWide = 10;        ///< cells across the pull
    std::uint32_t seed = 1;    ///< irregular triangulation seed
    bool crossSprings = false; ///< springs model: add cross springs over the hinges
    /// Newton stops when |r_free| <= tolerance·|reaction| (force norms) [-].
    double tolerance = 1e-10;
    int maxIterations = 50; ///< Newton iteration cap
};

/// What the tension test measured.
struct TensionTestResult {
    /// Requested stiffness along the pull: stretchWeft or stretchWarp [N/m].
    double requestedStretch = 0;
    /// Requested Poisson ratio: lateral contraction per strain along the pull, ν₁₂ (weft pull)
    /// or ν₂₁ = ν₁₂·E₂/E₁ (warp pull) [-].
    double requestedPoisson = 0;
    /// Reaction on the pulled edge / (width × strain) [N/m].
    double measuredStretch = 0;
    /// −(width change at mid-length / width) / strain [-].
    double measuredPoisson = 0;
    /// With a stiffening law (fem, a weft or warp pull): the strip's exact uniaxial secant
    /// stiffness at the imposed strain, reaction / (width × strain) of a homogeneous strip
    /// (`uniaxialLawStretch`); NaN otherwise [N/m].
    double lawStretch = std::numeric_limits<double>::quiet_NaN();
    double reactionForce = 0; ///< total force the pulling grip applies along the pull [N]
    double lateralStrain = 0; ///< width change at mid-length / width [-]
    int iterations = 0;       ///< Newton iterations
    double residual = 0;      ///< final |r_free| / |reaction| [-]
    bool converged = false;
    int vertices = 0;
    int triangles = 0;
    std::string error; ///< why the solve failed, empty otherwise
};

/// The reaction per width and strain of a homogeneous strip of `m` (St. Venant–Kirchhoff with its
/// stiffening law) pulled along weft or warp to engineering strain ε with free sides: Green
/// strain E = ε + ε²/2 along the pull, the lateral one compressive (so never stiffened), hence
/// S = E_pull·E + Δ·max(0, E − κ) exactly and the secant (1 + ε)·S / ε [N/m].
double uniaxialLawStretch(const sim::Material& m, PullDirection direction, double strain);

/// Runs the uniaxial tension test (see bench_material.cpp for the boundary conditions).
TensionTestResult runTensionTest(const TensionTestOptions& options);

/// `bench material` as a whole: options plus where to write the JSON.
struct MaterialBenchOptions {
    TensionTestOptions test;
    std::string fabric; ///< the preset the material was taken from, if any
    std::string out;    ///< JSON output path; empty = stdout only
};

/// Runs the test, prints a summary and writes the JSON atomically. Returns an exit code
/// (app/cli/commands.h).
int runMaterialBench(const MaterialBenchOptions& options);

} // namespace atelier::app
