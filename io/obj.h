#pragma once
/// Wavefront OBJ triangle meshes: reading (with UVs as cloth rest coordinates) and writing.

#include "io/limits.h"
#include "io/result.h"

#include "sim/core/types.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace atelier::io {

/// A named, contiguous range of triangles (an OBJ `g` or `o` group).
struct ObjGroup {
    std::string name;
    int firstTriangle = 0; ///< index of the group's first triangle
    int triangleCount = 0;
};

/// A triangle mesh read from an OBJ file.
///
/// Without `vt`, the vertices are the file's `v` lines in order. With `vt`, every face corner
/// must have one, and the vertices are the distinct (v, vt) pairs the faces use, ordered by
/// (v, vt): a vertex on a UV seam is split so that each vertex has exactly one UV, and a `v`
/// that no face uses is dropped.
struct ObjMesh {
    sim::MatX3 positions;  ///< (|V|×3) [file units, m for Atelier]
    sim::MatX2 uvs;        ///< (|V|×2) texture coordinates, or empty when the file has no `vt`
    sim::MatX3i triangles; ///< (|F|×3) polygons split into fans (v0, vi, vi+1)
    /// Groups in file order (empty groups dropped). Empty when the file has no `g`/`o` lines;
    /// otherwise faces before the first one form a group named "default".
    std::vector<ObjGroup> groups;
    /// For each vertex, the 0-based index of its `v` line (|V|).
    std::vector<int> sourceVertex;
};

/// Reads an OBJ file: `v`, `vt`, `vn`, `f` (all of `v`, `v/vt`, `v//vn`, `v/vt/vn`, negative =
/// relative indices), `g`, `o`; other statements (`mtllib`, `usemtl`, `s`, `l`, ...) are ignored.
/// Errors name the file and the line (`shirt.obj: line 12: face index 40 out of range [1, 39]`).
/// The file must be a regular file of at most `maxBytes` (see readFile).
Result<ObjMesh> readObj(const std::filesystem::path& path,
                        std::uint64_t maxBytes = Limits{}.maxMeshBytes);

/// Options of `writeObj`.
struct ObjWriteOptions {
    /// Texture coordinates written as `vt`: (|V|×2), one per vertex, or (|T|×2) indexed per
    /// corner by `uvTriangles`; empty = none.
    sim::MatX2 uvs;
    /// (|F|×3) each corner's row of `uvs`; empty = the corner's vertex.
    sim::MatX3i uvTriangles;
    /// A material library written as `mtllib`; when set, each group also selects the material
    /// of its (written) name with `usemtl`.
    std::string materialLibrary;
    /// Groups over the triangles (each written as `g name` before its first triangle; in the
    /// name, control characters, whitespace and `#` are written as `_`, an empty name as
    /// `default`).
    std::vector<ObjGroup> groups;
    bool normals = true; ///< write area-weighted vertex normals as `vn`
    /// Written as `# ...` lines at the top; may hold newlines (other control characters are
    /// written as spaces).
    std::string comment;
};

/// Writes a triangle mesh as OBJ, atomically. Numbers are written in the shortest form that
/// reads back exactly.
/// @param positions (|V|×3) vertex positions
/// @param triangles (|F|×3) 0-based vertex indices
Result<void> writeObj(const std::filesystem::path& path, const sim::MatX3& positions,
                      const sim::MatX3i& triangles, const ObjWriteOptions& options = {});

/// The OBJ text `writeObj` would write.
Result<std::string> formatObj(const sim::MatX3& positions, const sim::MatX3i& triangles,
                              const ObjWriteOptions& options = {});

} // namespace atelier::io
