#pragma once
/// A mesh file read through assimp and kept as assimp's scene, for the readers that need more
/// than its meshes' vertices (io-internal: mesh_import.cpp, body_animation.cpp). assimp's types
/// are only declared here: no header includes assimp (decisions/021).

#include "io/mesh_import.h"
#include "io/result.h"

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

struct aiMesh;
struct aiScene;
namespace Assimp {
class Importer;
}

namespace atelier::io::detail {

struct AssimpScene {
    AssimpScene();
    AssimpScene(AssimpScene&&) noexcept;
    AssimpScene& operator=(AssimpScene&&) noexcept;
    AssimpScene(const AssimpScene&) = delete;
    AssimpScene& operator=(const AssimpScene&) = delete;
    ~AssimpScene();

    std::unique_ptr<Assimp::Importer> importer; ///< owns `scene`
    const aiScene* scene = nullptr;
    std::string format; ///< as BodyImportReport::format
    /// The up axis the file declares: glTF is Y up by its specification, FBX says so in its
    /// metadata (UpAxis 1 = Y, 2 = Z); assimp turns a COLLADA Z_UP file Y up itself.
    std::optional<UpAxis> metadataUp;
};

/// Reads any file of bodyMeshExtensions through assimp with no post-processing but its
/// validation (assimp's triangulation asserts, and so aborts, on some broken files). The file
/// must be a regular file of at most `maxBytes`; a glTF's JSON (.gltf, a .glb's JSON chunk)
/// nested at most `maxJsonDepth` deep, without a key twice in an object. Errors name the file.
Result<AssimpScene> readAssimpScene(const std::filesystem::path& path, std::uint64_t maxBytes,
                                    int maxJsonDepth);

/// Appends the mesh's faces to `triangles` as fans of vertex indices offset by `base`; points
/// and lines (fewer than 3 corners) carry no surface and are dropped. Errors (naming `file`): a
/// face naming a vertex the mesh does not hold.
Result<void> appendTriangles(const aiMesh& mesh, int base, const std::string& file,
                             std::vector<std::array<int, 3>>& triangles);

/// A figure of a mesh file for messages, 4 significant digits ("%.4g").
std::string figure(double value);

} // namespace atelier::io::detail
