#pragma once
/// A fabric preset from what a textile lab measures, and what a preset will show in the lab:
/// the fit behind `atelier-cli fabric fit`.
///
/// Bending length (ASTM D1388, Peirce 1930): the overhang of a strip whose tip line falls
/// 41.5° below the horizontal, halved; in the heavy elastica that overhang L has
/// ρgL³/B = 8 (sim/analysis/heavy_elastica.h), so c = L/2 = (B/(ρg))^(1/3), B = ρg·c³.
/// Tensile stiffness per width at small strain along the weft, the warp and the bias (a strip
/// at 45°) gives the in-plane shear modulus of the orthotropic plate:
/// 1/G = 4/E₄₅ − 1/E₁ − 1/E₂ + 2ν₁₂/E₁ (biasTensile below, inverted).

#include "sim/core/result.h"
#include "sim/material.h"

#include <optional>

namespace atelier::patterns {

/// What the lab measured; every value optional except the density (SI units).
struct LabFabric {
    double density = 0; ///< areal density [kg/m²]
    /// Bending length c per direction (weft: a strip cut along the weft) [m]; or the rigidity.
    std::optional<double> bendingLengthWeft, bendingLengthWarp, bendingLengthBias;
    std::optional<double> bendingWeft, bendingWarp, bendingBias; ///< B [N·m]
    /// Tensile stiffness per width at small strain [N/m] per direction.
    std::optional<double> tensileWeft, tensileWarp, tensileBias;
    std::optional<double> poisson; ///< ν₁₂ [-]
};

/// Bending rigidity per width [N·m] of a strip of bending length `c` [m] and areal density
/// `density` [kg/m²]: ρg·c³.
double rigidityOfBendingLength(double c, double density);

/// Bending length [m] of a strip of rigidity `rigidity` [N·m]: (B/(ρg))^(1/3).
double bendingLengthOf(double rigidity, double density);

/// `base` with what the lab measured put in: density, B per direction (the isotropic `bending`
/// = √(B_weft·B_warp) where both are given, else the one given), stretch per direction, the
/// shear from the bias stiffness, ν₁₂. Errors name the measurement (`tensile_bias`, ...) and why:
/// not positive, a rigidity pair no plate has (sim::bendingRigidity), a bias stiffness outside
/// what weft and warp allow (G ≤ 0), both a bending length and a rigidity for one direction.
Result<sim::Material> fitFabric(const LabFabric& lab, const sim::Material& base);

/// Stiffness [N/m] and Poisson ratio ν₄₅ [-] of a strip of the orthotropic plate `material` cut
/// at 45° and pulled at small strain: its compliance turned by 45° (e.g. Jones, Mechanics of
/// Composite Materials, §2.6), 1/E₄₅ = (1/E₁ + 1/E₂ + 1/G − 2ν₁₂/E₁)/4,
/// ν₄₅ = E₄₅·(ν₁₂/(2E₁) − (1/E₁ + 1/E₂ − 1/G)/4).
struct StripResponse {
    double stretch = 0; ///< [N/m]
    double poisson = 0; ///< [-]
};
StripResponse biasTensile(const sim::Material& material);

/// What the lab will measure on `material`: bending length [m] and rigidity [N·m] per direction.
struct FabricFigures {
    double bendingLengthWeft = 0, bendingLengthWarp = 0, bendingLengthBias = 0; ///< [m]
    double bendingWeft = 0, bendingWarp = 0, bendingBias = 0;                   ///< [N·m]
    double tensileBias = 0; ///< stiffness of a bias strip at small strain [N/m]
};
Result<FabricFigures> fabricFigures(const sim::Material& material);

} // namespace atelier::patterns
