#include "io/mesh_import.h"

#include "io/assimp_scene.h"
#include "io/atomic_file.h"
#include "io/body_file.h"
#include "io/json_reader.h"
#include "io/obj.h"

#include "sim/mesh/joined_vertices.h"

#include <assimp/Importer.hpp>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <unordered_map>
#include <utility>

namespace atelier::io {

namespace {

std::string lowerExtension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    for (char& c : ext) {
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
    return ext;
}

std::string formatOfExtension(const std::string& ext) {
    if (ext == ".obj") {
        return "OBJ";
    }
    if (ext == ".fbx") {
        return "FBX";
    }
    if (ext == ".gltf" || ext == ".glb") {
        return "glTF 2.0";
    }
    if (ext == ".dae") {
        return "COLLADA";
    }
    if (ext == ".ply") {
        return "PLY";
    }
    return "STL";
}

/// Places every mesh instance of an assimp scene by its node's accumulated transform (so the
/// vertices are in scene coordinates), polygons fanned into triangles.
Result<RawMesh> rawMeshOf(const std::string& file, const detail::AssimpScene& read,
                          long long maxVertices) {
    const aiScene* scene = read.scene;
    RawMesh raw;
    raw.format = read.format;
    raw.metadataUp = read.metadataUp;
    std::vector<sim::Vec3> positions;
    std::vector<std::array<int, 3>> triangles;
    // Depth-first over the nodes with an explicit stack (a deep tree cannot overflow ours).
    std::vector<std::pair<const aiNode*, aiMatrix4x4>> stack;
    if (scene->mRootNode != nullptr) {
        stack.emplace_back(scene->mRootNode, scene->mRootNode->mTransformation);
    }
    while (!stack.empty()) {
        const auto [node, transform] = stack.back();
        stack.pop_back();
        for (unsigned c = 0; c < node->mNumChildren; ++c) {
            if (node->mChildren[c] != nullptr) {
                stack.emplace_back(node->mChildren[c],
                                   transform * node->mChildren[c]->mTransformation);
            }
        }
        for (unsigned i = 0; i < node->mNumMeshes; ++i) {
            if (node->mMeshes[i] >= scene->mNumMeshes) {
                return Error{file, "", "a node names a mesh the file does not hold"};
            }
            const aiMesh* mesh = scene->mMeshes[node->mMeshes[i]];
            if (static_cast<long long>(positions.size()) + mesh->mNumVertices > maxVertices) {
                return Error{file, "",
                             "more than " + std::to_string(maxVertices) +
                                 " vertices (the limit body-vertices)"};
            }
            const auto base = static_cast<int>(positions.size());
            for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
                const aiVector3D p = transform * mesh->mVertices[v];
                positions.emplace_back(p.x, p.y, p.z);
            }
            if (auto added = detail::appendTriangles(*mesh, base, file, triangles); !added.ok()) {
                return added.error();
            }
            raw.hasUvs = raw.hasUvs || mesh->HasTextureCoords(0);
            aiString name;
            if (mesh->mMaterialIndex < scene->mNumMaterials) {
                scene->mMaterials[mesh->mMaterialIndex]->Get(AI_MATKEY_NAME, name);
            }
            raw.materials.emplace_back(name.C_Str());
        }
    }
    raw.positions.resize(static_cast<Eigen::Index>(positions.size()), 3);
    for (std::size_t i = 0; i < positions.size(); ++i) {
        raw.positions.row(static_cast<Eigen::Index>(i)) = positions[i];
    }
    raw.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
    for (std::size_t f = 0; f < triangles.size(); ++f) {
        for (int k = 0; k < 3; ++k) {
            raw.triangles(static_cast<Eigen::Index>(f), k) =
                triangles[f][static_cast<std::size_t>(k)];
        }
    }
    return raw;
}

/// The error for an extension outside bodyMeshExtensions, or nullopt.
std::optional<Error> unsupported(const std::filesystem::path& path, const std::string& ext) {
    const auto& known = bodyMeshExtensions();
    if (std::find(known.begin(), known.end(), ext) != known.end()) {
        return std::nullopt;
    }
    std::string list;
    for (const std::string& e : known) {
        list += (list.empty() ? "" : ", ") + e;
    }
    return Error{path.string(), "",
                 "unsupported mesh format \"" + ext + "\" (supported: " + list + ")"};
}

struct CellHash {
    std::size_t operator()(const std::array<long long, 3>& c) const {
        std::size_t h = 1469598103934665603ULL;
        for (const long long v : c) {
            h = (h ^ static_cast<std::size_t>(v)) * 1099511628211ULL;
        }
        return h;
    }
};

} // namespace

