#pragma once
/// Placing a panel around the body: its mesh wrapped onto the cylinder of an arrangement slot.

#include "patterns/body.h"
#include "patterns/garment.h"
#include "patterns/mesh.h"

#include <vector>

namespace atelier::patterns {

/// Panel-plane coordinates used for placement: the pattern as drawn, mirrored in x for a
/// Back panel (so triangles keep their counter-clockwise order), centred on the middle of its
/// bounding box, then rotated by `placement.rotation` and moved by `placement.offset` [m].
sim::MatX2 placementCoordinates(const Panel& panel, const PanelMesh& mesh);

/// 3D start positions of a panel (|V|×3) [m]: each placement point (u, v) goes to
/// origin + a(v)·axis + r(v)·(cos(u/r(v))·facing + sin(u/r(v))·right). The radius r(v) of the
/// panel's row at v is the slot's profile there plus the clearance, or more where the row is
/// too wide to stay within ±slot.maxAngle (smoothed over ±3 cm, never below either bound);
/// a(v) makes the meridian's arc length equal to v, anchored at the panel's top row. Around,
/// arc lengths are kept exactly: the panel starts curved around the body part, clear of it,
/// with its front facing out.
sim::MatX3 wrapOnSlot(const sim::MatX2& coordinates, const ArrangementSlot& slot, double clearance);

/// Panels placed through each other: per pair of panels (a < b) whose triangles intersect,
/// how many of their triangle pairs do. `positions[p]` and `triangles[p]` are panel p's
/// placed vertices (|V_p|×3) and triangles (indices into them); a panel's own triangles are
/// tested against each other only `withinPanels` (entries with a == b), those sharing a vertex
/// left out. `joined`, if given, names each vertex (joined[p][v]): triangles sharing a name
/// touch where they are joined (seam partners about to weld) and are not counted.
struct PanelCrossing {
    int a = 0, b = 0;
    long pairs = 0;
};
std::vector<PanelCrossing> panelCrossings(const std::vector<sim::MatX3>& positions,
                                          const std::vector<sim::MatX3i>& triangles,
                                          const std::vector<std::vector<int>>* joined = nullptr,
                                          bool withinPanels = false);

} // namespace atelier::patterns
