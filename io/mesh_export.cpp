#include "io/mesh_export.h"

#include "io/atomic_file.h"

#include "sim/mesh/joined_vertices.h"
#include "sim/mesh/vertex_normals.h"

#include <assimp/Exporter.hpp>
#include <assimp/material.h>
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <map>
#include <memory>
#include <numeric>

namespace atelier::io {

namespace {

struct FormatInfo {
    MeshFormat format;
    const char* name;
    const char* extension;
    const char* assimpId; ///< nullptr: our own writer
};

constexpr std::array<FormatInfo, 5> FORMATS = {{
    {MeshFormat::Obj, "obj", ".obj", nullptr},
    {MeshFormat::Glb, "glb", ".glb", "glb2"},
    {MeshFormat::Fbx, "fbx", ".fbx", "fbx"},
    {MeshFormat::FbxAscii, "fbx-ascii", nullptr, "fbxa"},
    {MeshFormat::Ply, "ply", ".ply", "ply"},
}};

const FormatInfo& info(MeshFormat format) {
    return *std::find_if(FORMATS.begin(), FORMATS.end(),
                         [format](const FormatInfo& f) { return f.format == format; });
}

/// The material library beside an OBJ: its stem with `.mtl`, whitespace and `#` made `_` (an
/// `mtllib` name is one token).
std::filesystem::path mtlPath(const std::filesystem::path& obj) {
    std::string name = obj.stem().string() + ".mtl";
    for (char& c : name) {
        const auto u = static_cast<unsigned char>(c);
        if (u <= 0x20 || u == 0x7f || c == '#') {
            c = '_';
        }
    }
    return obj.parent_path() / name;
}

/// A distinct, light diffuse colour per group (a pastel palette cycled).
std::array<double, 3> groupColour(std::size_t g) {
    static constexpr std::array<std::array<double, 3>, 8> PALETTE = {{
        {0.90, 0.62, 0.55},
        {0.55, 0.72, 0.90},
        {0.62, 0.85, 0.58},
        {0.92, 0.82, 0.50},
        {0.76, 0.62, 0.88},
        {0.52, 0.84, 0.82},
        {0.90, 0.66, 0.80},
        {0.74, 0.74, 0.70},
    }};
    return PALETTE[g % PALETTE.size()];
}

/// The groups to write: the mesh's, or one over every triangle.
std::vector<ObjGroup> groupsOf(const SurfaceMesh& mesh) {
    if (!mesh.groups.empty()) {
        return mesh.groups;
    }
    return {ObjGroup{"surface", 0, static_cast<int>(mesh.triangles.rows())}};
}

/// The name as a material and group name (the OBJ writer's rule, kept for every format).
std::string materialName(const std::string& name) {
    if (name.empty()) {
        return "default";
    }
    std::string out = name;
    for (char& c : out) {
        const auto u = static_cast<unsigned char>(c);
        if (u <= 0x20 || u == 0x7f || c == '#') {
            c = '_';
        }
    }
    return out;
}

std::string formatMtl(const std::vector<ObjGroup>& groups) {
    std::string out = "# Atelier: one material per panel\n";
    for (std::size_t g = 0; g < groups.size(); ++g) {
        const auto c = groupColour(g);
        char line[96];
        std::snprintf(line, sizeof line, "Kd %.3f %.3f %.3f\n", c[0], c[1], c[2]);
        out += "newmtl " + materialName(groups[g].name) + "\n";
        out += "Ka 0 0 0\n";
        out += line;
        out += "Ks 0 0 0\nd 1\nillum 1\n";
    }
    return out;
}

aiMaterial* makeMaterial(const std::string& name, std::size_t g) {
    auto* material = new aiMaterial();
    const aiString aiName(materialName(name));
    material->AddProperty(&aiName, AI_MATKEY_NAME);
    const auto c = groupColour(g);
    const aiColor3D diffuse(static_cast<float>(c[0]), static_cast<float>(c[1]),
                            static_cast<float>(c[2]));
    material->AddProperty(&diffuse, 1, AI_MATKEY_COLOR_DIFFUSE);
    const aiColor4D base(diffuse.r, diffuse.g, diffuse.b, 1.0f);
    material->AddProperty(&base, 1, AI_MATKEY_BASE_COLOR);
    return material;
}

/// An assimp mesh of the given corners: `vertexOf` maps a (position, uv) key to the mesh's
/// vertex; positions, normals and (when `withUvs`) UVs filled from the surface.
struct PieceBuilder {
    const SurfaceMesh& mesh;
    const sim::MatX3& normals;
    bool withUvs;

