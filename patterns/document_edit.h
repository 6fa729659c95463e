#pragma once
/// Edits of a GarmentDocument, as free functions that keep every reference valid. Each returns
/// an Edit: the state before and after of the few panels and seams it touched (whole objects,
/// ids included) and of the id counter, so `undo` restores the document exactly and `redo`
/// replays it. A failed edit returns an Error and leaves the document untouched.
///
/// Undo restores the id counter too: an id freed by an undo is handed out again only by an
/// edit made after it, when the undone edit can no longer be redone (an undo stack drops its
/// redo entries on a new edit), so no live object or redoable edit ever shares an id.

#include "patterns/document.h"

#include "sim/core/result.h"

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace atelier::patterns {

/// One object before and after an edit (nullopt: absent) with its position in its list.
template <class T> struct Change {
    std::optional<T> before;
    std::optional<T> after;
    std::size_t beforeIndex = 0;
    std::size_t afterIndex = 0;
};

struct Edit {
    std::string description; ///< for an undo stack's menu: "split edge #12 of \"front\""
    std::vector<Change<doc::Panel>> panels;
    std::vector<Change<doc::Seam>> seams;
    std::uint32_t nextIdBefore = 0;
    std::uint32_t nextIdAfter = 0;
    /// The document's fabrics before and after, when the edit changed them (the list is short
    /// and kept whole); nullopt when it did not.
    std::optional<std::vector<GarmentMaterial>> materialsBefore;
    std::optional<std::vector<GarmentMaterial>> materialsAfter;
    /// The id of what the edit created (the point of a split, the panel of an add or a
    /// duplicate, the seam of an add); 0 when none.
    std::uint32_t created = 0;
};

/// The edit that takes the document from `edit`'s after-state back to its before-state.
Edit inverse(const Edit& edit);
/// Puts the document in `edit`'s after-state (from its before-state).
void redo(GarmentDocument& document, const Edit& edit);
/// Puts the document back in `edit`'s before-state (from its after-state).
void undo(GarmentDocument& document, const Edit& edit);

/// Moves a point of the outline, a hole or an internal line to `position` [m]; curve handles
/// stay where they are.
Result<Edit> movePoint(GarmentDocument& document, PanelId panel, PointId point, Vec2 position);

/// Inserts a point on an outline or hole edge at curve parameter t ∈ (0, 1): the edge keeps
/// its id for the first half, a new edge is the second; the curve is split exactly (de
/// Casteljau, arc sweep). Seam ranges and notches on the edge are re-expressed on the two
/// halves (a range across t becomes two), so they cover the same curve. Refused on a dart leg.
Result<Edit> splitEdge(GarmentDocument& document, PanelId panel, EdgeId edge, double t);

/// `splitEdge` at t, then the new point moved to `position` [m]: one edit.
Result<Edit> addPoint(GarmentDocument& document, PanelId panel, EdgeId edge, double t,
                      Vec2 position);

/// Removes an outline or hole point: its outgoing edge goes, its incoming edge now ends at the
/// next point. Refused when the contour would have fewer than 3 points, when a seam or dart
/// uses either edge (the seam would move to another curve) or a notch the outgoing edge.
Result<Edit> deletePoint(GarmentDocument& document, PanelId panel, PointId point);

/// Sets an edge's curve kind and handles (outline, hole or internal line).
Result<Edit> setCurve(GarmentDocument& document, PanelId panel, EdgeId edge,
                      const doc::Curve& curve);

/// Adds a drawn panel with new ids (its darts and notches by outline index); its name must be
/// new and its outline have ≥ 3 segments. `created` is the panel's id.
Result<Edit> addPanel(GarmentDocument& document, const Panel& drawn);

/// Removes a panel and every seam with a range on it.
Result<Edit> removePanel(GarmentDocument& document, PanelId panel);

/// Adds a seam; each range must be on an existing panel's outline edge, t0, t1 ∈ [0, 1],
/// t0 ≠ t1, both sides non-empty. `created` is the seam's id.
Result<Edit> addSeam(GarmentDocument& document, std::string name, std::vector<doc::SeamRange> a,
                     std::vector<doc::SeamRange> b);

Result<Edit> removeSeam(GarmentDocument& document, SeamId seam);

/// Sews side b the other way round: its ranges in reverse order, each reversed.
Result<Edit> reverseSeam(GarmentDocument& document, SeamId seam);
/// Sets how a seam bends once sewn: its rest fold angle [rad] in (−π, π) (0 = flat) and its
/// rigidity as a multiple of its cloths' (≥ 0; 1 = as the cloth), doc::Seam.
Result<Edit> setSeamBending(GarmentDocument& document, SeamId seam, double foldAngle,
                            double bendingScale);

/// Mirrors a panel about the vertical line through the middle of its outline's points: every
/// point, handle and the grain line; contours are reversed to keep their orientation, so seam
/// ranges and notches on them map t → 1 − t and dart legs swap. Ids stay.
Result<Edit> mirrorPanel(GarmentDocument& document, PanelId panel);

/// A copy of a panel with new ids under a new name (seams are not copied). `created` is the
/// copy's id.
Result<Edit> duplicatePanel(GarmentDocument& document, PanelId panel, std::string name);

/// Renames a panel (a new, non-empty name); seams refer to ids and are unaffected.
Result<Edit> renamePanel(GarmentDocument& document, PanelId panel, std::string name);

/// Places a panel on a body slot.
Result<Edit> placePanel(GarmentDocument& document, PanelId panel, const Placement& placement);

/// Places several panels at once, each as placePanel: one edit (one undo step). Refused, the
/// document untouched, when any of them is.
Result<Edit> placePanels(GarmentDocument& document,
                         const std::vector<std::pair<PanelId, Placement>>& placements);

/// Placements that lay `panels` side by side around slot `slot`, in the order given, `gap` [m]
/// apart, the row centred on the slot's middle line (offset around 0): panel i's offset around
/// is u_i − lo_i with u_0 = −W/2, u_{i+1} = u_i + (hi_i − lo_i) + gap and W the row's width,
/// where [lo_i, hi_i] is the panel's extent around the slot as placementCoordinates lays it
/// (mirrored for a Back panel, about the middle of its box, turned by its rotation). Each keeps
/// its rotation, clearance and offset along the slot; panels not in the document are left out.
std::vector<std::pair<PanelId, Placement>> sideBySide(const GarmentDocument& document,
                                                      const std::vector<PanelId>& panels,
                                                      const std::string& slot, double gap = 0.02);

/// Meshes a panel at its own particle distance [m] (0: the drape's), 1 mm to 1 m.
Result<Edit> setPanelParticleDistance(GarmentDocument& document, PanelId panel, double distance);

/// Gives a panel the fabric `material`, one of the document's materials.
Result<Edit> setPanelMaterial(GarmentDocument& document, PanelId panel, std::string material);

/// Sets the values of the document's fabric named `material.name`, or adds it when there is
/// none of that name. The name must not be empty; the values must be finite, with density,
/// stretch and shear moduli positive, Poisson's ratio in [0, 1), and bending, damping,
/// frictions and plasticity not negative (as io's material files).
Result<Edit> setMaterial(GarmentDocument& document, const GarmentMaterial& material);

/// Pins a point of a panel (`pin`'s id is ignored; a new one is handed out and is `created`).
/// The point must lie inside the panel, or the notch be one of the panel's; a position must be
/// finite and a release time at least 0.
Result<Edit> addPin(GarmentDocument& document, PanelId panel, const doc::Pin& pin);

/// Removes a pin of a panel.
Result<Edit> removePin(GarmentDocument& document, PanelId panel, PinId pin);

/// Adds a notch on an outline edge at curve parameter t ∈ [0, 1]. `created` is its id.
Result<Edit> addNotch(GarmentDocument& document, PanelId panel, EdgeId edge, double t);

/// Removes a notch of a panel; refused while a pin holds it.
Result<Edit> removeNotch(GarmentDocument& document, PanelId panel, NotchId notch);

/// Adds an internal line of straight edges through `points` (≥ 2, consecutive ones apart) [m],
/// the whole line inside the panel and out of its holes; `foldAngle` is the rest angle of the
/// hinges along it [rad], in (−π, π). `created` is its id.
Result<Edit> addInternalLine(GarmentDocument& document, PanelId panel,
                             const std::vector<Vec2>& points, double foldAngle = 0);

/// Removes an internal line of a panel.
Result<Edit> removeInternalLine(GarmentDocument& document, PanelId panel, LineId line);

/// Sets the rest angle of the hinges along an internal line [rad], in (−π, π).
Result<Edit> setFoldAngle(GarmentDocument& document, PanelId panel, LineId line, double angle);

/// Cuts a dart into an outline edge: two points `width` apart along the edge [m], centred at
/// curve parameter `t`, and a tip `depth` inside the panel from the middle of the chord between
/// them [m]; the two legs to the tip are straight and sewn together when the garment drapes.
/// The cut part of the edge must carry no seam or notch, and the legs stay inside the panel.
/// `created` is the dart's id.
Result<Edit> addDart(GarmentDocument& document, PanelId panel, EdgeId edge, double t, double width,
                     double depth);

/// A dart's size: the distance between its legs' bases (width) and from the middle of the chord
/// between them to its tip (depth) [m].
struct DartSize {
    double width = 0;
    double depth = 0;
};

/// The size of dart `dart` of `panel`; nullopt when the panel has no such dart.
std::optional<DartSize> dartSize(const doc::Panel& panel, DartId dart);

/// Resizes a dart: its bases slide along the chord between them, `width` apart about its middle
/// [m], and its tip moves along its direction from that middle to `depth` from it [m]. The
/// outline edges beside the bases keep their other ends (and curve handles). Refused when a
/// size is not positive, a base would pass the far end of its neighbouring edge ("wider than its
/// edge allows") or the legs would leave the panel.
Result<Edit> setDartSize(GarmentDocument& document, PanelId panel, DartId dart, double width,
                         double depth);

/// Removes a dart and its tip: the outline runs straight from one leg's base to the other's,
/// through the edge of the first leg. Refused while a seam or notch is on a leg.
Result<Edit> removeDart(GarmentDocument& document, PanelId panel, DartId dart);

/// Sets a panel's grain line: the warp direction [rad from +x], finite; stored in (−π, π].
Result<Edit> setGrainAngle(GarmentDocument& document, PanelId panel, double angle);

/// Moves a panel on the 2D pattern sheet (none: back beside the others); the position finite
/// and within 1 km, the angle finite, stored in (−π, π].
Result<Edit> setSheetPlace(GarmentDocument& document, PanelId panel,
                           std::optional<doc::SheetPlace> place);

} // namespace atelier::patterns
