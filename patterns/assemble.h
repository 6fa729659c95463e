#pragma once
/// Assembly: garment + meshes + body → the engine's scene, with only the stages it needs.

#include "patterns/body.h"
#include "patterns/mesh.h"
#include "patterns/placement.h"
#include "patterns/project.h"

#include "sim/scene.h"

#include <optional>
#include <string>
#include <vector>

namespace atelier::patterns {

/// A garment pin resolved to a vertex: `hold.vertex` (global) follows `hold`'s path in the
/// simulation's time (still, or moving to the pin's position) until `hold.releaseTime`.
struct HeldPin {
    int panel = 0; ///< garment panel index
    int pin = 0;   ///< index in the panel's pins
    sim::Drive hold;
};

/// How far a panel is moved from where its placement puts it, to clear panels it was placed
/// through (liftCrossedPanels): out from its slot, and round it.
struct SlotShift {
    double lift = 0;   ///< clearance added to the panel's own [m]
    double around = 0; ///< added to the placement's offset along the slot's circumference [m]
    bool operator==(const SlotShift&) const = default;
};

/// A panel placed through other panels, moved on its slot until it clears them.
struct PlacementLift {
    std::string panel;                ///< the moved panel's name
    double lift = 0;                  ///< clearance added to the panel's own [m]
    double around = 0;                ///< moved round its slot (SlotShift::around) [m]
    std::vector<std::string> crossed; ///< the panels it crossed as first placed
};
/// "front_right 10 mm out (crossed front_left)", "back_left -5 mm around (crossed back_right)":
/// a move as the report, the warnings and the window say it (out: clearance added; around:
/// added to the placement's offset around the slot, as a project's `offset_mm` says it).
std::string liftText(const PlacementLift& lift);

/// The scene of a drape and how its cloths map back to the garment.
struct AssembledGarment {
    sim::SceneSpec scene;
    /// First global vertex of each panel's cloth, plus the total at the end (|panels|+1).
    std::vector<int> panelOffsets;
    /// Per scene seam pair: its entry in GarmentMesh::seamOfPair (the garment seam, or
    /// −1 − panel for a dart).
    std::vector<int> pairSeam;
    /// The garment's pins resolved to vertices (pinGarment).
    std::vector<HeldPin> pins;
};

/// Builds the scene: one cloth per panel (rest shape in its material frame, start positions
/// wrapped on its slot at its clearance, moved by `shifts[p]` when given (liftCrossedPanels),
/// material by name, fold angles from internal lines), the seams and darts as imposed seam pairs
/// that weld when closed, the body as a closed static obstacle. Returns what is wrong (a panel's
/// slot missing on the body, a material missing) or nullopt.
std::optional<std::string> assembleGarment(const Garment& garment, const GarmentMesh& mesh,
                                           const Body& body, const DrapeSettings& settings,
                                           AssembledGarment& out,
                                           const std::vector<SlotShift>& shifts = {});

/// Panels through each other as a simulation starts from `x` (|V|×3, the assembled scene's
/// vertices; a Simulation's positions once its collision stage has resolved the start, which
/// pushes cloth within the contact layer of other cloth apart): per pair of panels whose
/// triangles intersect, how many pairs do, seam partners within the weld distance taken as one
/// vertex (they weld at the first step; panels sewn edge to edge touch there). `withinPanels`:
/// a panel's own triangle pairs too (entries with a == b).
std::vector<PanelCrossing> startCrossings(const AssembledGarment& assembled, const sim::MatX3& x,
                                          bool withinPanels = false);

/// Moves panels placed through each other apart on their slots, given the crossings the
/// assembled scene starts with (startCrossings; on a small body a trouser leg's slot brings the
/// front panels through each other at the crotch, on a body with spread legs the backs): 5 mm
/// at a time, out from the slot (a lift) or round it, up to 30 mm each way a panel; of the
/// worst-crossing pair, the panel and move that leave the fewest crossings as a simulation of
/// them starts (each try builds one). Returns the shift per panel (assembleGarment's `shifts`)
/// of the placement with the fewest crossings found, all zero when no move lessened them;
/// `lifted` receives the moved panels with the panels each crossed. `movable` (per panel;
/// empty: all) limits the moves to some panels (one placed again among panels that stay where
/// they are), and the crossings to those of movable panels.
std::vector<SlotShift> liftCrossedPanels(const Garment& garment, const GarmentMesh& mesh,
                                         const Body& body, const AssembledGarment& assembled,
                                         const std::vector<PanelCrossing>& crossings,
                                         std::vector<PlacementLift>& lifted,
                                         const std::vector<char>& movable = {});

/// Holds the garment's pins on `out`'s scene, whose cloths start where the simulation starts,
/// at drape time `drapeTime` [s] (0 for a new drape; later when a drape is rebuilt from where
/// it is). Each pin holds the panel vertex nearest its point (or its notch's vertex); a pin
/// with a position moves there in a straight line, arriving at the end of the sewing time; a
/// pin released before `drapeTime` is left out; a vertex pinned twice is held by the first.
/// Still pins for good become engine pins (inverse mass 0), the others drives. Replaces the
/// scene's pins and drives.
void pinGarment(const Garment& garment, const GarmentMesh& mesh, const DrapeSettings& settings,
                double drapeTime, AssembledGarment& out);

/// The garment pins holding at simulation time `time` [s], and the largest distance of a
/// pinned vertex from where its pin holds it at positions x (|V|×3) [m] (0 when none).
struct PinFigures {
    int holding = 0;
    double largestDisplacement = 0;
};
PinFigures pinFigures(const AssembledGarment& assembled, const sim::MatX3& x, double time);

/// A seam (or dart) that sewing did not close: its widest pair welded by force.
struct ForcedWeld {
    std::string seam;  ///< the seam's name, or "dart of PANEL"
    double widest = 0; ///< [m]
    int pairs = 0;     ///< pairs of it welded by force
};

/// Per garment seam, from the engine's per-pair gaps (sim::RunStats::forcedWeldGaps): the
/// seams with a pair welded by force, widest first.
std::vector<ForcedWeld> forcedWelds(const Garment& garment, const AssembledGarment& assembled,
                                    const std::vector<double>& gaps);

/// Largest distance between sewn vertex pairs [m] at positions x (global, |V|×3).
double seamGapMax(const AssembledGarment& assembled, const sim::MatX3& x);

/// Total triangle area of the cloths at positions x over their total rest area [-].
double areaRatio(const sim::SceneSpec& scene, const sim::MatX3& x);

/// How sharply a drape folds: the angle between the normals of the two triangles on either side
/// of an edge (|θ| of `sim::dihedralAngle`, 0 = flat) across the seams between panels and
/// inside the panels (their own hinges, and those of seams sewn within a panel: darts), at
/// positions x with each group of sewn vertices at its mean, as a single-surface
/// export writes it (io::weldedSurface): the same figures come from the exported mesh, counting
/// the edges whose faces lie in two panels' groups (tools/seam_folds.py).
struct FoldFigures {
    int seamEdges = 0;      ///< seam edges between panels
    double seamMedian = 0;  ///< median fold across them [rad]
    double seamMax = 0;     ///< largest [rad]
    double clothMedian = 0; ///< median fold inside the panels [rad]
};
FoldFigures foldFigures(const AssembledGarment& assembled, const sim::MatX3& positions);

} // namespace atelier::patterns
