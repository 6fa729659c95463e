#pragma once
/// Body meshes from other tools: OBJ (our reader), FBX, glTF 2.0 (.gltf/.glb), COLLADA, PLY and
/// STL (assimp), normalised to what a body is in Atelier: metres, Y up, standing on y = 0, one
/// welded triangle surface.

#include "io/limits.h"
#include "io/result.h"

#include "sim/core/types.h"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace atelier::io {

/// The length unit of a mesh file's coordinates. Auto = from the body's height.
enum class LengthUnit { Auto, Millimetre, Centimetre, Metre };
/// The axis a mesh file points up. Auto = from the file's metadata and its bounding box.
enum class UpAxis { Auto, Y, Z };

/// "mm", "cm", "m" or "auto" (also the project file's and the CLI's spelling); nullopt otherwise.
std::optional<LengthUnit> parseLengthUnit(std::string_view text);
std::optional<UpAxis> parseUpAxis(std::string_view text);
std::string_view unitName(LengthUnit unit);
std::string_view axisName(UpAxis axis);
/// Metres per file unit (1 for Auto).
double metresPerUnit(LengthUnit unit);

struct BodyImportOptions {
    LengthUnit units = LengthUnit::Auto; ///< the file's unit; Auto detects it from the height
    UpAxis up = UpAxis::Auto;            ///< the file's up axis; Auto detects it
    /// Vertices closer than this once in metres are one vertex (split normals, UV seams and
    /// per-face vertices of formats such as STL) [m].
    double weldDistance = 1e-6;
};

/// Auto-detected heights must fall in this range [m] (a child to a tall adult; a file outside
/// it needs its unit given).
inline constexpr double MIN_DETECTED_HEIGHT = 0.5;
inline constexpr double MAX_DETECTED_HEIGHT = 2.5;

/// What an import found and did.
struct BodyImportReport {
    std::string format; ///< "OBJ", "FBX", "glTF 2.0", "COLLADA", "PLY", "STL"
    LengthUnit units = LengthUnit::Metre;
    std::string unitsFrom; ///< "the height" or "given"
    UpAxis up = UpAxis::Y;
    std::string upFrom;      ///< "the bounding box", "the file's metadata" or "given"
    double fileHeight = 0;   ///< extent along the up axis [file units]
    double height = 0;       ///< [m]
    long sourceVertices = 0; ///< vertices as read
    long vertices = 0;       ///< after the positional weld, used by triangles
    long triangles = 0;
    long droppedTriangles = 0; ///< degenerate after the weld (two corners one vertex)
    long boundaryEdges = 0;    ///< edges of one triangle
    long holes = 0;            ///< boundary loops (connected groups of boundary edges)
    long nonManifoldEdges = 0; ///< edges of three or more triangles
    /// Problems that do not stop the import (holes, non-manifold edges, metadata overruled).
    std::vector<std::string> warnings;
};

struct ImportedBody {
    sim::MatX3 vertices;   ///< (|V|×3) [m], Y up, min y = 0
    sim::MatX3i triangles; ///< (|F|×3)
    BodyImportReport report;
    /// Per vertex of the file: the body vertex it became, or −1 (unused or dropped).
    std::vector<int> fromSource;
    /// Metres subtracted from every y to stand the body on y = 0.
    double floorOffset = 0;
};

/// A mesh as read from a file, in its own units and axes (the input of normaliseBody).
struct RawMesh {
    sim::MatX3 positions;  ///< (|V|×3) [file units]
    sim::MatX3i triangles; ///< (|F|×3)
    std::string format;
    std::optional<UpAxis> metadataUp; ///< the up axis the file declares, if it does
    /// The material name of each mesh the file holds, in order (assimp reads only).
    std::vector<std::string> materials;
    bool hasUvs = false; ///< whether a mesh carries texture coordinates (assimp reads only)
};

