#pragma once
/// A skinned, animated glTF 2.0 file written by the tests themselves (JSON with its buffer as
/// a base64 data: URI): a mesh on a two-joint skeleton, `root` (joint 0, at the origin) and
/// its child `upper` (joint 1, at `pivot`), and node animations of those joints.

#include "sim/core/types.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace atelier::test {

/// One channel: a node's translation (3 values per key) or rotation (x, y, z, w per key).
struct GltfChannel {
    int node = 1;                  ///< 1 = root, 2 = upper (node 0 carries the mesh)
    std::string path = "rotation"; ///< "translation" or "rotation"
    std::vector<float> times;      ///< [s]
    std::vector<float> values;     ///< 3 or 4 per key
    std::string interpolation = "LINEAR";
};

struct GltfAnimationSpec {
    std::string name;
    std::vector<GltfChannel> channels;
};

struct SkinnedGltfSpec {
    sim::MatX3 positions;  ///< (|V|×3) [m], the bind pose
    sim::MatX3i triangles; ///< (|F|×3)
    /// Per vertex, the weight of joint 1 (joint 0 has the rest); empty = the mesh has no skin.
    std::vector<double> upperWeight;
    sim::Vec3 pivot{0, 0, 0};         ///< joint 1's place, relative to joint 0 [m]
    sim::Vec3 meshNodeShift{0, 0, 0}; ///< the mesh node's translation (ignored when skinned)
    std::vector<GltfAnimationSpec> animations;
};