std::optional<LengthUnit> parseLengthUnit(std::string_view text) {
    if (text == "mm") {
        return LengthUnit::Millimetre;
    }
    if (text == "cm") {
        return LengthUnit::Centimetre;
    }
    if (text == "m") {
        return LengthUnit::Metre;
    }
    if (text == "auto") {
        return LengthUnit::Auto;
    }
    return std::nullopt;
}

std::optional<UpAxis> parseUpAxis(std::string_view text) {
    if (text == "y") {
        return UpAxis::Y;
    }
    if (text == "z") {
        return UpAxis::Z;
    }
    if (text == "auto") {
        return UpAxis::Auto;
    }
    return std::nullopt;
}

std::string_view unitName(LengthUnit unit) {
    switch (unit) {
    case LengthUnit::Millimetre:
        return "mm";
    case LengthUnit::Centimetre:
        return "cm";
    case LengthUnit::Metre:
        return "m";
    default:
        return "auto";
    }
}

std::string_view axisName(UpAxis axis) {
    switch (axis) {
    case UpAxis::Y:
        return "y";
    case UpAxis::Z:
        return "z";
    default:
        return "auto";
    }
}

double metresPerUnit(LengthUnit unit) {
    switch (unit) {
    case LengthUnit::Millimetre:
        return 0.001;
    case LengthUnit::Centimetre:
        return 0.01;
    default:
        return 1.0;
    }
}

const std::vector<std::string>& bodyMeshExtensions() {
    static const std::vector<std::string> EXTENSIONS = {".obj", ".fbx", ".gltf", ".glb",
                                                        ".dae", ".ply", ".stl"};
    return EXTENSIONS;
}

bool hasBodyMeshExtension(const std::filesystem::path& path) {
    const std::vector<std::string>& extensions = bodyMeshExtensions();
    return std::find(extensions.begin(), extensions.end(), lowerExtension(path)) !=
           extensions.end();
}

void weldByPosition(sim::MatX3& positions, sim::MatX3i& triangles, double distance, long& dropped,
                    std::vector<int>* sourceToWelded) {
    const Eigen::Index n = positions.rows();
    std::vector<int> target(static_cast<std::size_t>(n));
    std::iota(target.begin(), target.end(), 0);
    if (distance > 0) {
        // Vertices in a grid of cells `distance` wide: a partner is in one of the 27 cells
        // around a vertex's own.
        std::unordered_map<std::array<long long, 3>, std::vector<int>, CellHash> cells;
        cells.reserve(static_cast<std::size_t>(n));
        const double d2 = distance * distance;
        for (Eigen::Index i = 0; i < n; ++i) {
            std::array<long long, 3> cell{};
            for (int k = 0; k < 3; ++k) {
                cell[static_cast<std::size_t>(k)] =
                    static_cast<long long>(std::floor(positions(i, k) / distance));
            }
            int found = -1;
            for (long long dx = -1; dx <= 1 && found < 0; ++dx) {
                for (long long dy = -1; dy <= 1 && found < 0; ++dy) {
                    for (long long dz = -1; dz <= 1 && found < 0; ++dz) {
                        const auto it = cells.find({cell[0] + dx, cell[1] + dy, cell[2] + dz});
                        if (it == cells.end()) {
                            continue;
                        }
                        for (const int j : it->second) {
                            if ((positions.row(i) - positions.row(j)).squaredNorm() <= d2) {
                                found = j;
                                break;
                            }
                        }
                    }
                }
            }
            if (found >= 0) {
                target[static_cast<std::size_t>(i)] = found;
            } else {
                cells[cell].push_back(static_cast<int>(i));
            }
        }
    }
    // Reindex, drop degenerate triangles, then compact the vertices in first-use order of the
    // kept ones (by index).
    std::vector<std::array<int, 3>> kept;
    kept.reserve(static_cast<std::size_t>(triangles.rows()));
    dropped = 0;
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
        std::array<int, 3> t{};
        for (int k = 0; k < 3; ++k) {
            t[static_cast<std::size_t>(k)] = target[static_cast<std::size_t>(triangles(f, k))];
        }
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
            ++dropped;
            continue;
        }
        kept.push_back(t);
    }
    std::vector<int> newIndex(static_cast<std::size_t>(n), -1);
    for (const auto& t : kept) {
        for (const int v : t) {
            newIndex[static_cast<std::size_t>(v)] = 0;
        }
    }
    int next = 0;
    for (auto& id : newIndex) {
        if (id == 0) {
            id = next++;
        }
    }
    sim::MatX3 compact(next, 3);
    for (Eigen::Index i = 0; i < n; ++i) {
        if (const int id = newIndex[static_cast<std::size_t>(i)]; id >= 0) {
            compact.row(id) = positions.row(i);
        }
    }
    positions = std::move(compact);
    if (sourceToWelded != nullptr) {
        sourceToWelded->resize(static_cast<std::size_t>(n));
        for (Eigen::Index i = 0; i < n; ++i) {
            (*sourceToWelded)[static_cast<std::size_t>(i)] =
                newIndex[static_cast<std::size_t>(target[static_cast<std::size_t>(i)])];
        }
    }
    triangles.resize(static_cast<Eigen::Index>(kept.size()), 3);
    for (std::size_t f = 0; f < kept.size(); ++f) {
        for (int k = 0; k < 3; ++k) {
            triangles(static_cast<Eigen::Index>(f), k) =
                newIndex[static_cast<std::size_t>(kept[f][static_cast<std::size_t>(k)])];
        }
    }
}