/// Reads any mesh file of bodyMeshExtensions through assimp, as it is (file units and axes):
/// polygons fanned into triangles, node transforms applied, points and lines dropped, each
/// mesh's vertices as the file holds them (no join). The file must be a regular file of at
/// most `maxBytes` holding at most `maxVertices` vertices (every mesh instance counted).
Result<RawMesh> readMesh(const std::filesystem::path& path,
                         std::uint64_t maxBytes = Limits{}.maxMeshBytes,
                         long long maxVertices = Limits{}.maxBodyVertices);

/// File extensions importBody reads (lower case, with the dot).
const std::vector<std::string>& bodyMeshExtensions();
/// Whether the path's extension (any case) is one of bodyMeshExtensions.
bool hasBodyMeshExtension(const std::filesystem::path& path);

/// Reads a body mesh (the format from the extension, case-insensitive) and normalises it
/// (normaliseBody). The file must be a regular file of at most `limits.maxMeshBytes`. Errors
/// name the file: unreadable, an unsupported extension, no triangles, or not a body.
Result<ImportedBody> importBody(const std::filesystem::path& path,
                                const BodyImportOptions& options = {}, const Limits& limits = {});

/// Welds, detects (or applies) the unit and up axis, rotates Z up to Y up (x, y, z) → (x, z, −y)
/// so that a Z-up body facing −y faces +z, scales to metres and sets the lowest point on y = 0.
/// Refuses what cannot be a body: non-finite coordinates, fewer than 4 triangles, flat along an
/// axis, a height no unit makes plausible (auto), or a side longer than `limits.maxBodyExtent`.
/// `file` names the mesh in errors and warnings.
Result<ImportedBody> normaliseBody(const RawMesh& raw, const std::string& file,
                                   const BodyImportOptions& options = {},
                                   const Limits& limits = {});

/// Vertices closer than `distance` merged into one (the first in index order), triangles
/// reindexed, triangles left degenerate dropped (their count in `dropped`), unused vertices
/// removed. `sourceToWelded`, when given, receives each input vertex's new index (−1: removed).
void weldByPosition(sim::MatX3& positions, sim::MatX3i& triangles, double distance, long& dropped,
                    std::vector<int>* sourceToWelded = nullptr);

/// A body in motion: meshes of one body, one per frame, in the frame of the first.
struct BodyMotion {
    ImportedBody first;             ///< the first frame, imported as importBody does
    std::vector<sim::MatX3> frames; ///< every frame's vertices (the first's included) [m]
    std::vector<std::string> files; ///< the file of each frame
    /// The animation sampled, as `0 "walk"` (importBodyAnimation); empty for a mesh sequence.
    std::string animation;
};

/// A later frame of a body, `positions` in file coordinates (the vertices, in order, of the
/// raw mesh `first` was normalised from), in the frame of `first`: its unit, up axis, floor
/// offset and weld. Errors name `file`: a non-finite vertex, or a side longer than
/// `limits.maxBodyExtent`.
Result<sim::MatX3> placeAsFirstFrame(const sim::MatX3& positions, const ImportedBody& first,
                                     const std::string& file, const Limits& limits = {});

/// Reads the frames of an animated body (OBJ or any format importBody reads; typically an OBJ
/// sequence exported from a posed or skinned character), one file per frame in the given
/// order. The first frame is imported as importBody does; every other frame must hold the same
/// vertices (count) and triangles, and gets the first frame's unit, up axis, floor offset and
/// weld, so that the motion (walking, a raised arm, the body moving away) is kept. Errors name
/// the file: fewer than two frames, a frame whose mesh differs, a non-finite vertex, or a frame
/// reaching farther than `limits.maxBodyExtent`.
Result<BodyMotion> importBodyMotion(const std::vector<std::filesystem::path>& files,
                                    const BodyImportOptions& options = {},
                                    const Limits& limits = {});

/// Edge figures of a triangle mesh.
struct EdgeFigures {
    long boundaryEdges = 0;
    long holes = 0;
    long nonManifoldEdges = 0;
};
EdgeFigures edgeFigures(const sim::MatX3i& triangles, Eigen::Index vertexCount);

} // namespace atelier::io
