#pragma once
/// Meshing a garment: each panel triangulated at a particle distance into good triangles,
/// with the vertices along every seam placed so that both sides match one to one.

#include "patterns/garment.h"

#include <array>
#include <optional>
#include <string>
#include <vector>

namespace atelier::patterns {

class TriangulationCache;

struct MeshOptions {
    double particleDistance = 0.01; ///< target edge length [m] (typically 0.005–0.02)
    double minAngleDeg = 25;        ///< smallest triangle angle asked of the mesher [deg]
    /// Reuses the triangulations of panels meshed before with the same boundary (an edit
    /// re-triangulates only what it changed); null = triangulate every panel.
    TriangulationCache* cache = nullptr;
};

/// One panel's triangle mesh.
struct PanelMesh {
    /// (|V|×2) pattern coordinates as drawn [m]: the UVs of the exported mesh.
    sim::MatX2 pattern;
    /// (|V|×2) rest coordinates in the material frame [m]: the pattern mirrored for a Back
    /// panel and rotated so that the grain line (warp) is +y. The rest shape of the cloth.
    sim::MatX2 rest;
    sim::MatX3i triangles; ///< (|F|×3) counter-clockwise in `rest`
    /// Edges lying on internal lines, with the rest fold angle of their line [rad].
    std::vector<std::array<int, 2>> lineEdges;
    std::vector<double> lineFoldAngles;
    std::vector<int> notchVertices; ///< one vertex per notch, in the panel's notch order
};

/// A vertex of one panel's mesh.
struct VertexRef {
    int panel = 0;
    int vertex = 0;
    bool operator==(const VertexRef&) const = default;
};

struct GarmentMesh {
    std::vector<PanelMesh> panels; ///< in the garment's panel order
    /// Vertex pairs sewn together (seams, then darts), one to one along each seam.
    std::vector<std::array<VertexRef, 2>> seamPairs;
    std::vector<int> seamOfPair;       ///< (|pairs|) seam index; darts: −1 − panel index
    std::vector<std::string> warnings; ///< ease beyond tolerance, naming the seam and lengths
    double minAngleDeg = 0;            ///< smallest triangle angle over all panels [deg]
    long triangleCount = 0;
    double seconds = 0;         ///< wall time of the meshing [s]
    int panelsTriangulated = 0; ///< panels triangulated (the others came from the cache)
};

/// A problem with the garment, at a JSON-pointer-like place (`/panels/2/outline/3`).
struct GarmentIssue {
    std::string where;
    std::string message;
};

/// Largest width or height of a panel's outline [m]: beyond it a file is in the wrong units or
/// broken, and meshing it at a particle distance would not end.
inline constexpr double MAX_PANEL_EXTENT = 10.0;

/// Checks the garment's geometry and references: panels over MAX_PANEL_EXTENT, zero-length
/// segments, outlines that intersect themselves, holes and internal lines outside their panel,
/// seams naming missing panels or segments, darts out of range, pins outside their panel or on
/// a missing notch, parameters not finite, and an outline range sewn twice (patterns/seam_check.h).
/// Empty when it is fine.
std::vector<GarmentIssue> validateGarment(const Garment& garment);

/// How far outside a panel's contour a pin's point may lie and still count as on it [m]: the
/// contours are flattened at 32 chords per curve, whose sagitta on a 200 mm half circle is
/// 0.24 mm.
inline constexpr double PIN_CONTOUR_TOLERANCE = 0.001;

/// How far from the body's origin a pin may hold its vertex, per coordinate [m]: farther is a
/// unit mistake, and a vertex dragged there stretches its panel across everything (a pin 1000 km
/// away slowed a 40 mm drape to 6 s a step).
inline constexpr double MAX_PIN_POSITION = 10.0;

/// Whether `point` [m] lies inside the panel as drawn, or within PIN_CONTOUR_TOLERANCE of its
/// outline or a hole's contour (curves flattened at 32 chords; not inside a hole).
bool insidePanel(const Panel& panel, const Vec2& point);

/// Meshes every panel. Returns what went wrong (naming the panel) or nullopt.
std::optional<std::string> meshGarment(const Garment& garment, const MeshOptions& options,
                                       GarmentMesh& out);

/// A mesh's size, estimated before meshing.
struct MeshEstimate {
    long vertices = 0;
    long triangles = 0;
};

/// Bounds of a panel's own particle distance [m] (0 = the drape's).
inline constexpr double MIN_PANEL_PARTICLE_DISTANCE = 0.001;
inline constexpr double MAX_PANEL_PARTICLE_DISTANCE = 1.0;

/// The particle distance `panel` is meshed at: its own, or `particleDistance` [m].
double panelParticleDistance(const Panel& panel, double particleDistance);

/// The size meshGarment gives at `particleDistance` [m] (each panel at its own where it has
/// one), from the panels' areas A and outline
/// lengths L without triangulating (microseconds): the mesher's triangles are near-equilateral
/// with a mean edge ≈ h, so a panel holds about 2A/(√3h²) interior vertices, L/h boundary
/// vertices and 4A/(√3h²) triangles. Within ±20% of the samples' meshes at 10 and 20 mm; a
/// distance ≤ 0 or not finite gives the largest count.
MeshEstimate estimateGarmentMesh(const Garment& garment, double particleDistance);

/// Smallest interior angle over the triangles of a 2D mesh [deg].
double minTriangleAngleDeg(const sim::MatX2& points, const sim::MatX3i& triangles);

} // namespace atelier::patterns
