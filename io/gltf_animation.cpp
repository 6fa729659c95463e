#include "io/gltf_animation.h"

#include "io/atomic_file.h"

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>

namespace atelier::io {

namespace {

using nlohmann::json;

constexpr std::uint32_t GLB_MAGIC = 0x46546C67;  // "glTF"
constexpr std::uint32_t CHUNK_JSON = 0x4E4F534A; // "JSON"
constexpr std::uint32_t CHUNK_BIN = 0x004E4942;  // "BIN\0"
constexpr int FLOAT = 5126, UNSIGNED_INT = 5125; // accessor component types
constexpr int ARRAY_BUFFER = 34962, ELEMENT_ARRAY_BUFFER = 34963;

/// The binary chunk and the JSON entries that point into it.
class GlbBuilder {
  public:
    /// Appends floats as one buffer view and accessor; returns the accessor index. `type` is
    /// "SCALAR" or "VEC3"; `bounds` adds min and max (required for positions and times).
    int floats(const std::vector<float>& values, const char* type, bool bounds, int target) {
        const int components = std::strcmp(type, "VEC3") == 0 ? 3 : 1;
        json accessor = {{"bufferView", view(values.data(), values.size() * sizeof(float), target)},
                         {"componentType", FLOAT},
                         {"count", values.size() / static_cast<std::size_t>(components)},
                         {"type", type}};
        if (bounds) {
            std::vector<float> lo(static_cast<std::size_t>(components),
                                  std::numeric_limits<float>::max());
            std::vector<float> hi(static_cast<std::size_t>(components),
                                  std::numeric_limits<float>::lowest());
            for (std::size_t i = 0; i < values.size(); ++i) {
                const std::size_t c = i % static_cast<std::size_t>(components);
                lo[c] = std::min(lo[c], values[i]);
                hi[c] = std::max(hi[c], values[i]);
            }
            accessor["min"] = lo;
            accessor["max"] = hi;
        }
        accessors.push_back(std::move(accessor));
        return static_cast<int>(accessors.size()) - 1;
    }
    int indices(const std::vector<std::uint32_t>& values) {
        accessors.push_back(
            {{"bufferView", view(values.data(), values.size() * 4, ELEMENT_ARRAY_BUFFER)},
             {"componentType", UNSIGNED_INT},
             {"count", values.size()},
             {"type", "SCALAR"}});
        return static_cast<int>(accessors.size()) - 1;
    }

    json accessors = json::array();
    json views = json::array();
    std::string bin;

