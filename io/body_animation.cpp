#include "io/body_animation.h"

#include "io/assimp_scene.h"

#include <Eigen/Geometry>
#include <assimp/anim.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unordered_map>
#include <utility>

namespace atelier::io {

namespace {

using Mat4 = Eigen::Matrix4d;

/// Ticks per second where an animation gives none (assimp's viewer assumes the same).
constexpr double DEFAULT_TICKS_PER_SECOND = 25.0;

std::string seconds(double value) {
    return detail::figure(value) + " s";
}

Mat4 toEigen(const aiMatrix4x4& m) {
    Mat4 out;
    out << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3,
        m.d4;
    return out;
}

std::string animationName(const aiAnimation& animation, unsigned index) {
    const std::string name = animation.mName.C_Str();
    return std::to_string(index) + " \"" + name + "\"";
}

double ticksPerSecond(const aiAnimation& animation) {
    return animation.mTicksPerSecond > 0 ? animation.mTicksPerSecond : DEFAULT_TICKS_PER_SECOND;
}

/// The file's animations as `0 "walk" (1.2 s), 1 "run" (0.8 s)`.
std::string animationList(const aiScene& scene) {
    std::string out;
    for (unsigned a = 0; a < scene.mNumAnimations; ++a) {
        const aiAnimation& animation = *scene.mAnimations[a];
        out += (out.empty() ? "" : ", ") + animationName(animation, a) + " (" +
               seconds(animation.mDuration / ticksPerSecond(animation)) + ")";
    }
    return out;
}

/// The animation `wanted` names (a name, else an index), or an error listing the file's.
Result<unsigned> pickAnimation(const aiScene& scene, const std::string& wanted,
                               const std::string& file) {
    const std::string holds = std::to_string(scene.mNumAnimations) +
                              (scene.mNumAnimations == 1 ? " animation: " : " animations: ") +
                              animationList(scene);
    if (wanted.empty()) {
        return 0U;
    }
    for (unsigned a = 0; a < scene.mNumAnimations; ++a) {
        if (wanted == scene.mAnimations[a]->mName.C_Str()) {
            return a;
        }
    }
    const bool digits =
        std::all_of(wanted.begin(), wanted.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (!digits || wanted.size() > 9) {
        return Error{file, "", "no animation is named \"" + wanted + "\"; the file holds " + holds};
    }
    const unsigned long index = std::stoul(wanted);
    if (index >= scene.mNumAnimations) {
        return Error{file, "",
                     "animation index " + wanted + " is out of range; the file holds " + holds};
    }
    return static_cast<unsigned>(index);
}

/// One node of the scene, in depth-first order (a parent before its children).
struct SceneNode {
    const aiNode* node = nullptr;
    int parent = -1;
    Mat4 local = Mat4::Identity();         ///< its own transform (when no channel moves it)
    const aiNodeAnim* channel = nullptr;   ///< the animation's channel of this node, if any
    Eigen::Vector3d restPosition{0, 0, 0}; ///< its transform decomposed: for missing keys
    Eigen::Quaterniond restRotation = Eigen::Quaterniond::Identity();
    Eigen::Vector3d restScale{1, 1, 1};
};

/// The value of keys (sorted by time) at `tick`: the first before the first key, the last after
/// the last, in between `mix(a, b, s)` of the two around it.
template <typename Key, typename Value, typename Convert, typename Mix>
Value sampleKeys(const Key* keys, unsigned count, double tick, Convert convert, Mix mix) {
    const Key* end = keys + count;
    const Key* after =
        std::upper_bound(keys, end, tick, [](double t, const Key& k) { return t < k.mTime; });
    if (after == keys) {
        return convert(keys[0].mValue);
    }
    if (after == end) {
        return convert(keys[count - 1].mValue);
    }
    const Key& a = *(after - 1);
    const Key& b = *after;
    const double span = b.mTime - a.mTime;
    const double s = span > 0 ? (tick - a.mTime) / span : 1.0;
    return mix(convert(a.mValue), convert(b.mValue), s);
}

Eigen::Vector3d vec(const aiVector3D& v) {
    return {v.x, v.y, v.z};
}
Eigen::Quaterniond quat(const aiQuaternion& q) {
    return Eigen::Quaterniond(q.w, q.x, q.y, q.z).normalized();
}

/// The node's local transform at `tick` from its channel.
Mat4 animatedLocal(const SceneNode& n, double tick) {
    const aiNodeAnim& c = *n.channel;
    const auto lerp = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b, double s) {
        return Eigen::Vector3d((1 - s) * a + s * b);
    };
    const auto slerp = [](const Eigen::Quaterniond& a, const Eigen::Quaterniond& b, double s) {
        return a.slerp(s, b);
    };
    const Eigen::Vector3d t = c.mNumPositionKeys > 0
                                  ? sampleKeys<aiVectorKey, Eigen::Vector3d>(
                                        c.mPositionKeys, c.mNumPositionKeys, tick, vec, lerp)
                                  : n.restPosition;
    const Eigen::Quaterniond r = c.mNumRotationKeys > 0
                                     ? sampleKeys<aiQuatKey, Eigen::Quaterniond>(
                                           c.mRotationKeys, c.mNumRotationKeys, tick, quat, slerp)
                                     : n.restRotation;
    const Eigen::Vector3d s = c.mNumScalingKeys > 0
                                  ? sampleKeys<aiVectorKey, Eigen::Vector3d>(
                                        c.mScalingKeys, c.mNumScalingKeys, tick, vec, lerp)
                                  : n.restScale;
    Mat4 m = Mat4::Identity();
    m.topLeftCorner<3, 3>() = r.normalized().toRotationMatrix() * s.asDiagonal();
    m.topRightCorner<3, 1>() = t;
    return m;
}

/// What is wrong with a channel's keys (a non-finite time or value, a zero rotation, times
/// going back), or an empty string.
std::string channelProblem(const aiNodeAnim& c) {
    const std::string node = std::string("node \"") + c.mNodeName.C_Str() + "\": ";
    const auto check = [&node](const auto* keys, unsigned count, const char* what,
                               auto finite) -> std::string {
        for (unsigned k = 0; k < count; ++k) {
            if (!std::isfinite(keys[k].mTime) || !finite(keys[k].mValue)) {
                return node + what + " key " + std::to_string(k) + " is not finite";
            }
            if (k > 0 && keys[k].mTime < keys[k - 1].mTime) {
                return node + what + " key " + std::to_string(k) +
                       " comes before the key before it";
            }
        }
        return {};
    };
    const auto finiteVector = [](const aiVector3D& v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    };
    const auto finiteRotation = [](const aiQuaternion& q) {
        const double norm2 =
            double(q.w) * q.w + double(q.x) * q.x + double(q.y) * q.y + double(q.z) * q.z;
        return std::isfinite(norm2) && norm2 > 1e-12;
    };
    for (std::string problem :
         {check(c.mPositionKeys, c.mNumPositionKeys, "position", finiteVector),
          check(c.mRotationKeys, c.mNumRotationKeys, "rotation", finiteRotation),
          check(c.mScalingKeys, c.mNumScalingKeys, "scale", finiteVector)}) {
        if (!problem.empty()) {
            return problem;
        }
    }
    return {};
}

/// One placed mesh: its vertices, and the bones that move them.
struct Instance {
    const aiMesh* mesh = nullptr;
    int node = -1; ///< the node carrying it
    struct Bone {
        int node = -1;
        Mat4 offset;
    };
    std::vector<Bone> bones;
};

/// The skinned positions of every instance at the given global transforms, appended in
/// instance order (file coordinates).
void pose(const std::vector<Instance>& instances, const std::vector<Mat4>& global,
          sim::MatX3& out) {
    Eigen::Index base = 0;
    for (const Instance& inst : instances) {
        const aiMesh& mesh = *inst.mesh;
        const auto n = static_cast<Eigen::Index>(mesh.mNumVertices);
        sim::MatX3 sum = sim::MatX3::Zero(n, 3);
        Eigen::VectorXd weight = Eigen::VectorXd::Zero(n);
        for (std::size_t b = 0; b < inst.bones.size(); ++b) {
            const Mat4 m =
                global[static_cast<std::size_t>(inst.bones[b].node)] * inst.bones[b].offset;
            const aiBone& bone = *mesh.mBones[b];
            for (unsigned w = 0; w < bone.mNumWeights; ++w) {
                const aiVertexWeight& vw = bone.mWeights[w];
                const aiVector3D& p = mesh.mVertices[vw.mVertexId];
                const Eigen::Vector3d q = m.topLeftCorner<3, 3>() * Eigen::Vector3d(p.x, p.y, p.z) +
                                          m.topRightCorner<3, 1>();
                sum.row(vw.mVertexId) += vw.mWeight * q.transpose();
                weight[vw.mVertexId] += vw.mWeight;
            }
        }
        const Mat4& own = global[static_cast<std::size_t>(inst.node)];
        for (Eigen::Index v = 0; v < n; ++v) {
            if (weight[v] > 1e-9) {
                out.row(base + v) = sum.row(v) / weight[v];
            } else {
                const aiVector3D& p = mesh.mVertices[v];
                out.row(base + v) = (own.topLeftCorner<3, 3>() * Eigen::Vector3d(p.x, p.y, p.z) +
                                     own.topRightCorner<3, 1>())
                                        .transpose();
            }
        }
        base += n;
    }
}

} // namespace

Result<BodyMotion> importBodyAnimation(const std::filesystem::path& path,
                                       const BodyAnimationOptions& options, const Limits& limits) {
    const std::string file = path.string();
    const auto fail = [&file](std::string message) { return Error{file, "", std::move(message)}; };
    if (!(options.fps > 0 && options.fps <= limits.maxFrameRate)) {
        return fail("the sampling rate must be above 0 and at most " +
                    std::to_string(static_cast<long long>(limits.maxFrameRate)) +
                    " frames per second (the limit frame-rate)");
    }
    auto read = detail::readAssimpScene(path, limits.maxMeshBytes, limits.maxJsonDepth);
    if (!read.ok()) {
        return read.error();
    }
    const aiScene& scene = *read.value().scene;
    if (scene.mNumAnimations == 0 || scene.mAnimations == nullptr) {
        return fail("the file holds no animation (a skinned, animated body is needed; a body "
                    "exported frame by frame is read as a mesh sequence)");
    }
    auto picked = pickAnimation(scene, options.animation, file);
    if (!picked.ok()) {
        return picked.error();
    }
    const aiAnimation& animation = *scene.mAnimations[picked.value()];
    const std::string name = animationName(animation, picked.value());
    const auto failIn = [&](const std::string& message) {
        return fail("animation " + name + ": " + message);
    };
    const double tps = ticksPerSecond(animation);
    if (!std::isfinite(animation.mTicksPerSecond) || !std::isfinite(animation.mDuration) ||
        !std::isfinite(tps)) {
        return failIn("its duration or ticks per second is not finite");
    }
    const double length = animation.mDuration / tps;
    if (!(length > 0)) {
        return failIn("it lasts " + seconds(length) + ": there is no motion to sample");
    }

    // The nodes, depth first with an explicit stack (a deep tree cannot overflow ours).
    std::vector<SceneNode> nodes;
    std::unordered_map<std::string, int> byName;
    if (scene.mRootNode == nullptr) {
        return fail("the file holds no node");
    }
    std::vector<std::pair<const aiNode*, int>> stack{{scene.mRootNode, -1}};
    while (!stack.empty()) {
        const auto [node, parent] = stack.back();
        stack.pop_back();
        SceneNode n;
        n.node = node;
        n.parent = parent;
        n.local = toEigen(node->mTransformation);
        if (!n.local.allFinite()) {
            return fail(std::string("node \"") + node->mName.C_Str() +
                        "\": its transform is not finite");
        }
        aiVector3D scale, position;
        aiQuaternion rotation;
        node->mTransformation.Decompose(scale, rotation, position);
        n.restPosition = vec(position);
        n.restScale = vec(scale);
        n.restRotation = Eigen::Quaterniond(rotation.w, rotation.x, rotation.y, rotation.z);
        const int index = static_cast<int>(nodes.size());
        byName.emplace(node->mName.C_Str(), index);
        nodes.push_back(n);
        for (unsigned c = node->mNumChildren; c-- > 0;) {
            if (node->mChildren[c] != nullptr) {
                stack.emplace_back(node->mChildren[c], index);
            }
        }
    }
    for (unsigned c = 0; c < animation.mNumChannels; ++c) {
        const aiNodeAnim& channel = *animation.mChannels[c];
        if (std::string problem = channelProblem(channel); !problem.empty()) {
            return failIn(problem);
        }
        const auto it = byName.find(channel.mNodeName.C_Str());
        if (it != byName.end()) {
            nodes[static_cast<std::size_t>(it->second)].channel = &channel;
        }
    }

    // Whether the animation moves each node: a channel on it or on an ancestor.
    std::vector<char> moved(nodes.size(), 0);
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const int parent = nodes[i].parent;
        moved[i] = static_cast<char>(nodes[i].channel != nullptr ||
                                     (parent >= 0 && moved[static_cast<std::size_t>(parent)] != 0));
    }

