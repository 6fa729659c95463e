#include "io/gltf_animation.h"
#include "io/temp_dir.h"

#include <assimp/Importer.hpp>
#include <assimp/anim.h>
#include <assimp/scene.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace atelier;

namespace {

/// A square of two triangles, lifted by `lift` and pushed along x by `shift` [m].
sim::MatX3 square(double lift, double shift) {
    sim::MatX3 x(4, 3);
    x << 0, 0, 0, 1, 0, 0, 1, 0, 1, 0, 0, 1;
    x.col(1).array() += lift;
    x.col(0).array() += shift;
    return x;
}

sim::MatX3i squareTriangles() {
    sim::MatX3i t(2, 3);
    t << 0, 2, 1, 0, 3, 2;
    return t;
}

} // namespace

TEST(GltfSequence, AssimpReadsTheMorphTargetsAndTheirAnimation) {
    const test::TempDir dir;
    io::SequenceMesh cloth{
        "cloth", squareTriangles(), {square(0, 0), square(0.1, 0), square(0.3, 0.05)}};
    io::SequenceMesh body{
        "body", squareTriangles(), {square(-1, 0), square(-1, 0.2), square(-1, 0.4)}};
    const std::vector<double> times{0.0, 1.0 / 30, 2.0 / 30};
    const auto path = dir / "seq.glb";
    ASSERT_TRUE(io::writeSequenceGlb(path, {cloth, body}, times).ok());

    Assimp::Importer importer;
    const aiScene* scene = importer.ReadFile(path.string(), 0);
    ASSERT_NE(scene, nullptr) << importer.GetErrorString();
    ASSERT_EQ(scene->mNumMeshes, 2u);
    for (unsigned m = 0; m < 2; ++m) {
        const aiMesh* mesh = scene->mMeshes[m];
        const io::SequenceMesh& written = m == 0 ? cloth : body;
        EXPECT_EQ(std::string(mesh->mName.C_Str()), written.name);
        ASSERT_EQ(mesh->mNumVertices, 4u);
        ASSERT_EQ(mesh->mNumFaces, 2u);
        // glTF targets hold displacements; assimp adds them to the base when it reads.
        ASSERT_EQ(mesh->mNumAnimMeshes, 2u);
        for (unsigned k = 0; k < 2; ++k) {
            const aiAnimMesh* target = mesh->mAnimMeshes[k];
            ASSERT_TRUE(target->HasPositions());
            for (unsigned i = 0; i < 4; ++i) {
                for (int c = 0; c < 3; ++c) {
                    EXPECT_NEAR(target->mVertices[i][static_cast<unsigned>(c)],
                                written.frames[k + 1](i, c), 1e-6)
                        << "mesh " << m << " frame " << k + 1 << " vertex " << i;
                }
            }
        }
        for (unsigned i = 0; i < 4; ++i) {
            EXPECT_NEAR(mesh->mVertices[i].y, written.frames[0](i, 1), 1e-6);
        }
    }
    ASSERT_EQ(scene->mNumAnimations, 1u);
    const aiAnimation* animation = scene->mAnimations[0];
    ASSERT_EQ(animation->mNumMorphMeshChannels, 2u);
    const aiMeshMorphAnim* channel = animation->mMorphMeshChannels[0];
    ASSERT_EQ(channel->mNumKeys, 3u);
    // Key k shows frame k: no target at the first key, target k−1 alone after it.
    for (unsigned k = 0; k < 3; ++k) {
        const aiMeshMorphKey& key = channel->mKeys[k];
        double sum = 0;
        for (unsigned j = 0; j < key.mNumValuesAndWeights; ++j) {
            sum += key.mWeights[j];
            if (k > 0 && key.mValues[j] == k - 1) {
                EXPECT_DOUBLE_EQ(key.mWeights[j], 1.0);
            }
        }
        EXPECT_DOUBLE_EQ(sum, k == 0 ? 0.0 : 1.0) << "key " << k;
    }
    // The key times, in the animation's ticks.
    const double ticksPerSecond =
        animation->mTicksPerSecond > 0 ? animation->mTicksPerSecond : 1000.0;
    EXPECT_NEAR(channel->mKeys[2].mTime / ticksPerSecond, times[2], 1e-6);
}

TEST(GltfSequence, RefusesWhatCannotBeASequenceNamingTheFile) {
    const test::TempDir dir;
    const auto path = dir / "bad.glb";
    const io::SequenceMesh cloth{"cloth", squareTriangles(), {square(0, 0), square(0.1, 0)}};
    const auto expectError = [&](const std::vector<io::SequenceMesh>& meshes,
                                 const std::vector<double>& times, const std::string& words) {
        const auto written = io::writeSequenceGlb(path, meshes, times);
        ASSERT_FALSE(written.ok()) << words;
        EXPECT_NE(written.error().toString().find(path.string()), std::string::npos);
        EXPECT_NE(written.error().toString().find(words), std::string::npos)
            << written.error().toString();
        EXPECT_FALSE(std::filesystem::exists(path));
    };
    expectError({}, {0.0}, "no mesh");
    expectError({cloth}, {0.0, 0.0}, "must increase");
    expectError({cloth}, {0.0, 0.1, 0.2}, "2 frames for 3 times");
    io::SequenceMesh grows = cloth;
    grows.frames[1] = sim::MatX3::Zero(5, 3);
    expectError({grows}, {0.0, 0.1}, "changes its vertex count at frame 1");
    io::SequenceMesh broken = cloth;
    broken.frames[1](2, 1) = std::nan("");
    expectError({broken}, {0.0, 0.1}, "non-finite position at frame 1");
    io::SequenceMesh outOfRange = cloth;
    outOfRange.triangles(1, 2) = 4;
    expectError({outOfRange}, {0.0, 0.1}, "index out of range");
}