    aiMesh* build(int firstTriangle, int triangleCount, unsigned materialIndex,
                  const std::string& name) const {
        std::map<std::pair<int, int>, unsigned> vertexOf;
        std::vector<std::pair<int, int>> corners; // (position, uv) per mesh vertex
        std::vector<std::array<unsigned, 3>> faces;
        for (int f = firstTriangle; f < firstTriangle + triangleCount; ++f) {
            std::array<unsigned, 3> face{};
            for (int k = 0; k < 3; ++k) {
                const std::pair<int, int> key{mesh.triangles(f, k),
                                              withUvs ? mesh.uvTriangles(f, k) : -1};
                const auto [it, added] =
                    vertexOf.emplace(key, static_cast<unsigned>(corners.size()));
                if (added) {
                    corners.push_back(key);
                }
                face[static_cast<std::size_t>(k)] = it->second;
            }
            faces.push_back(face);
        }
        auto* out = new aiMesh();
        out->mName = aiString(materialName(name));
        out->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
        out->mMaterialIndex = materialIndex;
        out->mNumVertices = static_cast<unsigned>(corners.size());
        out->mVertices = new aiVector3D[corners.size()];
        out->mNormals = new aiVector3D[corners.size()];
        if (withUvs) {
            out->mTextureCoords[0] = new aiVector3D[corners.size()];
            out->mNumUVComponents[0] = 2;
        }
        for (std::size_t v = 0; v < corners.size(); ++v) {
            const auto [p, t] = corners[v];
            const auto f = [](double value) { return static_cast<ai_real>(value); };
            out->mVertices[v] = aiVector3D(f(mesh.positions(p, 0)), f(mesh.positions(p, 1)),
                                           f(mesh.positions(p, 2)));
            out->mNormals[v] = aiVector3D(f(normals(p, 0)), f(normals(p, 1)), f(normals(p, 2)));
            if (withUvs) {
                out->mTextureCoords[0][v] = aiVector3D(f(mesh.uvs(t, 0)), f(mesh.uvs(t, 1)), 0);
            }
        }
        out->mNumFaces = static_cast<unsigned>(faces.size());
        out->mFaces = new aiFace[faces.size()];
        for (std::size_t i = 0; i < faces.size(); ++i) {
            out->mFaces[i].mNumIndices = 3;
            out->mFaces[i].mIndices = new unsigned[3]{faces[i][0], faces[i][1], faces[i][2]};
        }
        return out;
    }
};

/// Whether every position has one UV over all its corners (then per-vertex UVs are exact).
bool oneUvPerPosition(const SurfaceMesh& mesh) {
    std::vector<int> uvOf(static_cast<std::size_t>(mesh.positions.rows()), -1);
    for (Eigen::Index f = 0; f < mesh.triangles.rows(); ++f) {
        for (int k = 0; k < 3; ++k) {
            int& seen = uvOf[static_cast<std::size_t>(mesh.triangles(f, k))];
            const int t = mesh.uvTriangles(f, k);
            if (seen >= 0 && seen != t && mesh.uvs.row(seen) != mesh.uvs.row(t)) {
                return false;
            }
            seen = t;
        }
    }
    return true;
}

/// The scene assimp exports: one mesh per group (glTF, FBX) or one mesh over every triangle
/// (PLY), each on a child node of the root.
std::unique_ptr<aiScene> buildScene(const SurfaceMesh& mesh, MeshFormat format,
                                    const sim::MatX3& normals) {
    const std::vector<ObjGroup> groups = groupsOf(mesh);
    auto scene = std::make_unique<aiScene>();
    scene->mRootNode = new aiNode("atelier");
    const bool hasUvs = mesh.uvs.rows() > 0;
    std::vector<aiMesh*> meshes;
    std::vector<aiMaterial*> materials;
    if (format == MeshFormat::Ply) {
        const PieceBuilder builder{mesh, normals, hasUvs && oneUvPerPosition(mesh)};
        meshes.push_back(builder.build(0, static_cast<int>(mesh.triangles.rows()), 0, "surface"));
        materials.push_back(makeMaterial("surface", 0));
    } else {
        const PieceBuilder builder{mesh, normals, hasUvs};
        for (std::size_t g = 0; g < groups.size(); ++g) {
            meshes.push_back(builder.build(groups[g].firstTriangle, groups[g].triangleCount,
                                           static_cast<unsigned>(g), groups[g].name));
            materials.push_back(makeMaterial(groups[g].name, g));
        }
    }
    scene->mNumMeshes = static_cast<unsigned>(meshes.size());
    scene->mMeshes = new aiMesh*[meshes.size()];
    std::copy(meshes.begin(), meshes.end(), scene->mMeshes);
    scene->mNumMaterials = static_cast<unsigned>(materials.size());
    scene->mMaterials = new aiMaterial*[materials.size()];
    std::copy(materials.begin(), materials.end(), scene->mMaterials);
    scene->mRootNode->mNumChildren = static_cast<unsigned>(meshes.size());
    scene->mRootNode->mChildren = new aiNode*[meshes.size()];
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        auto* node = new aiNode(meshes[m]->mName.C_Str());
        node->mParent = scene->mRootNode;
        node->mNumMeshes = 1;
        node->mMeshes = new unsigned[1]{static_cast<unsigned>(m)};
        scene->mRootNode->mChildren[m] = node;
    }
    return scene;
}

Result<void> checkSurface(const std::filesystem::path& path, const SurfaceMesh& mesh) {
    const auto fail = [&path](std::string message) {
        return Error{path.string(), "", std::move(message)};
    };
    if (mesh.triangles.rows() == 0) {
        return fail("nothing to export: the surface has no triangles");
    }
    if (!mesh.positions.allFinite()) {
        return fail("the surface has a non-finite position");
    }
    if (mesh.triangles.minCoeff() < 0 || mesh.triangles.maxCoeff() >= mesh.positions.rows()) {
        return fail("a triangle's vertex index is out of range");
    }
    if (mesh.uvs.rows() > 0 &&
        (mesh.uvTriangles.rows() != mesh.triangles.rows() || mesh.uvTriangles.minCoeff() < 0 ||
         mesh.uvTriangles.maxCoeff() >= mesh.uvs.rows())) {
        return fail("the texture coordinates do not match the triangles");
    }
    for (const ObjGroup& g : mesh.groups) {
        if (g.firstTriangle < 0 || g.triangleCount < 0 ||
            g.firstTriangle + g.triangleCount > mesh.triangles.rows()) {
            return fail("group '" + g.name + "' is out of the triangle range");
        }
    }
    return {};
}

} // namespace

