// `atelier-cli animate`: a skirt draped on the mannequin's mesh, then carried along as the
// body turns and steps sideways (given frame by frame, or as a skinned glTF animation); the
// sequence read back through assimp.
#include "app/cli_run.h"

#include "io/mesh_import.h"
#include "io/obj.h"
#include "io/skinned_gltf.h"
#include "io/temp_dir.h"

#include <assimp/Importer.hpp>
#include <assimp/scene.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

using namespace atelier;

namespace {

double meanX(const aiVector3D* v, unsigned n) {
    double sum = 0;
    for (unsigned i = 0; i < n; ++i) {
        sum += v[i].x;
    }
    return sum / n;
}

} // namespace

TEST(AnimateCli, TheSkirtFollowsTheBodyAndTheSequenceReadsBack) {
    const test::TempDir dir;
    ASSERT_EQ(test::runCli(dir, "body --out " + test::inQuotes(dir / "body.obj")).exitCode, 0);
    auto body = io::readObj(dir / "body.obj");
    ASSERT_TRUE(body.ok()) << body.error().toString();
    // Six frames at 30 per second: the body turns by up to 15° and steps 3 cm along x.
    std::filesystem::create_directories(dir / "walk");
    constexpr int frames = 6;
    for (int k = 0; k < frames; ++k) {
        const double s = static_cast<double>(k) / (frames - 1);
        const double a = 15.0 * std::numbers::pi / 180 * std::sin(std::numbers::pi * s);
        sim::MatX3 x = body.value().positions;
        for (Eigen::Index i = 0; i < x.rows(); ++i) {
            const double px = x(i, 0), pz = x(i, 2);
            x(i, 0) = std::cos(a) * px + std::sin(a) * pz + 0.03 * s;
            x(i, 2) = -std::sin(a) * px + std::cos(a) * pz;
        }
        std::ostringstream name;
        name << "walk/f" << k << ".obj";
        ASSERT_TRUE(io::writeObj(dir / name.str(), x, body.value().triangles).ok());
    }
    std::ifstream in(std::string(ATELIER_SOURCE_DIR) + "/assets/garments/skirt.atelier");
    nlohmann::json project = nlohmann::json::parse(in);
    project["body"] = {{"mesh", "walk/f0.obj"}};
    std::ofstream(dir / "skirt.atelier") << project.dump();

    const test::CliRun run = test::runCli(
        dir, "animate " + test::inQuotes(dir / "skirt.atelier") + " --body-frames " +
                 test::inQuotes(dir / "walk") + " --out " + test::inQuotes(dir / "seq.glb") +
                 " --report " + test::inQuotes(dir / "motion.json") + " --frames-dir " +
                 test::inQuotes(dir / "frames") + " --particle-distance 30 --time-limit 1.5");
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    const nlohmann::json report = nlohmann::json::parse(std::ifstream(dir / "motion.json"));
    EXPECT_EQ(report["frames"], frames);
    EXPECT_LT(report["max_penetration_m"].get<double>(), 0.002);
    EXPECT_EQ(report["max_intersecting_pairs"], 0);
    EXPECT_TRUE(std::filesystem::exists(dir / "frames/frame_00005.obj"));
    EXPECT_TRUE(std::filesystem::exists(dir / "frames/body_00005.obj"));

    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile((dir / "seq.glb").string(), 0);
    ASSERT_NE(scene, nullptr) << importer.GetErrorString();
    ASSERT_EQ(scene->mNumMeshes, 2u);
    const aiMesh* garment = scene->mMeshes[0];
    const aiMesh* bodyMesh = scene->mMeshes[1];
    ASSERT_EQ(garment->mNumAnimMeshes, static_cast<unsigned>(frames - 1));
    ASSERT_EQ(bodyMesh->mNumAnimMeshes, static_cast<unsigned>(frames - 1));
    ASSERT_EQ(scene->mNumAnimations, 1u);
    // The body stepped 3 cm; the skirt went with it (within a centimetre: it swings).
    const aiAnimMesh* lastBody = bodyMesh->mAnimMeshes[frames - 2];
    const aiAnimMesh* lastGarment = garment->mAnimMeshes[frames - 2];
    EXPECT_NEAR(meanX(lastBody->mVertices, bodyMesh->mNumVertices) -
                    meanX(bodyMesh->mVertices, bodyMesh->mNumVertices),
                0.03, 1e-4);
    EXPECT_NEAR(meanX(lastGarment->mVertices, garment->mNumVertices) -
                    meanX(garment->mVertices, garment->mNumVertices),
                0.03, 0.01);
}

