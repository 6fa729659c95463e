#include "io/body_animation.h"
#include "io/skinned_gltf.h"
#include "io/temp_dir.h"

#include <assimp/Importer.hpp>
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <utility>

using namespace atelier;

namespace {

constexpr double PIVOT = 0.85;    // joint 1's height [m]
constexpr double BEND_DEG = 30.0; // joint 1's rotation about z over the 1 s of "bend"
constexpr double SHIFT = 0.1;     // root's translation along x over the 1 s of "bend" [m]

/// A closed prism 0.4 × 1.7 × 0.25 m standing on y = 0, in three rings of four vertices
/// (y = 0, 0.85, 1.7) whose weights on joint 1 are 0, ½ and 1.
test::SkinnedGltfSpec prism() {
    test::SkinnedGltfSpec spec;
    spec.positions.resize(12, 3);
    const double corners[4][2] = {{-0.2, -0.125}, {0.2, -0.125}, {0.2, 0.125}, {-0.2, 0.125}};
    for (int r = 0; r < 3; ++r) {
        for (int j = 0; j < 4; ++j) {
            spec.positions.row(4 * r + j) << corners[j][0], PIVOT * r, corners[j][1];
            spec.upperWeight.push_back(0.5 * r);
        }
    }
    spec.triangles.resize(20, 3);
    int f = 0;
    for (int r = 0; r < 2; ++r) {
        for (int j = 0; j < 4; ++j) {
            const int a = 4 * r + j, b = 4 * r + (j + 1) % 4;
            spec.triangles.row(f++) << a, b, b + 4;
            spec.triangles.row(f++) << a, b + 4, a + 4;
        }
    }
    spec.triangles.row(f++) << 0, 2, 1;
    spec.triangles.row(f++) << 0, 3, 2;
    spec.triangles.row(f++) << 8, 9, 10;
    spec.triangles.row(f++) << 8, 10, 11;
    spec.pivot = sim::Vec3(0, PIVOT, 0);
    // glTF ignores a skinned mesh node's transform: this shift must not show.
    spec.meshNodeShift = sim::Vec3(5, 0, 0);
    const auto half = static_cast<float>(BEND_DEG / 2 * std::numbers::pi / 180);
    spec.animations.push_back(
        {"bend",
         {{2, "rotation", {0, 1}, {0, 0, 0, 1, 0, 0, std::sin(half), std::cos(half)}},
          {1, "translation", {0, 1}, {0, 0, 0, static_cast<float>(SHIFT), 0, 0}}}});
    spec.animations.push_back({"sway", {{1, "translation", {0, 0.5F}, {0, 0, 0, 0, 0, 0.05F}}}});
    return spec;
}

/// Where "bend" puts bind-pose point p of weight w on joint 1 at time t: the blend of
/// root(t)·p and root(t)·T(pivot)·Rz(θ(t))·T(−pivot)·p.
sim::Vec3 bent(const sim::Vec3& p, double w, double t) {
    const double a = BEND_DEG * std::numbers::pi / 180 * t;
    const sim::Vec3 root(SHIFT * t, 0, 0);
    const sim::Vec3 q = p - sim::Vec3(0, PIVOT, 0);
    const sim::Vec3 turned(std::cos(a) * q.x() - std::sin(a) * q.y(),
                           std::sin(a) * q.x() + std::cos(a) * q.y(), q.z());
    return (1 - w) * (p + root) + w * (root + sim::Vec3(0, PIVOT, 0) + turned);
}

/// Each source vertex's place at frame k against the analytical skinning at time t.
void expectFrame(const io::BodyMotion& m, const test::SkinnedGltfSpec& spec, std::size_t k,
                 double t) {
    ASSERT_LT(k, m.frames.size());
    for (Eigen::Index i = 0; i < spec.positions.rows(); ++i) {
        const int v = m.first.fromSource[static_cast<std::size_t>(i)];
        ASSERT_GE(v, 0);
        const sim::Vec3 want = bent(spec.positions.row(i).transpose(),
                                    spec.upperWeight[static_cast<std::size_t>(i)], t);
        const sim::Vec3 got = m.frames[k].row(v).transpose();
        EXPECT_LT((got - want).norm(), 1e-6) << "vertex " << i << " at t = " << t << ": "
                                             << got.transpose() << " against " << want.transpose();
    }
}

std::string errorOf(const std::filesystem::path& file, const io::BodyAnimationOptions& options,
                    const io::Limits& limits = {}) {
    auto motion = io::importBodyAnimation(file, options, limits);
    EXPECT_FALSE(motion.ok());
    if (motion.ok()) {
        return {};
    }
    const std::string text = motion.error().toString();
    EXPECT_NE(text.find(file.string()), std::string::npos) << text;
    return text;
}

} // namespace