EdgeFigures edgeFigures(const sim::MatX3i& triangles, Eigen::Index vertexCount) {
    std::vector<std::pair<int, int>> edges;
    edges.reserve(static_cast<std::size_t>(3 * triangles.rows()));
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
        for (int k = 0; k < 3; ++k) {
            const int a = triangles(f, k);
            const int b = triangles(f, (k + 1) % 3);
            edges.emplace_back(std::min(a, b), std::max(a, b));
        }
    }
    std::sort(edges.begin(), edges.end());
    EdgeFigures out;
    // Boundary loops: connected groups of boundary edges (joined over their vertices).
    std::vector<std::pair<int, int>> boundary;
    std::vector<char> onBoundary(static_cast<std::size_t>(vertexCount), 0);
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && edges[j] == edges[i]) {
            ++j;
        }
        const std::size_t uses = j - i;
        if (uses == 1) {
            ++out.boundaryEdges;
            const auto [a, b] = edges[i];
            onBoundary[static_cast<std::size_t>(a)] = 1;
            onBoundary[static_cast<std::size_t>(b)] = 1;
            boundary.emplace_back(a, b);
        } else if (uses > 2) {
            ++out.nonManifoldEdges;
        }
        i = j;
    }
    const std::vector<int> loop = sim::joinedGroups(static_cast<int>(vertexCount), boundary);
    for (Eigen::Index v = 0; v < vertexCount; ++v) {
        if (onBoundary[static_cast<std::size_t>(v)] != 0 &&
            loop[static_cast<std::size_t>(v)] == v) {
            ++out.holes;
        }
    }
    return out;
}