TEST(AnimateCli, AMannequinProjectOrAForeignMeshIsRefusedBeforeAnyWork) {
    const test::TempDir dir;
    ASSERT_EQ(test::runCli(dir, "body --out " + test::inQuotes(dir / "body.obj")).exitCode, 0);
    std::filesystem::copy_file(dir / "body.obj", dir / "b1.obj");
    const std::string skirt = std::string(ATELIER_SOURCE_DIR) + "/assets/garments/skirt.atelier";
    const test::CliRun mannequin = test::runCli(
        dir, "animate " + test::inQuotes(skirt) + " --body-frames " +
                 test::inQuotes(dir / "body.obj") + " " + test::inQuotes(dir / "b1.obj") +
                 " --out " + test::inQuotes(dir / "seq.glb"));
    EXPECT_EQ(mannequin.exitCode, 2);
    EXPECT_NE(mannequin.stderrText.find("the body is the mannequin"), std::string::npos)
        << mannequin.stderrText;
    EXPECT_NE(mannequin.stderrText.find("/body"), std::string::npos);
    EXPECT_FALSE(std::filesystem::exists(dir / "seq.glb"));
}

TEST(AnimateCli, TheSkirtFollowsASkinnedGltfAnimation) {
    const test::TempDir dir;
    ASSERT_EQ(test::runCli(dir, "body --out " + test::inQuotes(dir / "body.obj")).exitCode, 0);
    auto body = io::readObj(dir / "body.obj");
    ASSERT_TRUE(body.ok()) << body.error().toString();
    // The mannequin on two joints: the root steps 3 cm along x over 1/6 s while the head
    // (joint 1, above 1.45 m) turns 20° about y.
    test::SkinnedGltfSpec spec;
    spec.positions = body.value().positions;
    spec.triangles = body.value().triangles;
    constexpr double NECK = 1.45;
    for (Eigen::Index i = 0; i < spec.positions.rows(); ++i) {
        spec.upperWeight.push_back(spec.positions(i, 1) > NECK ? 1.0 : 0.0);
    }
    spec.pivot = sim::Vec3(0, NECK, 0);
    const auto half = static_cast<float>(10.0 * std::numbers::pi / 180);
    const float end = 1.0F / 6;
    spec.animations.push_back(
        {"step",
         {{1, "translation", {0, end}, {0, 0, 0, 0.03F, 0, 0}},
          {2, "rotation", {0, end}, {0, 0, 0, 1, 0, std::sin(half), 0, std::cos(half)}}}});
    std::ofstream(dir / "step.gltf") << test::skinnedGltf(spec);
    std::ifstream in(std::string(ATELIER_SOURCE_DIR) + "/assets/garments/skirt.atelier");
    nlohmann::json project = nlohmann::json::parse(in);
    project["body"] = {{"mesh", "step.gltf"}};
    std::ofstream(dir / "skirt.atelier") << project.dump();

    const test::CliRun run = test::runCli(
        dir, "animate " + test::inQuotes(dir / "skirt.atelier") + " --body-animation " +
                 test::inQuotes(dir / "step.gltf") + " --animation step --fps 30 --out " +
                 test::inQuotes(dir / "seq.glb") + " --report " +
                 test::inQuotes(dir / "motion.json") + " --frames-dir " +
                 test::inQuotes(dir / "frames") + " --particle-distance 30 --time-limit 1.5");
    ASSERT_EQ(run.exitCode, 0) << run.stderrText;
    EXPECT_NE(run.stderrText.find("of animation 0 \"step\""), std::string::npos) << run.stderrText;
    const nlohmann::json report = nlohmann::json::parse(std::ifstream(dir / "motion.json"));
    EXPECT_EQ(report["frames"], 6); // 0 to 1/6 s at 30 per second
    EXPECT_LT(report["max_penetration_m"].get<double>(), 0.002);
    EXPECT_EQ(report["max_intersecting_pairs"], 0);
    // The drape rested on the animation's first frame, and the skirt went with the body.
    const auto garment0 = io::readObj(dir / "frames/frame_00000.obj");
    const auto garment5 = io::readObj(dir / "frames/frame_00005.obj");
    const auto body0 = io::readObj(dir / "frames/body_00000.obj");
    const auto body5 = io::readObj(dir / "frames/body_00005.obj");
    ASSERT_TRUE(garment0.ok() && garment5.ok() && body0.ok() && body5.ok());
    EXPECT_NEAR(body0.value().positions.col(0).mean(), spec.positions.col(0).mean(), 1e-6);
    EXPECT_NEAR(body5.value().positions.col(0).mean() - body0.value().positions.col(0).mean(), 0.03,
                1e-3); // the head's turn moves its mean a little
    EXPECT_NEAR(garment5.value().positions.col(0).mean() - garment0.value().positions.col(0).mean(),
                0.03, 0.01);
    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile((dir / "seq.glb").string(), 0);
    ASSERT_NE(scene, nullptr) << importer.GetErrorString();
    ASSERT_EQ(scene->mNumMeshes, 2U);
    EXPECT_EQ(scene->mMeshes[1]->mNumAnimMeshes, 5U);
}