namespace detail {

inline std::string base64(const std::string& bytes) {
    static const char* const digits =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    std::size_t i = 0;
    for (; i + 2 < bytes.size(); i += 3) {
        const auto n = (std::uint32_t(std::uint8_t(bytes[i])) << 16) |
                       (std::uint32_t(std::uint8_t(bytes[i + 1])) << 8) |
                       std::uint32_t(std::uint8_t(bytes[i + 2]));
        for (int k = 3; k >= 0; --k) {
            out += digits[(n >> (6 * k)) & 63];
        }
    }
    if (i < bytes.size()) {
        std::uint32_t n = std::uint32_t(std::uint8_t(bytes[i])) << 16;
        if (i + 1 < bytes.size()) {
            n |= std::uint32_t(std::uint8_t(bytes[i + 1])) << 8;
        }
        out += digits[(n >> 18) & 63];
        out += digits[(n >> 12) & 63];
        out += i + 1 < bytes.size() ? digits[(n >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

/// The buffer and its views and accessors, built array by array.
struct GltfBuffer {
    std::string bytes;
    nlohmann::json views = nlohmann::json::array();
    nlohmann::json accessors = nlohmann::json::array();

    template <typename T>
    int add(const std::vector<T>& data, int componentType, const std::string& type, int count,
            nlohmann::json extra = nlohmann::json::object()) {
        const std::size_t offset = bytes.size();
        bytes.resize(offset + data.size() * sizeof(T));
        std::memcpy(bytes.data() + offset, data.data(), data.size() * sizeof(T));
        while (bytes.size() % 4 != 0) {
            bytes.push_back('\0');
        }
        views.push_back(
            {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", data.size() * sizeof(T)}});
        nlohmann::json accessor = {{"bufferView", static_cast<int>(views.size()) - 1},
                                   {"componentType", componentType},
                                   {"count", count},
                                   {"type", type}};
        accessor.update(extra);
        accessors.push_back(accessor);
        return static_cast<int>(accessors.size()) - 1;
    }
};

} // namespace detail

/// The .gltf text of the spec.
inline std::string skinnedGltf(const SkinnedGltfSpec& spec) {
    constexpr int FLOAT = 5126, UINT32 = 5125, UINT16 = 5123;
    detail::GltfBuffer buf;
    const auto n = static_cast<int>(spec.positions.rows());
    std::vector<float> positions;
    for (int i = 0; i < n; ++i) {
        for (int k = 0; k < 3; ++k) {
            positions.push_back(static_cast<float>(spec.positions(i, k)));
        }
    }
    const sim::Vec3 lo = spec.positions.colwise().minCoeff();
    const sim::Vec3 hi = spec.positions.colwise().maxCoeff();
    const int position = buf.add(positions, FLOAT, "VEC3", n,
                                 {{"min", {float(lo.x()), float(lo.y()), float(lo.z())}},
                                  {"max", {float(hi.x()), float(hi.y()), float(hi.z())}}});
    std::vector<std::uint32_t> indices;
    for (Eigen::Index f = 0; f < spec.triangles.rows(); ++f) {
        for (int k = 0; k < 3; ++k) {
            indices.push_back(static_cast<std::uint32_t>(spec.triangles(f, k)));
        }
    }
    const int index = buf.add(indices, UINT32, "SCALAR", static_cast<int>(indices.size()));
    nlohmann::json primitive = {{"attributes", {{"POSITION", position}}}, {"indices", index}};
    nlohmann::json meshNode = {
        {"name", "body"},
        {"mesh", 0},
        {"translation", {spec.meshNodeShift.x(), spec.meshNodeShift.y(), spec.meshNodeShift.z()}}};
    nlohmann::json gltf = {{"asset", {{"version", "2.0"}, {"generator", "atelier tests"}}},
                           {"scene", 0}};
    if (!spec.upperWeight.empty()) {
        std::vector<std::uint16_t> joints;
        std::vector<float> weights;
        for (int i = 0; i < n; ++i) {
            joints.insert(joints.end(), {0, 1, 0, 0});
            const auto w = static_cast<float>(spec.upperWeight[static_cast<std::size_t>(i)]);
            weights.insert(weights.end(), {1.0F - w, w, 0.0F, 0.0F});
        }
        primitive["attributes"]["JOINTS_0"] = buf.add(joints, UINT16, "VEC4", n);
        primitive["attributes"]["WEIGHTS_0"] = buf.add(weights, FLOAT, "VEC4", n);
        // Column-major inverse bind matrices: identity for root, a translation by −pivot for
        // upper (both joints unrotated at bind time).
        std::vector<float> inverseBind = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0,
                                          0, 1, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};
        for (int k = 0; k < 3; ++k) {
            inverseBind.push_back(-static_cast<float>(spec.pivot[k]));
        }
        inverseBind.push_back(1);
        gltf["skins"] = {{{"joints", {1, 2}},
                          {"skeleton", 1},
                          {"inverseBindMatrices", buf.add(inverseBind, FLOAT, "MAT4", 2)}}};
        meshNode["skin"] = 0;
    }
    gltf["meshes"] = {{{"name", "body"}, {"primitives", {primitive}}}};
    gltf["nodes"] = {
        meshNode,
        {{"name", "root"}, {"children", {2}}},
        {{"name", "upper"}, {"translation", {spec.pivot.x(), spec.pivot.y(), spec.pivot.z()}}}};
    gltf["scenes"] = {{{"nodes", {0, 1}}}};
    nlohmann::json animations = nlohmann::json::array();
    for (const GltfAnimationSpec& a : spec.animations) {
        nlohmann::json channels = nlohmann::json::array();
        nlohmann::json samplers = nlohmann::json::array();
        for (const GltfChannel& c : a.channels) {
            const auto keys = static_cast<int>(c.times.size());
            float first = c.times.front(), last = c.times.front();
            for (const float t : c.times) {
                first = std::min(first, t);
                last = std::max(last, t);
            }
            const int input =
                buf.add(c.times, FLOAT, "SCALAR", keys, {{"min", {first}}, {"max", {last}}});
            const int output =
                buf.add(c.values, FLOAT, c.path == "rotation" ? "VEC4" : "VEC3", keys);
            samplers.push_back(
                {{"input", input}, {"output", output}, {"interpolation", c.interpolation}});
            channels.push_back({{"sampler", static_cast<int>(samplers.size()) - 1},
                                {"target", {{"node", c.node}, {"path", c.path}}}});
        }
        animations.push_back({{"name", a.name}, {"channels", channels}, {"samplers", samplers}});
    }
    if (!animations.empty()) {
        gltf["animations"] = animations;
    }
    gltf["accessors"] = buf.accessors;
    gltf["bufferViews"] = buf.views;
    gltf["buffers"] = {
        {{"byteLength", buf.bytes.size()},
         {"uri", "data:application/octet-stream;base64," + detail::base64(buf.bytes)}}};
    return gltf.dump();
}

} // namespace atelier::test