Result<ImportedBody> normaliseBody(const RawMesh& raw, const std::string& file,
                                   const BodyImportOptions& options, const Limits& limits) {
    const auto fail = [&file](std::string message) { return Error{file, "", std::move(message)}; };
    for (Eigen::Index i = 0; i < raw.positions.rows(); ++i) {
        if (!raw.positions.row(i).allFinite()) {
            return fail("vertex " + std::to_string(i) + " is not finite");
        }
    }
    for (Eigen::Index f = 0; f < raw.triangles.rows(); ++f) {
        for (int k = 0; k < 3; ++k) {
            if (raw.triangles(f, k) < 0 || raw.triangles(f, k) >= raw.positions.rows()) {
                return fail("triangle " + std::to_string(f) + " has a vertex index out of range");
            }
        }
    }
    if (raw.triangles.rows() == 0) {
        return fail("the file holds no triangles: it cannot be a body");
    }
    if (raw.triangles.rows() < 4) {
        return fail(std::to_string(raw.triangles.rows()) +
                    (raw.triangles.rows() == 1 ? " triangle" : " triangles") +
                    " cannot be a body (a body is a surface around a volume: at least 4)");
    }
    ImportedBody out;
    BodyImportReport& report = out.report;
    report.format = raw.format;
    report.sourceVertices = static_cast<long>(raw.positions.rows());

    // The file's extents decide the up axis (a standing body is several times taller than it
    // is deep) and, through its height, the unit.
    const sim::Vec3 lo = raw.positions.colwise().minCoeff();
    const sim::Vec3 hi = raw.positions.colwise().maxCoeff();
    const sim::Vec3 extent = hi - lo;
    if (!(extent.minCoeff() > 1e-6 * extent.maxCoeff())) {
        return fail("the mesh is flat (" + detail::figure(extent.x()) + " × " +
                    detail::figure(extent.y()) + " × " + detail::figure(extent.z()) +
                    " file units): it cannot be a body");
    }
    if (options.up != UpAxis::Auto) {
        report.up = options.up;
        report.upFrom = "given";
    } else {
        const UpAxis byBox = extent.y() >= extent.z() ? UpAxis::Y : UpAxis::Z;
        const bool decisive =
            std::max(extent.y(), extent.z()) >= 1.5 * std::min(extent.y(), extent.z());
        if (raw.metadataUp && (!decisive || *raw.metadataUp == byBox)) {
            report.up = *raw.metadataUp;
            report.upFrom = "the file's metadata";
        } else {
            report.up = byBox;
            report.upFrom = "the bounding box";
            if (raw.metadataUp) {
                report.warnings.push_back(
                    "the file declares " + std::string(axisName(*raw.metadataUp)) +
                    " up but the body is tallest along " + std::string(axisName(byBox)) +
                    ": using " + std::string(axisName(byBox)) + " (give the up axis if wrong)");
            } else if (!decisive) {
                report.warnings.push_back("the mesh is about as deep as it is tall: assumed " +
                                          std::string(axisName(byBox)) +
                                          " up (give the up axis if wrong)");
            }
        }
    }
    report.fileHeight = report.up == UpAxis::Z ? extent.z() : extent.y();
    if (options.units != LengthUnit::Auto) {
        report.units = options.units;
        report.unitsFrom = "given";
    } else {
        bool found = false;
        for (const LengthUnit unit :
             {LengthUnit::Metre, LengthUnit::Centimetre, LengthUnit::Millimetre}) {
            const double h = report.fileHeight * metresPerUnit(unit);
            if (h >= MIN_DETECTED_HEIGHT && h <= MAX_DETECTED_HEIGHT) {
                report.units = unit;
                found = true;
            }
        }
        if (!found) {
            return fail("the mesh is " + detail::figure(report.fileHeight) +
                        " file units tall: in no unit (mm, cm, m) is that a body " +
                        detail::figure(MIN_DETECTED_HEIGHT) + " to " +
                        detail::figure(MAX_DETECTED_HEIGHT) +
                        " m tall (give the unit if it is one)");
        }
        report.unitsFrom = "the height";
    }

    // To metres, Y up, standing on y = 0.
    const double scale = metresPerUnit(report.units);
    sim::MatX3 x(raw.positions.rows(), 3);
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
        const sim::Vec3 p = raw.positions.row(i);
        x.row(i) = report.up == UpAxis::Z ? sim::Vec3(p.x(), p.z(), -p.y()) : p;
    }
    x *= scale;
    out.floorOffset = x.col(1).minCoeff();
    x.col(1).array() -= out.floorOffset;
    report.height = x.col(1).maxCoeff();
    if (auto problem = checkBodyExtent(x, limits.maxBodyExtent)) {
        return fail(*problem);
    }

    sim::MatX3i triangles = raw.triangles;
    weldByPosition(x, triangles, options.weldDistance, report.droppedTriangles, &out.fromSource);
    if (triangles.rows() < 4) {
        return fail("once vertices closer than " + detail::figure(options.weldDistance) +
                    " m are welded, " + std::to_string(triangles.rows()) +
                    " triangles are left: it cannot be a body");
    }
    report.vertices = static_cast<long>(x.rows());
    report.triangles = static_cast<long>(triangles.rows());
    const EdgeFigures edges = edgeFigures(triangles, x.rows());
    report.boundaryEdges = edges.boundaryEdges;
    report.holes = edges.holes;
    report.nonManifoldEdges = edges.nonManifoldEdges;
    if (report.droppedTriangles > 0) {
        report.warnings.push_back(std::to_string(report.droppedTriangles) +
                                  " degenerate triangles dropped");
    }
    if (edges.holes > 0) {
        report.warnings.push_back("the surface is open: " + std::to_string(edges.holes) +
                                  (edges.holes == 1 ? " hole (" : " holes (") +
                                  std::to_string(edges.boundaryEdges) + " boundary edges)");
    }
    if (edges.nonManifoldEdges > 0) {
        report.warnings.push_back(std::to_string(edges.nonManifoldEdges) +
                                  " non-manifold edges (shared by three or more triangles)");
    }
    out.vertices = std::move(x);
    out.triangles = std::move(triangles);
    return out;
}