    // The mesh instances and their bones; whether the animation moves the body.
    std::vector<Instance> instances;
    std::vector<std::array<int, 3>> triangles;
    long long vertexCount = 0;
    bool skinned = false;
    bool bodyMoves = false;
    for (std::size_t i = 0; i < nodes.size(); ++i) {
        const aiNode& node = *nodes[i].node;
        for (unsigned m = 0; m < node.mNumMeshes; ++m) {
            if (node.mMeshes[m] >= scene.mNumMeshes) {
                return fail("a node names a mesh the file does not hold");
            }
            Instance inst;
            inst.mesh = scene.mMeshes[node.mMeshes[m]];
            inst.node = static_cast<int>(i);
            if (vertexCount + inst.mesh->mNumVertices > limits.maxBodyVertices) {
                return fail("more than " + std::to_string(limits.maxBodyVertices) +
                            " vertices (the limit body-vertices)");
            }
            for (unsigned b = 0; b < inst.mesh->mNumBones; ++b) {
                const aiBone& bone = *inst.mesh->mBones[b];
                const auto it = byName.find(bone.mName.C_Str());
                if (it == byName.end()) {
                    return fail(std::string("bone \"") + bone.mName.C_Str() +
                                "\" names no node of the file");
                }
                Instance::Bone out{it->second, toEigen(bone.mOffsetMatrix)};
                if (!out.offset.allFinite()) {
                    return fail(std::string("bone \"") + bone.mName.C_Str() +
                                "\": its offset (inverse bind) matrix is not finite");
                }
                for (unsigned w = 0; w < bone.mNumWeights; ++w) {
                    if (!std::isfinite(bone.mWeights[w].mWeight) ||
                        bone.mWeights[w].mVertexId >= inst.mesh->mNumVertices) {
                        return fail(std::string("bone \"") + bone.mName.C_Str() + "\": weight " +
                                    std::to_string(w) +
                                    " is not finite or names a vertex the mesh does not hold");
                    }
                }
                inst.bones.push_back(out);
                skinned = true;
                bodyMoves = bodyMoves || moved[static_cast<std::size_t>(it->second)] != 0;
            }
            // A mesh without bones follows its node.
            bodyMoves = bodyMoves || (inst.bones.empty() && moved[i] != 0);
            if (auto added = detail::appendTriangles(*inst.mesh, static_cast<int>(vertexCount),
                                                     file, triangles);
                !added.ok()) {
                return added.error();
            }
            vertexCount += inst.mesh->mNumVertices;
            instances.push_back(std::move(inst));
        }
    }
    if (!bodyMoves) {
        return failIn(skinned ? "the animation moves none of the skin's bones: it does not move "
                                "the body"
                              : "no mesh has a skin (bones), and the animation moves no node "
                                "that carries a mesh: it does not move the body");
    }

