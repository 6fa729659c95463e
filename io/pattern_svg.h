#pragma once
/// The garment's 2D pattern as SVG at real size, for printing and plotting
/// (`atelier-cli export-pattern`; docs/file-formats.md "Patterns out").
///
/// The sheet's width and height are in millimetres with a viewBox in millimetres, so one user
/// unit is one millimetre printed at 100 %. One group per panel (`<g class="panel">`, its name
/// in `<title>`), holding paths of these classes:
/// - `cut-line`: the outline and the holes offset by the seam allowance away from the fabric
///   (patterns::offsetPolyline: a polyline, curves sampled to `curveToleranceMm`, round
///   corners); with no allowance, the outline itself in true curves;
/// - `sewing-line`: the outline, dashed, in true curves (`L`, `Q`, `C`, `A`), one path; holes
///   are further `sewing-line hole` paths;
/// - `internal-line` (fold lines dash-dotted), `dart` (the dart's centre line, mouth to tip),
///   `notch` (ticks across the cut line), `grain-line` (a double arrow along the warp),
///   `seam-mark` (a tick across the sewing line where each seam edge starts and ends, and
///   `<text class="seam-label">` with the seam's name beside the edge);
/// - `<text class="label">`: the panel's name, fabric, and "cut 1" (or "cut 1 mirrored" for a
///   PanelSide::Back panel, which is drawn mirrored as it is cut).
/// Pattern y (up) points down the sheet. Panels are packed in shelves, tallest first, with a
/// 100 mm calibration square (`<g id="calibration">`), on a sheet of the width asked for or
/// of the width that makes the sheet smallest; no two panels' drawings overlap.

#include "io/result.h"

#include "patterns/garment.h"

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace atelier::io {

struct PatternSvgOptions {
    /// Cut line outside the sewing line [mm]; 0 = the outline is the cut line.
    double seamAllowanceMm = 10.0;
    /// Width of the sheet, e.g. a plotter's roll [mm]; 0 = the width from the widest panel to
    /// all in one row that gives the smallest sheet.
    double sheetWidthMm = 0.0;
    /// Space between panels and around the sheet [mm].
    double gapMm = 10.0;
    /// Largest distance between a curve and the polyline of its offset [mm].
    double curveToleranceMm = 0.02;
};

/// Where a panel went on the sheet.
struct PatternSvgPanel {
    std::string name;
    /// The panel's drawing (paths and text) lies in [minX, maxX] × [minY, maxY] [mm].
    double minX = 0, minY = 0, maxX = 0, maxY = 0;
};

/// The SVG text and its layout.
struct PatternSvg {
    std::string text;
    double widthMm = 0, heightMm = 0;
    std::vector<PatternSvgPanel> panels; ///< in the garment's panel order
};

/// The largest seam allowance accepted [mm].
inline constexpr double MAX_SEAM_ALLOWANCE_MM = 500.0;

/// The most points a panel's outline and holes may take as polylines (at the curve
/// tolerance). The samples' largest panel takes 261; the outward and inward offsets of a
/// 20,000-corner polygon took 0.12 s, of 100,000 corners 2.8 s (docs/benchmarks.md).
inline constexpr std::size_t MAX_PANEL_POINTS = 20000;

/// The pattern of `garment` as SVG. A seam allowance that is negative, not finite or above
/// MAX_SEAM_ALLOWANCE_MM, a garment without panels, a panel over MAX_PANEL_POINTS or wider
/// than the sheet asked for, or a seam or notch naming a panel or segment that does not exist
/// is an error.
Result<PatternSvg> patternSvg(const patterns::Garment& garment, const PatternSvgOptions& options);

/// Writes `patternSvg(garment, options)` to `path` atomically.
Result<PatternSvg> writePatternSvg(const std::filesystem::path& path,
                                   const patterns::Garment& garment,
                                   const PatternSvgOptions& options);

} // namespace atelier::io
