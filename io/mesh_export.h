#pragma once
/// Triangle surfaces out to other tools: OBJ + MTL (our writer), glTF 2.0 binary, FBX (binary
/// or ASCII) and PLY (assimp's exporters), each written atomically.

#include "io/obj.h"
#include "io/result.h"

#include "sim/core/types.h"

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace atelier::io {

/// A surface to export: where triangles meet they share a position (one vertex), while the
/// texture coordinates are per corner, so that a vertex on a seam between two panels is one
/// vertex with a UV in each panel.
struct SurfaceMesh {
    sim::MatX3 positions;    ///< (|V|×3) [m]
    sim::MatX3i triangles;   ///< (|F|×3) into positions
    sim::MatX2 uvs;          ///< (|T|×2) texture coordinates, or empty
    sim::MatX3i uvTriangles; ///< (|F|×3) into uvs; empty when uvs is
    /// Contiguous triangle ranges, each written as a group with its own material (a panel).
    std::vector<ObjGroup> groups;
    std::string comment; ///< written where the format has comments (OBJ)
};

/// The surface of per-piece vertices `x` with the vertex pairs `welds` joined: each connected
/// group of joined vertices becomes one vertex at the group's mean position (the first
/// member's index order is kept); every original vertex keeps its own UV.
/// @param x (|V|×3), triangles (|F|×3), uvs (|V|×2 or empty)
SurfaceMesh weldedSurface(const sim::MatX3& x, const sim::MatX3i& triangles, const sim::MatX2& uvs,
                          std::vector<ObjGroup> groups,
                          const std::vector<std::pair<int, int>>& welds);

enum class MeshFormat { Obj, Glb, Fbx, FbxAscii, Ply };

/// "obj", "glb", "fbx", "fbx-ascii", "ply".
std::string_view meshFormatName(MeshFormat format);
std::optional<MeshFormat> parseMeshFormat(std::string_view name);
/// The format an output path asks for by its extension (case-insensitive): .obj, .glb, .fbx,
/// .ply; nullopt for any other.
std::optional<MeshFormat> meshFormatOfPath(const std::filesystem::path& path);
/// The names parseMeshFormat knows, comma-separated (for messages and help).
std::string meshFormatList();

/// The files an export of `path` writes: the path, and for OBJ the material library beside it
/// (`NAME.mtl`).
std::vector<std::filesystem::path> exportedFiles(const std::filesystem::path& path,
                                                 MeshFormat format);

/// Writes the surface in `format`, every file atomically (OBJ: the MTL first). OBJ keeps the
/// shared vertices (`v` once, `vt` per corner, `vn` per vertex), one group and material per
/// group; PLY is one mesh of the shared vertices, with UVs only where each vertex has one;
/// glTF and FBX carry one mesh and material per group (a glTF or assimp vertex has one UV, so
/// a seam vertex is repeated in each piece's mesh). assimp writes single precision.
Result<void> exportMesh(const std::filesystem::path& path, const SurfaceMesh& mesh,
                        MeshFormat format);

} // namespace atelier::io