    // The window and its frames.
    const double window = options.duration < 0 ? length - options.start : options.duration;
    if (!(options.start >= 0 && options.start < length)) {
        return failIn("the window starts at " + seconds(options.start) +
                      ", outside the animation (0 to " + seconds(length) + ")");
    }
    if (!(window > 0) || options.start + window > length * (1 + 1e-9)) {
        return failIn("the window " + seconds(options.start) + " + " + seconds(window) +
                      " is empty or passes the animation's end (" + seconds(length) + ")");
    }
    const double frameCount = std::floor(window * options.fps + 1e-9) + 1;
    if (frameCount < 2) {
        return failIn("at " + detail::figure(options.fps) + " frames per second the window of " +
                      seconds(window) + " holds one frame; a motion needs at least two");
    }
    if (frameCount > static_cast<double>(limits.maxFrames)) {
        return failIn(detail::figure(frameCount) + " frames are more than " +
                      std::to_string(limits.maxFrames) + " (the limit frames)");
    }
    if (frameCount * static_cast<double>(vertexCount) >
        static_cast<double>(limits.maxBodyVertices)) {
        return failIn(std::to_string(static_cast<long long>(frameCount)) + " frames of " +
                      std::to_string(vertexCount) + " vertices are more than " +
                      std::to_string(limits.maxBodyVertices) +
                      " vertices in all (the limit body-vertices)");
    }
    const auto frames = static_cast<std::size_t>(frameCount);

