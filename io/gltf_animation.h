#pragma once
/// A mesh sequence as one glTF 2.0 binary file (.glb) that any glTF viewer plays: each mesh
/// keeps its first frame as its positions and every later frame as a morph target, and one
/// animation moves the morph weights from frame to frame (docs/file-formats.md, "Sequences
/// out"; why our own writer: docs/decisions/026-gltf-sequence-writer.md).

#include "io/result.h"

#include "sim/core/types.h"

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace atelier::io {

/// One animated mesh: fixed triangles, positions per frame.
struct SequenceMesh {
    std::string name;
    sim::MatX3i triangles;          ///< (|F|×3)
    std::vector<sim::MatX3> frames; ///< (|V|×3) per frame [m]
    /// Base colour (linear RGB) of the mesh's material.
    std::array<double, 3> colour{0.8, 0.8, 0.8};
};

/// Writes `meshes`, all with the same number of frames at `times` [s] (increasing, as many as
/// frames), as a .glb atomically. With LINEAR interpolation of the weights, a time between two
/// frames shows the positions interpolated linearly between them, as the drape computed them.
/// Errors name the file: no mesh, frames and times that do not match, a mesh whose frames
/// differ in size, a non-finite position, or the write failing.
Result<void> writeSequenceGlb(const std::filesystem::path& path,
                              const std::vector<SequenceMesh>& meshes,
                              const std::vector<double>& times);

} // namespace atelier::io