SurfaceMesh weldedSurface(const sim::MatX3& x, const sim::MatX3i& triangles, const sim::MatX2& uvs,
                          std::vector<ObjGroup> groups,
                          const std::vector<std::pair<int, int>>& welds) {
    const auto n = static_cast<std::size_t>(x.rows());
    // A group's vertex sits where its first member does in the order.
    const std::vector<int> group = sim::joinedGroups(static_cast<int>(n), welds);
    const auto root = [&group](int v) { return group[static_cast<std::size_t>(v)]; };
    std::vector<int> compact(n, -1);
    int next = 0;
    for (std::size_t v = 0; v < n; ++v) {
        if (root(static_cast<int>(v)) == static_cast<int>(v)) {
            compact[v] = next++;
        }
    }
    SurfaceMesh out;
    out.positions = sim::MatX3::Zero(next, 3);
    std::vector<int> members(static_cast<std::size_t>(next), 0);
    for (std::size_t v = 0; v < n; ++v) {
        const int id = compact[static_cast<std::size_t>(root(static_cast<int>(v)))];
        out.positions.row(id) += x.row(static_cast<Eigen::Index>(v));
        ++members[static_cast<std::size_t>(id)];
    }
    for (int id = 0; id < next; ++id) {
        out.positions.row(id) /= members[static_cast<std::size_t>(id)];
    }
    out.triangles.resize(triangles.rows(), 3);
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
        for (int k = 0; k < 3; ++k) {
            out.triangles(f, k) = compact[static_cast<std::size_t>(root(triangles(f, k)))];
        }
    }
    if (uvs.rows() > 0) {
        out.uvs = uvs;
        out.uvTriangles = triangles;
    }
    out.groups = std::move(groups);
    return out;
}

