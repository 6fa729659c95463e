#pragma once
/// The geometry behind the pattern view's tools, as free functions over the garment document:
/// the panel a drawing makes, the seam ranges a pick along an outline makes, and seam lengths.
/// No Qt here; the view (ui/widgets/pattern_view.h) turns mouse events into these calls.

#include "patterns/document.h"
#include "patterns/garment.h"

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace atelier::ui {

/// The panel a drawing of `corners` makes (pattern coordinates [m], in either turning sense;
/// straight edges): its outline counter-clockwise, named "panel N" with the first N the
/// document does not use, in the document's first material (none when it has none), and, as
/// an imported DXF piece, on the torso slots in turn (front, back, front, ...), each pair 5 cm
/// further out, so that none starts inside another.
patterns::Panel drawnPanel(const patterns::GarmentDocument& document,
                           const std::vector<patterns::Vec2>& corners);

/// A point of a free curve drawn with the pen tool: where it was put down, and for a smooth
/// point its outgoing Bézier handle (the incoming one mirrors it through the point) [m].
struct PenPoint {
    patterns::Vec2 at = patterns::Vec2::Zero();
    std::optional<patterns::Vec2> handle;
};

/// The panel of a closed free curve through `points` (≥ 3), as drawnPanel: a segment is a cubic
/// Bézier when either end has a handle, a line otherwise; drawn clockwise, the points are taken
/// in reverse, each handle mirrored, so the outline runs counter-clockwise.
patterns::Panel drawnCurvePanel(const patterns::GarmentDocument& document,
                                std::vector<PenPoint> points);

/// A point on a contour: edge `edge` (its index) at curve parameter `t` ∈ [0, 1].
struct OutlinePlace {
    int edge = 0;
    double t = 0;
};

/// The seam ranges along `panel`'s outline from `from` to `to`, forward (with the outline's
/// direction) or backward: the first and last edges partly (from `from.t`, to `to.t`), the
/// edges between whole; ranges of zero length are left out. From and to on one edge give one
/// range when the direction agrees with their order, else the way round the whole outline.
std::vector<patterns::doc::SeamRange>
outlineRanges(const patterns::doc::Panel& panel, OutlinePlace from, OutlinePlace to, bool forward);

/// The same chain run the other way: ranges in reverse order, each with t0 and t1 swapped.
std::vector<patterns::doc::SeamRange> reversedRanges(std::vector<patterns::doc::SeamRange> ranges);

/// Arc length of a chain of seam ranges [m]; ranges on a missing panel or edge count 0.
double rangesLength(const patterns::GarmentDocument& document,
                    const std::vector<patterns::doc::SeamRange>& ranges);

/// The two sides' lengths of a seam [m].
std::pair<double, double> seamLengths(const patterns::GarmentDocument& document,
                                      const patterns::doc::Seam& seam);

/// Largest |bulge| the arc handle sets: tan(θ/4) = 10, a sweep of 4·atan(10) ≈ 337° [-].
inline constexpr double MAX_HANDLE_BULGE = 10.0;

/// The bulge of the arc from `start` to `end` whose middle is the point of the chord's
/// perpendicular bisector nearest `through` [m]: with c = |end − start| and h the signed
/// distance of `through` from the chord (positive on its left), the sagitta is |h| and
/// bulge = tan(θ/4) = −2h/c (a counter-clockwise arc, bulge > 0, bulges to the right of its
/// chord), clamped to ±MAX_HANDLE_BULGE; 0 for a chord of zero length.
double bulgeThrough(const patterns::Vec2& start, const patterns::Vec2& end,
                    const patterns::Vec2& through);

/// "seam N" with the first N no seam of the document is named.
std::string newSeamName(const patterns::GarmentDocument& document);

} // namespace atelier::ui