    BodyMotion motion;
    motion.animation = name;
    std::vector<Mat4> global(nodes.size());
    sim::MatX3 x(vertexCount, 3);
    for (std::size_t k = 0; k < frames; ++k) {
        const double t = options.start + static_cast<double>(k) / options.fps;
        const double tick = std::min(t, length) * tps;
        for (std::size_t i = 0; i < nodes.size(); ++i) {
            const SceneNode& n = nodes[i];
            const Mat4 local = n.channel != nullptr ? animatedLocal(n, tick) : n.local;
            global[i] =
                n.parent < 0 ? local : Mat4(global[static_cast<std::size_t>(n.parent)] * local);
        }
        pose(instances, global, x);
        if (!x.allFinite()) {
            return failIn("at " + seconds(t) + " the posed body is not finite");
        }
        if (k == 0) {
            RawMesh raw;
            raw.positions = x;
            raw.triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
            for (std::size_t f = 0; f < triangles.size(); ++f) {
                for (int c = 0; c < 3; ++c) {
                    raw.triangles(static_cast<Eigen::Index>(f), c) =
                        triangles[f][static_cast<std::size_t>(c)];
                }
            }
            raw.format = read.value().format;
            raw.metadataUp = read.value().metadataUp;
            auto first = normaliseBody(raw, file, options.import, limits);
            if (!first.ok()) {
                return first.error();
            }
            motion.first = std::move(first).value();
        }
        auto placed = placeAsFirstFrame(x, motion.first, file, limits);
        if (!placed.ok()) {
            return fail("animation " + name + " at " + seconds(t) + ": " + placed.error().message);
        }
        motion.frames.push_back(std::move(placed).value());
        motion.files.push_back(file);
    }
    std::vector<std::string>& warnings = motion.first.report.warnings;
    if (scene.mNumAnimations > 1) {
        warnings.push_back("the file holds " + std::to_string(scene.mNumAnimations) +
                           " animations (" + animationList(scene) + "); sampled " + name);
    }
    if (animation.mNumMorphMeshChannels > 0 || animation.mNumMeshChannels > 0) {
        warnings.push_back("animation " + name +
                           ": its morph-target (blend shape) channels are not applied");
    }
    return motion;
}

} // namespace atelier::io