std::string_view meshFormatName(MeshFormat format) {
    return info(format).name;
}

std::optional<MeshFormat> parseMeshFormat(std::string_view name) {
    for (const FormatInfo& f : FORMATS) {
        if (name == f.name) {
            return f.format;
        }
    }
    return std::nullopt;
}

std::optional<MeshFormat> meshFormatOfPath(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext) {
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
    for (const FormatInfo& f : FORMATS) {
        if (f.extension != nullptr && ext == f.extension) {
            return f.format;
        }
    }
    return std::nullopt;
}

std::string meshFormatList() {
    std::string out;
    for (const FormatInfo& f : FORMATS) {
        out += (out.empty() ? "" : ", ") + std::string(f.name);
    }
    return out;
}

std::vector<std::filesystem::path> exportedFiles(const std::filesystem::path& path,
                                                 MeshFormat format) {
    if (format == MeshFormat::Obj) {
        return {path, mtlPath(path)};
    }
    return {path};
}

Result<void> exportMesh(const std::filesystem::path& path, const SurfaceMesh& mesh,
                        MeshFormat format) {
    if (auto checked = checkSurface(path, mesh); !checked.ok()) {
        return checked;
    }
    sim::MatX3 normals;
    sim::vertexNormals(mesh.positions, mesh.triangles, normals);
    if (format == MeshFormat::Obj) {
        const std::vector<ObjGroup> groups = groupsOf(mesh);
        const std::filesystem::path mtl = mtlPath(path);
        if (auto written = writeFileAtomically(mtl, formatMtl(groups)); !written.ok()) {
            return written;
        }
        ObjWriteOptions options;
        options.uvs = mesh.uvs;
        options.uvTriangles = mesh.uvTriangles;
        options.groups = groups;
        options.comment = mesh.comment;
        options.materialLibrary = mtl.filename().string();
        return writeObj(path, mesh.positions, mesh.triangles, options);
    }
    const std::unique_ptr<aiScene> scene = buildScene(mesh, format, normals);
    Assimp::Exporter exporter;
    // The whole file in memory, then written atomically (no partial file at `path`).
    const aiExportDataBlob* blob = exporter.ExportToBlob(scene.get(), info(format).assimpId);
    if (blob == nullptr) {
        return Error{path.string(), "",
                     std::string("cannot export as ") + info(format).name + ": " +
                         exporter.GetErrorString()};
    }
    return writeFileAtomically(path,
                               std::string_view(static_cast<const char*>(blob->data), blob->size));
}

} // namespace atelier::io