Result<RawMesh> readMesh(const std::filesystem::path& path, std::uint64_t maxBytes,
                         long long maxVertices) {
    auto read = detail::readAssimpScene(path, maxBytes, Limits{}.maxJsonDepth);
    if (!read.ok()) {
        return read.error();
    }
    return rawMeshOf(path.string(), read.value(), maxVertices);
}

namespace detail {

namespace {

/// The JSON of a glTF file: all of a .gltf, the first chunk of a .glb when it is its JSON
/// chunk (a 12-byte header, then the chunk's length and type "JSON"); empty otherwise.
std::string_view gltfJson(const std::string& ext, const std::string& text) {
    if (ext == ".gltf") {
        return text;
    }
    if (ext != ".glb" || text.size() < 20 || text.compare(16, 4, "JSON") != 0) {
        return {};
    }
    std::uint32_t length = 0;
    for (int k = 3; k >= 0; --k) {
        length = (length << 8) | static_cast<unsigned char>(text[12 + static_cast<std::size_t>(k)]);
    }
    return std::string_view(text).substr(20, length);
}

} // namespace

AssimpScene::AssimpScene() = default;
AssimpScene::AssimpScene(AssimpScene&&) noexcept = default;
AssimpScene& AssimpScene::operator=(AssimpScene&&) noexcept = default;
AssimpScene::~AssimpScene() = default;

std::string figure(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", value);
    return text;
}

Result<AssimpScene> readAssimpScene(const std::filesystem::path& path, std::uint64_t maxBytes,
                                    int maxJsonDepth) {
    const std::string ext = lowerExtension(path);
    if (auto error = unsupported(path, ext)) {
        return *error;
    }
    auto text = readFile(path, maxBytes);
    if (!text.ok()) {
        return text.error();
    }
    const std::string file = path.string();
    // assimp's glTF reader parses its JSON recursively: 200,000 nested arrays overflow the stack
    // (a fuzzed .gltf, tests/fuzz/regressions/gltf-body-nested-arrays-stack-overflow).
    if (const std::string_view json = gltfJson(ext, text.value()); !json.empty()) {
        if (auto error = checkJsonStructure(json, file, maxJsonDepth)) {
            return *error;
        }
    }
    AssimpScene out;
    out.importer = std::make_unique<Assimp::Importer>();
    const unsigned steps = aiProcess_ValidateDataStructure;
    // A .gltf (which may name other files) is read from the file, the others from memory.
    out.scene = ext == ".gltf"
                    ? out.importer->ReadFile(file, steps)
                    : out.importer->ReadFileFromMemory(text.value().data(), text.value().size(),
                                                       steps, ext.substr(1).c_str());
    if (out.scene == nullptr) {
        std::string why = out.importer->GetErrorString();
        return Error{file, "", "cannot read the mesh: " + (why.empty() ? "unknown error" : why)};
    }
    out.format = formatOfExtension(ext);
    if (ext == ".gltf" || ext == ".glb") {
        out.metadataUp = UpAxis::Y;
    } else if (out.scene->mMetaData != nullptr) {
        int up = -1;
        if (out.scene->mMetaData->Get("UpAxis", up) && (up == 1 || up == 2)) {
            out.metadataUp = up == 1 ? UpAxis::Y : UpAxis::Z;
        }
    }
    return out;
}

Result<void> appendTriangles(const aiMesh& mesh, int base, const std::string& file,
                             std::vector<std::array<int, 3>>& triangles) {
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
        const aiFace& face = mesh.mFaces[f];
        for (unsigned k = 0; k < face.mNumIndices; ++k) {
            if (face.mIndices[k] >= mesh.mNumVertices) {
                return Error{file, "",
                             "a face names a vertex the mesh does not hold (" +
                                 std::to_string(face.mIndices[k]) + " of " +
                                 std::to_string(mesh.mNumVertices) + ")"};
            }
        }
        // Polygons as fans; points and lines (fewer than 3 corners) carry no surface.
        for (unsigned k = 1; k + 1 < face.mNumIndices; ++k) {
            triangles.push_back({base + static_cast<int>(face.mIndices[0]),
                                 base + static_cast<int>(face.mIndices[k]),
                                 base + static_cast<int>(face.mIndices[k + 1])});
        }
    }
    return {};
}

} // namespace detail

