#pragma once
/// The garment as a designer edits it: panels, outline points, edges, internal lines, darts,
/// notches and seams, each with a stable id, so that every reference survives edits. A seam
/// names a panel id and an edge id, never a panel name or a segment index that an edit can
/// shift; renaming a panel or inserting a point leaves every seam on the curve it was on.
///
/// Plain data in SI units (metres, radians). Edits are free functions in
/// patterns/document_edit.h; the mesher still takes the index-based patterns::Garment, which
/// `toGarment` gives.

#include "patterns/garment.h"

#include "sim/core/result.h"

#include <compare>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace atelier::patterns {

/// A stable identifier of one kind of object. Ids come from one counter per document and are
/// never held by two objects; 0 is "none".
template <class Tag> struct Id {
    std::uint32_t value = 0;
    explicit operator bool() const { return value != 0; }
    auto operator<=>(const Id&) const = default;
};

using PanelId = Id<struct PanelTag>;
using PointId = Id<struct PointTag>;
using EdgeId = Id<struct EdgeTag>;
using HoleId = Id<struct HoleTag>;
using LineId = Id<struct LineTag>;
using DartId = Id<struct DartTag>;
using NotchId = Id<struct NotchTag>;
using SeamId = Id<struct SeamTag>;
using PinId = Id<struct PinTag>;

namespace doc {

/// A corner of a contour or internal line [m].
struct Point {
    PointId id;
    Vec2 position = Vec2::Zero();
};

/// The curve between two consecutive points; its ends are those points.
struct Curve {
    SegmentKind kind = SegmentKind::Line;
    Vec2 control1 = Vec2::Zero(); ///< Quadratic, Cubic [m]
    Vec2 control2 = Vec2::Zero(); ///< Cubic [m]
    /// Arc only: tan(θ/4) for the sweep θ, positive counter-clockwise (as Segment::bulge) [-].
    double bulge = 0;
};

struct Edge {
    EdgeId id;
    Curve curve;
};

/// A closed cycle of points: `edges[i]` runs from `points[i]` to `points[(i + 1) % n]`
/// (|edges| = |points|). Each corner is stored once.
struct Contour {
    std::vector<Point> points;
    std::vector<Edge> edges;
};

struct Hole {
    HoleId id;
    Contour contour;
};

/// An open chain inside the panel: `edges[i]` runs from `points[i]` to `points[i + 1]`
/// (|edges| = |points| − 1 ≥ 1).
struct InternalLine {
    LineId id;
    std::vector<Point> points;
    std::vector<Edge> edges;
    double foldAngle = 0; ///< rest dihedral angle of the hinges along it [rad]
};

/// Two consecutive outline edges meeting at the dart's tip, sewn together (`leg1` reversed
/// against `leg2`): `leg2` directly follows `leg1` in the outline and `leg1` is not the
/// outline's last edge (as patterns::Dart).
struct Dart {
    DartId id;
    EdgeId leg1;
    EdgeId leg2;
};

/// A mark on an outline edge at curve parameter `t` ∈ [0, 1].
struct Notch {
    NotchId id;
    EdgeId edge;
    double t = 0.5;
};

/// A point of the panel held while the garment drapes (as patterns::Pin): the vertex nearest
/// `point`, or the vertex of notch `notch` when set.
struct Pin {
    PinId id;
    Vec2 point = Vec2::Zero();    ///< in the pattern plane [m]; unused with a notch
    NotchId notch;                ///< a notch of the panel, or none
    std::optional<Vec3> position; ///< where it is held, body frame [m]; none: where placed
    double releaseTime = std::numeric_limits<double>::infinity(); ///< drape time [s]
};

/// Where a panel lies on the 2D pattern sheet (the designer's arrangement, drawn in the pattern
/// view; the drape does not use it): the sheet point of the panel's own origin [m] and the
/// panel's turn, counter-clockwise [rad].
struct SheetPlace {
    Vec2 at = Vec2::Zero();
    double angle = 0;
};

struct Panel {
    PanelId id;
    std::string name; ///< unique in the document; nothing refers to it
    Contour outline;  ///< counter-clockwise
    std::vector<Hole> holes;
    std::vector<InternalLine> internalLines;
    std::vector<Dart> darts;
    std::vector<Notch> notches;
    std::vector<Pin> pins;
    double grainAngle = 1.5707963267948966; ///< warp direction [rad from +x]
    std::string material;                   ///< a fabric of the document's materials
    PanelSide side = PanelSide::Front;
    Placement placement;
    double particleDistance = 0;     ///< as patterns::Panel::particleDistance [m]; 0: the drape's
    std::optional<SheetPlace> sheet; ///< none: laid out beside the others
};

/// A range of one panel's outline edge from curve parameter `t0` to `t1` (t0 > t1 runs against
/// the outline's direction).
struct SeamRange {
    PanelId panel;
    EdgeId edge;
    double t0 = 0;
    double t1 = 1;
};

/// Two chains of ranges sewn together, start to start and end to end (as patterns::Seam).
struct Seam {
    SeamId id;
    std::string name;
    std::vector<SeamRange> a;
    std::vector<SeamRange> b;
    double foldAngle = 0;    ///< as patterns::Seam::foldAngle [rad]
    double bendingScale = 1; ///< as patterns::Seam::bendingScale [-]
};

} // namespace doc

