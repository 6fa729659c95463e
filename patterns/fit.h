#pragma once
/// Whether a draped garment fits its body: how far each panel is stretched at the end of the
/// drape, and a verdict naming the panels and seams that do not fit.

#include "patterns/assemble.h"

#include <string>
#include <string_view>
#include <vector>

namespace atelier::patterns {

/// How far one panel is stretched at positions x. Per triangle, the largest principal stretch
/// λ of its deformation gradient F (rest triangle in the pattern plane → triangle at x):
/// \f[ \lambda^2 = \max \operatorname{eig}(F^{\mathsf T}F),\qquad F = [x_1 - x_0,\; x_2 - x_0]
///     \,[\bar u_1 - \bar u_0,\; \bar u_2 - \bar u_0]^{-1} \f]
/// and the strain λ − 1, rotation-free and independent of the mesh: an exported OBJ gives the
/// same from its positions and UVs (tools/fit_strain.py).
struct PanelStrain {
    std::string panel;
    double maxStrain = 0; ///< largest λ − 1 over its triangles [-]
    double maxHeight = 0; ///< height (y) of that triangle's centroid [m]
    double over5 = 0;     ///< share of its rest area stretched beyond 5% [-]
    double over10 = 0;    ///< share beyond 10% [-]
};

/// Per panel (scene cloth), at positions x (global, |V|×3).
std::vector<PanelStrain> panelStrains(const AssembledGarment& assembled, const sim::MatX3& x);

enum class FitLevel {
    Fits,       ///< no panel stretched beyond 5% over 5% of its area, seams closed
    Tight,      ///< a panel stretched beyond 5% over 5% or more of its area
    DoesNotFit, ///< beyond 10% over 5% or more, a seam left open, or cloth through cloth
};

/// "fits", "tight", "does not fit".
std::string_view fitName(FitLevel fit);

/// Share of a panel's area beyond a strain that makes it count (5%: a fabric's comfortable
/// wearing ease; 10%: beyond a woven's elastic range). The 10 mm samples on the default female
/// body keep under 1% of any panel beyond 10% (docs/patterns-and-draping.md).
inline constexpr double FIT_AREA_SHARE = 0.05;

struct FitVerdict {
    FitLevel fit = FitLevel::Fits;
    std::string message; ///< what does not fit, where and by how much; empty when it fits
};

/// The verdict from the panels' strains, the seams left open after sewing (ForcedWeld per seam:
/// its unwelded pairs and their widest gap) and the count of intersecting triangle pairs, of
/// which `withBody` are cloth–obstacle pairs (Simulation::intersectingTrianglePairs).
FitVerdict fitVerdict(const std::vector<PanelStrain>& strains,
                      const std::vector<ForcedWeld>& openSeams, int intersectingPairs,
                      int withBody);

/// A drape's fit: its panels' strains and the verdict (DrapeSession::fit).
struct GarmentFit {
    std::vector<PanelStrain> panels;
    FitVerdict verdict;

    /// Largest strain of any panel [-] (the report's `strain_max`).
    double largestStrain() const;
    /// Largest share of a panel's area beyond 10% strain [-]
    /// (`strain_beyond_10pct_share_max`).
    double largestShareBeyond10() const;
};

} // namespace atelier::patterns