namespace {

/// A body file as read: our OBJ reader for .obj, assimp for the other formats.
Result<RawMesh> readBodyFile(const std::filesystem::path& path, const Limits& limits) {
    const std::string ext = lowerExtension(path);
    if (auto error = unsupported(path, ext)) {
        return *error;
    }
    if (ext != ".obj") {
        auto read = detail::readAssimpScene(path, limits.maxMeshBytes, limits.maxJsonDepth);
        if (!read.ok()) {
            return read.error();
        }
        return rawMeshOf(path.string(), read.value(), limits.maxBodyVertices);
    }
    auto obj = readObj(path, limits.maxMeshBytes);
    if (!obj.ok()) {
        return obj.error();
    }
    RawMesh raw;
    raw.positions = std::move(obj.value().positions);
    raw.triangles = std::move(obj.value().triangles);
    raw.format = "OBJ";
    return raw;
}

} // namespace

Result<ImportedBody> importBody(const std::filesystem::path& path, const BodyImportOptions& options,
                                const Limits& limits) {
    auto raw = readBodyFile(path, limits);
    if (!raw.ok()) {
        return raw.error();
    }
    return normaliseBody(raw.value(), path.string(), options, limits);
}

Result<sim::MatX3> placeAsFirstFrame(const sim::MatX3& positions, const ImportedBody& first,
                                     const std::string& file, const Limits& limits) {
    const BodyImportReport& how = first.report;
    const double scale = metresPerUnit(how.units);
    sim::MatX3 x = sim::MatX3::Zero(first.vertices.rows(), 3);
    for (Eigen::Index i = 0; i < positions.rows(); ++i) {
        const int target = i < static_cast<Eigen::Index>(first.fromSource.size())
                               ? first.fromSource[static_cast<std::size_t>(i)]
                               : -1;
        if (target < 0) {
            continue;
        }
        const sim::Vec3 p = positions.row(i);
        if (!p.allFinite()) {
            return Error{file, "", "vertex " + std::to_string(i) + " is not finite"};
        }
        sim::Vec3 q = how.up == UpAxis::Z ? sim::Vec3(p.x(), p.z(), -p.y()) : p;
        q *= scale;
        q.y() -= first.floorOffset;
        x.row(target) = q.transpose();
    }
    if (auto problem = checkBodyExtent(x, limits.maxBodyExtent)) {
        return Error{file, "", *problem};
    }
    return x;
}

Result<BodyMotion> importBodyMotion(const std::vector<std::filesystem::path>& files,
                                    const BodyImportOptions& options, const Limits& limits) {
    if (files.size() < 2) {
        return Error{files.empty() ? std::string() : files.front().string(), "",
                     "a motion needs at least two frames, " + std::to_string(files.size()) +
                         (files.size() == 1 ? " was given" : " were given")};
    }
    BodyMotion motion;
    auto firstRaw = readBodyFile(files.front(), limits);
    if (!firstRaw.ok()) {
        return firstRaw.error();
    }
    auto first = normaliseBody(firstRaw.value(), files.front().string(), options, limits);
    if (!first.ok()) {
        return first.error();
    }
    motion.first = std::move(first).value();
    const ImportedBody& body = motion.first;
    const sim::MatX3i firstTriangles = firstRaw.value().triangles;
    const long long firstVertexCount = firstRaw.value().positions.rows();
    for (std::size_t k = 0; k < files.size(); ++k) {
        const std::string file = files[k].string();
        Result<RawMesh> raw = k == 0 ? std::move(firstRaw) : readBodyFile(files[k], limits);
        if (!raw.ok()) {
            return raw.error();
        }
        const RawMesh& mesh = raw.value();
        if (k > 0 &&
            (mesh.positions.rows() != firstVertexCount ||
             mesh.triangles.rows() != firstTriangles.rows() || mesh.triangles != firstTriangles)) {
            return Error{file, "",
                         "frame " + std::to_string(k) + " is not the first frame's mesh moved (" +
                             std::to_string(mesh.positions.rows()) + " vertices and " +
                             std::to_string(mesh.triangles.rows()) + " triangles against " +
                             std::to_string(firstVertexCount) + " and " +
                             std::to_string(firstTriangles.rows()) +
                             ", or the triangles differ): every frame must be the same mesh"};
        }
        auto x = placeAsFirstFrame(mesh.positions, body, file, limits);
        if (!x.ok()) {
            return x.error();
        }
        motion.frames.push_back(std::move(x).value());
        motion.files.push_back(file);
    }
    return motion;
}

} // namespace atelier::io