struct GarmentDocument {
    std::string name;
    std::vector<doc::Panel> panels;
    std::vector<doc::Seam> seams;
    std::vector<GarmentMaterial> materials; ///< fabrics, referred to by name
    double easeTolerance = 0.005;           ///< as Garment::easeTolerance [m]
    /// The next id to hand out; every id in the document is below it.
    std::uint32_t nextId = 1;

    /// A fresh id of any kind.
    template <class IdType> IdType newId() { return IdType{nextId++}; }

    doc::Panel* panel(PanelId id);
    const doc::Panel* panel(PanelId id) const;
    doc::Seam* seam(SeamId id);
    const doc::Seam* seam(SeamId id) const;
    /// The panel with this name, or null.
    const doc::Panel* panelNamed(const std::string& name) const;
};

/// Index of the outline edge `edge` in `panel`, or −1.
int outlineEdgeIndex(const doc::Panel& panel, EdgeId edge);

/// The contour (outline or hole) of `panel` holding `point` / `edge`, or null; `index` is the
/// position of the point / edge in it.
doc::Contour* contourOfPoint(doc::Panel& panel, PointId point, int& index);
doc::Contour* contourOfEdge(doc::Panel& panel, EdgeId edge, int& index);

/// The segment of edge `i` of a contour [m].
Segment contourSegment(const doc::Contour& contour, std::size_t i);
/// The segment of an edge with curve `c` from `start` to `end`.
Segment segmentOf(const doc::Curve& c, const Vec2& start, const Vec2& end);

/// The index-based garment the mesher takes: panels and seams in document order, outline
/// segments in cycle order from each outline's first point.
Garment toGarment(const GarmentDocument& document);

/// The document of a garment, ids handed out in garment order. Expects a valid garment
/// (patterns::validateGarment): a seam naming a missing panel keeps a null id. An internal
/// line whose segments do not join end to start becomes several lines.
GarmentDocument fromGarment(const Garment& garment);

/// Converts one drawn panel, handing out its ids from `document`'s counter (the panel is not
/// added).
doc::Panel panelFromDrawing(GarmentDocument& document, const Panel& drawn);

/// Checks every reference: ids unique and below `nextId`, seams on existing panels' outline
/// edges with t in [0, 1], darts on consecutive outline edges, notches on outline edges,
/// contours of ≥ 3 points, panel names unique and non-empty, pins on a notch of their panel
/// (or at a finite point) with a finite position and a release time that is not NaN.
Result<void> checkDocument(const GarmentDocument& document);

/// A deterministic text dump of the whole document, ids included, every number written
/// exactly (17 significant digits): equal dumps mean equal documents.
std::string dumpDocument(const GarmentDocument& document);

} // namespace atelier::patterns