  private:
    int view(const void* data, std::size_t bytes, int target) {
        json v = {{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}};
        if (target != 0) {
            v["target"] = target;
        }
        bin.append(static_cast<const char*>(data), bytes);
        bin.append((4 - bin.size() % 4) % 4, '\0');
        views.push_back(std::move(v));
        return static_cast<int>(views.size()) - 1;
    }
};

std::vector<float> asFloats(const sim::MatX3& x) {
    std::vector<float> out(static_cast<std::size_t>(x.rows()) * 3);
    for (Eigen::Index i = 0; i < x.rows(); ++i) {
        for (int k = 0; k < 3; ++k) {
            out[static_cast<std::size_t>(3 * i + k)] = static_cast<float>(x(i, k));
        }
    }
    return out;
}

/// Area-weighted vertex normals, unit length (+y where a vertex has no area).
sim::MatX3 vertexNormals(const sim::MatX3& x, const sim::MatX3i& triangles) {
    sim::MatX3 n = sim::MatX3::Zero(x.rows(), 3);
    for (Eigen::Index f = 0; f < triangles.rows(); ++f) {
        const sim::Vec3 a = x.row(triangles(f, 0)), b = x.row(triangles(f, 1)),
                        c = x.row(triangles(f, 2));
        const sim::Vec3 area = (b - a).cross(c - a);
        for (int k = 0; k < 3; ++k) {
            n.row(triangles(f, k)) += area.transpose();
        }
    }
    for (Eigen::Index i = 0; i < n.rows(); ++i) {
        const double length = n.row(i).norm();
        if (length > 0) {
            n.row(i) /= length;
        } else {
            n.row(i) = sim::Vec3::UnitY().transpose();
        }
    }
    return n;
}

void appendLittleEndian(std::string& out, std::uint32_t value) {
    for (int k = 0; k < 4; ++k) {
        out.push_back(static_cast<char>((value >> (8 * k)) & 0xFFu));
    }
}

std::optional<std::string> checkInput(const std::vector<SequenceMesh>& meshes,
                                      const std::vector<double>& times) {
    if (meshes.empty()) {
        return "no mesh to write";
    }
    if (times.empty()) {
        return "no frame to write";
    }
    for (std::size_t k = 0; k < times.size(); ++k) {
        if (!std::isfinite(times[k]) || (k > 0 && !(times[k] > times[k - 1]))) {
            return "the frame times must increase (frame " + std::to_string(k) + ")";
        }
    }
    for (const SequenceMesh& m : meshes) {
        if (m.frames.size() != times.size()) {
            return "mesh '" + m.name + "' has " + std::to_string(m.frames.size()) + " frames for " +
                   std::to_string(times.size()) + " times";
        }
        for (std::size_t k = 0; k < m.frames.size(); ++k) {
            if (m.frames[k].rows() != m.frames.front().rows()) {
                return "mesh '" + m.name + "' changes its vertex count at frame " +
                       std::to_string(k);
            }
            if (!m.frames[k].allFinite()) {
                return "mesh '" + m.name + "' has a non-finite position at frame " +
                       std::to_string(k);
            }
        }
        if (m.triangles.size() > 0 &&
            (m.triangles.minCoeff() < 0 || m.triangles.maxCoeff() >= m.frames.front().rows())) {
            return "mesh '" + m.name + "' has a triangle index out of range";
        }
    }
    return std::nullopt;
}

} // namespace

Result<void> writeSequenceGlb(const std::filesystem::path& path,
                              const std::vector<SequenceMesh>& meshes,
                              const std::vector<double>& times) {
    if (auto problem = checkInput(meshes, times)) {
        return Error{path.string(), "", *problem};
    }
    GlbBuilder b;
    json gltfMeshes = json::array(), nodes = json::array(), materials = json::array();
    json channels = json::array(), samplers = json::array();
    std::vector<float> timeValues(times.begin(), times.end());
    const int timeAccessor = b.floats(timeValues, "SCALAR", true, 0);
    const std::size_t targets = times.size() - 1;
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        const SequenceMesh& mesh = meshes[m];
        const sim::MatX3& base = mesh.frames.front();
        const sim::MatX3 baseNormals = vertexNormals(base, mesh.triangles);
        std::vector<std::uint32_t> index(static_cast<std::size_t>(mesh.triangles.size()));
        for (Eigen::Index f = 0; f < mesh.triangles.rows(); ++f) {
            for (int k = 0; k < 3; ++k) {
                index[static_cast<std::size_t>(3 * f + k)] =
                    static_cast<std::uint32_t>(mesh.triangles(f, k));
            }
        }
        json primitive = {
            {"attributes",
             {{"POSITION", b.floats(asFloats(base), "VEC3", true, ARRAY_BUFFER)},
              {"NORMAL", b.floats(asFloats(baseNormals), "VEC3", false, ARRAY_BUFFER)}}},
            {"indices", b.indices(index)},
            {"material", m},
            {"mode", 4}};
        json morphs = json::array();
        for (std::size_t k = 1; k < mesh.frames.size(); ++k) {
            const sim::MatX3 moved = mesh.frames[k] - base;
            const sim::MatX3 turned = vertexNormals(mesh.frames[k], mesh.triangles) - baseNormals;
            morphs.push_back({{"POSITION", b.floats(asFloats(moved), "VEC3", true, ARRAY_BUFFER)},
                              {"NORMAL", b.floats(asFloats(turned), "VEC3", false, ARRAY_BUFFER)}});
        }
        json gltfMesh = {{"name", mesh.name}, {"primitives", json::array({primitive})}};
        if (targets > 0) {
            gltfMesh["primitives"][0]["targets"] = morphs;
            gltfMesh["weights"] = std::vector<float>(targets, 0.0F);
            // Key k shows frame k: all weights 0 at the first, target k−1 alone after it.
            std::vector<float> weights(times.size() * targets, 0.0F);
            for (std::size_t k = 1; k < times.size(); ++k) {
                weights[k * targets + (k - 1)] = 1.0F;
            }
            samplers.push_back({{"input", timeAccessor},
                                {"output", b.floats(weights, "SCALAR", false, 0)},
                                {"interpolation", "LINEAR"}});
            channels.push_back(
                {{"sampler", samplers.size() - 1}, {"target", {{"node", m}, {"path", "weights"}}}});
        }
        gltfMeshes.push_back(std::move(gltfMesh));
        nodes.push_back({{"name", mesh.name}, {"mesh", m}});
        materials.push_back(
            {{"name", mesh.name},
             {"doubleSided", true},
             {"pbrMetallicRoughness",
              {{"baseColorFactor", {mesh.colour[0], mesh.colour[1], mesh.colour[2], 1.0}},
               {"metallicFactor", 0.0},
               {"roughnessFactor", 0.9}}}});
    }
    std::vector<int> sceneNodes(meshes.size());
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        sceneNodes[m] = static_cast<int>(m);
    }
    json gltf = {{"asset", {{"version", "2.0"}, {"generator", "Atelier"}}},
                 {"scene", 0},
                 {"scenes", json::array({{{"nodes", sceneNodes}}})},
                 {"nodes", nodes},
                 {"meshes", gltfMeshes},
                 {"materials", materials},
                 {"accessors", b.accessors},
                 {"bufferViews", b.views},
                 {"buffers", json::array({{{"byteLength", b.bin.size()}}})}};
    if (!channels.empty()) {
        gltf["animations"] =
            json::array({{{"name", "sequence"}, {"channels", channels}, {"samplers", samplers}}});
    }
    std::string text = gltf.dump();
    text.append((4 - text.size() % 4) % 4, ' ');
    std::string out;
    appendLittleEndian(out, GLB_MAGIC);
    appendLittleEndian(out, 2);
    appendLittleEndian(out, static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + b.bin.size()));
    appendLittleEndian(out, static_cast<std::uint32_t>(text.size()));
    appendLittleEndian(out, CHUNK_JSON);
    out += text;
    appendLittleEndian(out, static_cast<std::uint32_t>(b.bin.size()));
    appendLittleEndian(out, CHUNK_BIN);
    out += b.bin;
    return writeFileAtomically(path, out);
}

} // namespace atelier::io