TEST(BodyAnimation, SampledFramesAreTheAnalyticalSkinning) {
    const test::TempDir dir;
    const test::SkinnedGltfSpec spec = prism();
    const auto file = dir.write("bend.gltf", test::skinnedGltf(spec));
    io::BodyAnimationOptions options;
    options.fps = 10;
    options.animation = "bend";
    auto motion = io::importBodyAnimation(file, options);
    ASSERT_TRUE(motion.ok()) << motion.error().toString();
    const io::BodyMotion& m = motion.value();
    EXPECT_EQ(m.animation, "0 \"bend\"");
    ASSERT_EQ(m.frames.size(), 11U); // 0, 0.1, ..., 1 s
    EXPECT_EQ(m.files.size(), 11U);
    EXPECT_EQ(m.first.report.units, io::LengthUnit::Metre);
    EXPECT_EQ(m.first.report.up, io::UpAxis::Y);
    EXPECT_EQ(m.first.vertices.rows(), 12);
    EXPECT_EQ(m.first.triangles.rows(), 20);
    EXPECT_NEAR(m.first.floorOffset, 0.0, 1e-7);
    EXPECT_EQ(m.first.report.holes, 0);
    using Sample = std::pair<std::size_t, double>; // frame, time [s]
    for (const auto& [k, t] : {Sample{0, 0.0}, Sample{3, 0.3}, Sample{5, 0.5}, Sample{10, 1.0}}) {
        expectFrame(m, spec, k, t);
    }
    EXPECT_LT((m.frames[0] - m.first.vertices).cwiseAbs().maxCoeff(), 1e-12);

    // A window of the animation: 0.25 s to 0.75 s at 4 frames per second.
    options.fps = 4;
    options.start = 0.25;
    options.duration = 0.5;
    auto window = io::importBodyAnimation(file, options);
    ASSERT_TRUE(window.ok()) << window.error().toString();
    ASSERT_EQ(window.value().frames.size(), 3U);
    for (const auto& [k, t] : {Sample{0, 0.25}, Sample{1, 0.5}, Sample{2, 0.75}}) {
        expectFrame(window.value(), spec, k, t);
    }
}

TEST(BodyAnimation, AssimpGivesGltfTimesInMillisecondsAndTheInverseBindMatricesAsOffsets) {
    // The conventions importBodyAnimation relies on (docs/decisions/027-skinned-bodies.md).
    const test::TempDir dir;
    const auto file = dir.write("bend.gltf", test::skinnedGltf(prism()));
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(file.string(), 0);
    ASSERT_NE(scene, nullptr) << importer.GetErrorString();
    ASSERT_EQ(scene->mNumAnimations, 2U);
    EXPECT_DOUBLE_EQ(scene->mAnimations[0]->mTicksPerSecond, 1000.0);
    EXPECT_DOUBLE_EQ(scene->mAnimations[0]->mDuration, 1000.0);
    ASSERT_EQ(scene->mNumMeshes, 1U);
    const aiMesh* mesh = scene->mMeshes[0];
    ASSERT_EQ(mesh->mNumBones, 2U);
    EXPECT_STREQ(mesh->mBones[1]->mName.C_Str(), "upper");
    EXPECT_FLOAT_EQ(mesh->mBones[1]->mOffsetMatrix.b4, -static_cast<float>(PIVOT));
}

TEST(BodyAnimation, PicksTheAnimationByNameOrIndexAndListsThem) {
    const test::TempDir dir;
    const auto file = dir.write("two.gltf", test::skinnedGltf(prism()));
    io::BodyAnimationOptions options;
    options.fps = 10;
    auto first = io::importBodyAnimation(file, options);
    ASSERT_TRUE(first.ok()) << first.error().toString();
    EXPECT_EQ(first.value().frames.size(), 11U);
    ASSERT_FALSE(first.value().first.report.warnings.empty());
    EXPECT_NE(first.value().first.report.warnings.front().find("1 \"sway\" (0.5 s)"),
              std::string::npos)
        << first.value().first.report.warnings.front();
    for (const char* pick : {"sway", "1"}) {
        options.animation = pick;
        auto sway = io::importBodyAnimation(file, options);
        ASSERT_TRUE(sway.ok()) << sway.error().toString();
        EXPECT_EQ(sway.value().animation, "1 \"sway\"");
        ASSERT_EQ(sway.value().frames.size(), 6U);
        // The root slid 5 cm along z; nothing bent.
        const sim::MatX3 moved = sway.value().frames[5] - sway.value().frames[0];
        EXPECT_NEAR(moved.col(2).minCoeff(), 0.05, 1e-6);
        EXPECT_NEAR(moved.col(2).maxCoeff(), 0.05, 1e-6);
        EXPECT_LT(moved.leftCols<2>().cwiseAbs().maxCoeff(), 1e-6);
    }
    options.animation = "2";
    const std::string outOfRange = errorOf(file, options);
    EXPECT_NE(outOfRange.find("index 2 is out of range"), std::string::npos) << outOfRange;
    EXPECT_NE(outOfRange.find("0 \"bend\" (1 s), 1 \"sway\" (0.5 s)"), std::string::npos)
        << outOfRange;
    options.animation = "walk";
    const std::string unknown = errorOf(file, options);
    EXPECT_NE(unknown.find("no animation is named \"walk\""), std::string::npos) << unknown;
    EXPECT_NE(unknown.find("\"sway\""), std::string::npos) << unknown;
}

