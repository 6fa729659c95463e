#pragma once
/// The garment as a designer draws it: panels (closed outlines of lines, Béziers and arcs in
/// the pattern plane), seams between boundary ranges, and where each panel is placed on the
/// body. Plain data in SI units (metres, radians where named so); files are io/'s business.

#include "sim/core/types.h"
#include "sim/material.h"

#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace atelier::patterns {

using sim::Vec2;
using sim::Vec3;

enum class SegmentKind {
    Line,      ///< straight from `start` to `end`
    Quadratic, ///< quadratic Bézier with control point `control1`
    Cubic,     ///< cubic Bézier with control points `control1`, `control2`
    Arc,       ///< circular arc from `start` to `end` with `bulge`
};

/// One piece of a panel's outline (or of an internal line) in the pattern plane [m].
struct Segment {
    SegmentKind kind = SegmentKind::Line;
    Vec2 start = Vec2::Zero();
    Vec2 end = Vec2::Zero();
    Vec2 control1 = Vec2::Zero();
    Vec2 control2 = Vec2::Zero();
    /// Arc only: tan(θ/4) for the arc's sweep θ, positive counter-clockwise from start to end
    /// (the DXF convention); |bulge| = 1 is a half circle [-].
    double bulge = 0;
};

/// A closed loop of segments: segment i ends where segment i+1 starts, the last ends where
/// the first starts.
using Loop = std::vector<Segment>;

/// A line inside a panel that becomes mesh edges: a fold or crease whose hinges get a rest
/// fold angle (0 = a plain line, e.g. a placement mark).
struct InternalLine {
    std::vector<Segment> path; ///< open chain of segments, inside the panel
    double foldAngle = 0;      ///< rest dihedral angle of the hinges along it [rad]
};

/// A dart cut into the outline: the two outline segments `leg` and `leg + 1` meet at the
/// dart's tip and are sewn together (leg reversed against leg + 1) when the garment is
/// assembled.
struct Dart {
    int leg = 0; ///< index of the first leg in the outline
};

/// A mark on the outline (for matching pieces): it becomes a mesh vertex.
struct Notch {
    int segment = 0;
    double t = 0.5; ///< curve parameter on the segment [0, 1]
};

/// A point of a panel held while the garment drapes: the mesh vertex nearest `point` (or the
/// vertex of notch `notch`) is held where the panel is placed, or moved to `position`, until
/// `releaseTime`. A held vertex has inverse mass 0: nothing the cloth does moves it.
struct Pin {
    Vec2 point = Vec2::Zero(); ///< in the pattern plane, as drawn [m]; unused with a notch
    int notch = -1;            ///< index of one of the panel's notches, or −1 (use `point`)
    /// Where the vertex is held, in the body's frame [m]: reached in a straight line over the
    /// sewing time from where it is placed. None: held where it is placed.
    std::optional<Vec3> position;
    /// Drape time at which the pin lets go [s]; infinity: never.
    double releaseTime = std::numeric_limits<double>::infinity();
};

/// Which side of the fabric faces away from the body. A `Back` panel is the mirror image of
/// its drawing (cut from the fabric turned over), so one drawing gives left and right pieces.
enum class PanelSide { Front, Back };

/// Where a panel starts: on one of the body's arrangement slots.
struct Placement {
    std::string slot;           ///< slot name on the body (e.g. "torso_front")
    Vec2 offset = Vec2::Zero(); ///< panel origin on the slot surface: (around, along) [m]
    double rotation = 0;        ///< rotation of the panel in its plane [rad]
    double clearance = 0.02;    ///< gap kept to the body surface [m]
};

struct Panel {
    std::string name;
    Loop outline;            ///< counter-clockwise
    std::vector<Loop> holes; ///< clockwise or counter-clockwise, inside the outline
    std::vector<InternalLine> internalLines;
    std::vector<Dart> darts;
    std::vector<Notch> notches;
    std::vector<Pin> pins;
    /// Direction of the warp (grain line) in the pattern plane [rad from +x]; the material
    /// frame is weft = warp rotated by −90°.
    double grainAngle = 1.5707963267948966;
    std::string material; ///< name of a fabric in the garment's materials
    PanelSide side = PanelSide::Front;
    Placement placement;
    /// This panel's particle distance (mesh edge length) [m]; 0: the drape's. A seam between
    /// panels of different distances is sewn at the finer one on both sides.
    double particleDistance = 0;
};

/// A range of one panel's outline: segment `segment` from curve parameter `t0` to `t1`
/// (t0 > t1 runs against the outline's direction).
struct SeamEdge {
    std::string panel;
    int segment = 0;
    double t0 = 0;
    double t1 = 1;
};

/// Two chains of boundary ranges sewn together, start to start and end to end, matched by
/// arc length fraction. One to one: one edge a side; one to many: one long edge against two
/// shorter ones. Different lengths are ease or gathering.
struct Seam {
    std::string name;
    std::vector<SeamEdge> a;
    std::vector<SeamEdge> b;
    /// Once sewn, the rest fold angle across the seam [rad], in (−π, π): 0 = flat, the cloth
    /// running on across it; positive where it turns away from the front of side a (a convex
    /// edge seen from there, as a box's), sim::SeamPair::foldAngle.
    double foldAngle = 0;
    /// Once sewn, the seam's bending rigidity as a multiple of its cloths' (1 = as the cloth
    /// beside it; a pressed-open seam allowance adds two layers: about 3), ≥ 0.
    double bendingScale = 1;
};

/// A named fabric used by panels.
struct GarmentMaterial {
    std::string name;
    sim::Material material;
};

struct Garment {
    std::string name;
    std::vector<Panel> panels;
    std::vector<Seam> seams;
    std::vector<GarmentMaterial> materials;
    /// Seams whose sides differ by more than this in length get a warning naming both [m].
    double easeTolerance = 0.005;

    /// Index of the panel with this name, or -1.
    int panelIndex(const std::string& name) const;
};

} // namespace atelier::patterns
