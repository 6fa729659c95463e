#pragma once
/// What the overlays of a picture show, computed from a garment's arrays: strain against the
/// rest shape (the pattern UVs), seam edges, closeness to the body. Plain array functions; the
/// app layer turns them into colours and lines of a Scene. The strain legend is drawn into the
/// finished picture (text.h).

#include "ui/render/scene.h"

#include "io/png.h"

#include "sim/core/types.h"

#include <vector>

namespace atelier::render {

/// (|F|) signed principal strain of each triangle [-]: with F (3×2) the deformation gradient
/// from the rest triangle (`rest`, (|V|×2) [m], e.g. the pattern coordinates a drape writes
/// as UVs) to the triangle in `positions` (|V|×3) [m], and σ₁ ≥ σ₂ its singular values (the
/// principal stretches), the strain is σ₁ − 1 when σ₁ − 1 ≥ 1 − σ₂ (stretched) and σ₂ − 1
/// otherwise (compressed). 0.05 = 5% longer than cut. NaN where the rest triangle has no area
/// (no strain to show; drawn grey).
///
/// \f$F = [x_1 - x_0,\ x_2 - x_0]\,[u_1 - u_0,\ u_2 - u_0]^{-1}\f$,
/// \f$\sigma_{1,2}^2\f$ the eigenvalues of \f$F^\top F\f$.
sim::VecX triangleStrain(const sim::MatX3& positions, const sim::MatX3i& triangles,
                         const sim::MatX2& rest);

/// Colours of strain values: white at 0, red for stretch, blue for compression, saturated at
/// ±`rangeFraction` (0.1 = ±10%), grey where NaN.
std::vector<Colour> strainColours(const sim::VecX& strain, double rangeFraction);

/// Draws the strain legend into a picture: a vertical colour bar along the right edge with
/// tick labels at −range, −range/2, 0, +range/2, +range in % and the title "strain", on a
/// translucent white panel. Sized from the picture's height (readable at 256 pixels and up).
void drawStrainLegend(io::RgbaImage& image, double rangeFraction);

/// (|E|×2) the seam edges of a garment given as panels (each triangle's panel in
/// `trianglePanel`, (|F|)): the boundary edges of a panel whose two end vertices lie within
/// `tolerance` [m] of boundary vertices of one other panel (sewn cloth lies together after a
/// drape; unsewn hems, necklines and cuffs do not).
sim::MatX2i seamEdgesByPosition(const sim::MatX3& positions, const sim::MatX3i& triangles,
                                const std::vector<int>& trianglePanel, double tolerance);

/// (|V|) signed distance of each garment vertex to a closed body surface [m] (negative inside),
/// searched up to `maxDistance`; +inf farther than that.
sim::VecX bodyDistances(const sim::MatX3& garment, const sim::MatX3& bodyPositions,
                        const sim::MatX3i& bodyTriangles, double maxDistance);

} // namespace atelier::render