TEST(BodyAnimation, BadAnimationsAreRefusedNamingTheFileAndTheProblem) {
    const test::TempDir dir;
    io::BodyAnimationOptions options;
    options.fps = 10;

    test::SkinnedGltfSpec still = prism();
    still.animations.clear();
    EXPECT_NE(errorOf(dir.write("still.gltf", test::skinnedGltf(still)), options)
                  .find("holds no animation"),
              std::string::npos);

    test::SkinnedGltfSpec unskinned = prism();
    unskinned.upperWeight.clear();
    EXPECT_NE(errorOf(dir.write("unskinned.gltf", test::skinnedGltf(unskinned)), options)
                  .find("no mesh has a skin"),
              std::string::npos);

    test::SkinnedGltfSpec instant = prism();
    instant.animations = {{"instant", {{2, "rotation", {0}, {0, 0, 0.2F, 0.98F}}}}};
    EXPECT_NE(
        errorOf(dir.write("instant.gltf", test::skinnedGltf(instant)), options).find("lasts 0 s"),
        std::string::npos);

    test::SkinnedGltfSpec broken = prism();
    broken.animations[0].channels[0].values[6] = std::numeric_limits<float>::quiet_NaN();
    const std::string nan = errorOf(dir.write("nan.gltf", test::skinnedGltf(broken)), options);
    EXPECT_NE(nan.find("node \"upper\": rotation key 1 is not finite"), std::string::npos) << nan;

    // assimp's recursive JSON parser would overflow the stack on a deep enough nesting.
    const std::string deep = "{\"asset\": " + std::string(300, '[') + std::string(300, ']') + "}";
    EXPECT_NE(errorOf(dir.write("deep.gltf", deep), options).find("nested deeper than 256"),
              std::string::npos);

    const auto bend = dir.write("bend.gltf", test::skinnedGltf(prism()));
    io::Limits few;
    few.maxFrames = 5;
    const std::string many = errorOf(bend, options, few);
    EXPECT_NE(many.find("11 frames are more than 5 (the limit frames)"), std::string::npos) << many;
    options.start = 0.9;
    options.duration = 0.5;
    EXPECT_NE(errorOf(bend, options).find("passes the animation's end"), std::string::npos);
    options.duration = 0.05;
    EXPECT_NE(errorOf(bend, options).find("a motion needs at least two"), std::string::npos);
}

TEST(BodyAnimation, BlendersFbxAndColladaExportsOfThePrismAreTheAnalyticalSkinning) {
    // The prism and its "bend", rigged, animated and exported by Blender 3.4's own FBX (binary)
    // and COLLADA exporters (tests/io/data/skins/make_skins.py makes them): files another tool
    // wrote, with its axes, units, bone frames and baked keys (24 a second).
    const test::SkinnedGltfSpec spec = prism();
    for (const char* name : {"bend.fbx", "bend.dae"}) {
        SCOPED_TRACE(name);
        const std::filesystem::path file =
            std::filesystem::path(ATELIER_SOURCE_DIR) / "tests/io/data/skins" / name;
        io::BodyAnimationOptions options;
        options.fps = 10;
        auto motion = io::importBodyAnimation(file, options);
        ASSERT_TRUE(motion.ok()) << motion.error().toString();
        const io::BodyMotion& m = motion.value();
        ASSERT_EQ(m.frames.size(), 11U); // 0, 0.1, ..., 1 s
        EXPECT_EQ(m.first.report.up, io::UpAxis::Y);
        ASSERT_EQ(m.first.vertices.rows(), 12) << "the prism's corners, welded";
        // Each imported vertex is the prism corner it stands on in the first frame.
        for (Eigen::Index v = 0; v < m.first.vertices.rows(); ++v) {
            Eigen::Index corner = 0;
            const double gap =
                (spec.positions.rowwise() - m.frames[0].row(v)).rowwise().norm().minCoeff(&corner);
            ASSERT_LT(gap, 1e-5) << "vertex " << v << " at " << m.frames[0].row(v);
            for (const std::size_t k : {3U, 5U, 10U}) {
                const double t = 0.1 * static_cast<double>(k);
                const sim::Vec3 want = bent(spec.positions.row(corner).transpose(),
                                            spec.upperWeight[static_cast<std::size_t>(corner)], t);
                EXPECT_LT((m.frames[k].row(v).transpose() - want).norm(), 1e-5)
                    << "corner " << corner << " at t = " << t << ": " << m.frames[k].row(v)
                    << " against " << want.transpose();
            }
        }
    }
}
