// Touching a simulation between steps: stepping one step at a time (with pauses) is the
// uninterrupted run to the bit; grabbing, pinning and moving an obstacle; snapshots.

#include "sim/collision/obstacle.h"
#include "sim/mesh/vertex_normals.h"
#include "sim/simulation.h"
#include "sim/snapshot.h"
#include "sim/test_scenes.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

namespace atelier {
namespace {

using sim::MatX3;
using sim::Vec3;

/// A 0.4 m sheet of 16×16 cells lying 2 cm above a 1 m box whose top is at y = 0 (the box
/// centred under the sheet), implicit Euler with self-collision: a garment-like scene.
sim::SceneSpec sheetOverBox() {
    sim::SceneSpec s = test::smallSheet(sim::StretchModel::Fem, 16, 0.4, false, true);
    s.cloths[0].position.col(1).array() += 0.02;
    s.cloths[0].selfCollision = true;
    sim::ObstacleSpec box;
    box.name = "box";
    sim::makeBoxMesh(Vec3(1.0, 0.2, 1.0), 2, box.vertices, box.triangles);
    box.vertices.rowwise() += Vec3(0.2, -0.1, -0.2).transpose();
    box.closed = true;
    s.obstacles.push_back(box);
    s.integrator.kind = sim::IntegratorKind::ImplicitEuler;
    s.integrator.dt = 1.0 / 200;
    s.frameRate = 30;
    return s;
}

bool sameBits(const MatX3& a, const MatX3& b) {
    return a.rows() == b.rows() && std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
}

TEST(Interaction, StepByStepWithPausesIsTheUninterruptedRun) {
    const sim::SceneSpec scene = sheetOverBox();
    // The reference advances frame by frame (advance(), which does not go through the
    // step-by-step path).
    sim::Simulation whole(scene);
    for (int frame = 1; frame <= 12; ++frame) {
        ASSERT_EQ(whole.advance(frame / 30.0 - whole.time()), sim::RunStatus::Finished)
            << whole.error();
    }

    sim::Simulation stepped(scene);
    sim::SnapshotBuffer snapshots; // publishing must not change a bit either
    stepped.publishTo(&snapshots);
    long steps = 0;
    while (stepped.time() < 0.4 - 1e-12) {
        ASSERT_EQ(stepped.step(0.4), sim::RunStatus::Finished);
        if (++steps % 7 == 0) {
            std::this_thread::sleep_for(std::chrono::microseconds(200)); // a pause
        }
    }
    EXPECT_EQ(stepped.time(), whole.time());
    EXPECT_EQ(stepped.stats().steps, whole.stats().steps);
    EXPECT_TRUE(sameBits(stepped.positions(), whole.positions()));
    EXPECT_TRUE(sameBits(stepped.velocities(), whole.velocities()));
    EXPECT_EQ(stepped.frameIndex(), 12);
    sim::Simulation run(scene);
    ASSERT_EQ(run.run(0.4), sim::RunStatus::Finished);
    EXPECT_TRUE(sameBits(run.positions(), whole.positions()));
}

TEST(Interaction, StepNeverGoesPastUntil) {
    sim::Simulation s(sheetOverBox());
    ASSERT_EQ(s.step(1.0), sim::RunStatus::Finished); // a frame to 1/30 s is under way
    const double until = s.time() + 0.002;            // nearer than the frame's end
    ASSERT_EQ(s.step(until), sim::RunStatus::Finished);
    EXPECT_LE(s.time(), until + 1e-15);
    EXPECT_EQ(s.step(until), sim::RunStatus::Finished) << "at until: nothing to do";
    EXPECT_LE(s.time(), until + 1e-15);
    ASSERT_EQ(s.run(0.05), sim::RunStatus::Finished);
    EXPECT_NEAR(s.time(), 0.05, 1e-12);
}

TEST(Interaction, PinningAGrabbedVertexHoldsIt) {
    sim::Simulation s(sheetOverBox());
    ASSERT_EQ(s.run(0.3), sim::RunStatus::Finished);
    const int vertex = s.clothTriangles()(0, 0);
    const Vec3 at = s.positions().row(vertex).transpose();
    const int grab = s.grab({0, Vec3(1, 0, 0)}, at + Vec3(0, 0.1, 0));
    ASSERT_GT(grab, 0);
    ASSERT_TRUE(s.pin(vertex));
    ASSERT_EQ(s.run(0.5), sim::RunStatus::Finished);
    EXPECT_EQ(Vec3(s.positions().row(vertex).transpose()), at) << "the pin wins over the grab";
    EXPECT_GT(s.positions()(s.clothTriangles()(0, 1), 1), at.y() + 0.02)
        << "the grab lifts the rest";
}

TEST(Interaction, GrabbedCornerFollowsAndComesBackToRestWithoutIntersections) {
    sim::Simulation s(sheetOverBox());
    ASSERT_EQ(s.run(0.5), sim::RunStatus::Finished) << s.error();
    // The corner triangle at the origin (vertex 0 of the combined triangles' first triangle).
    const int triangle = 0;
    const int vertex = s.clothTriangles()(triangle, 0);
    sim::ClothPoint point{triangle, Vec3(1, 0, 0)};
    const Vec3 start = s.positions().row(vertex).transpose();
    const int grab = s.grab(point, start, 0.02);
    ASSERT_GT(grab, 0);
    // Lift by 10 cm over 0.2 s, moving the target every step as a mouse would, then hold.
    const double t0 = s.time();
    while (s.time() < t0 + 0.4) {
        const double f = std::min(1.0, (s.time() - t0) / 0.2);
        ASSERT_TRUE(s.moveGrab(grab, start + Vec3(0, 0.1 * f, 0)));
        ASSERT_EQ(s.step(), sim::RunStatus::Finished) << s.error();
    }
    const Vec3 held = s.positions().row(vertex).transpose();
    EXPECT_NEAR(held.y(), start.y() + 0.1, 0.005);
    EXPECT_EQ(test::intersections(s), 0);
    EXPECT_TRUE(s.release(grab));
    EXPECT_FALSE(s.release(grab));
    ASSERT_EQ(s.run(s.time() + 1.5), sim::RunStatus::Finished) << s.error();
    // Back down on the box, at rest, untangled and unstretched.
    EXPECT_LT(s.positions()(vertex, 1), start.y() + 0.01);
    EXPECT_EQ(test::intersections(s), 0);
    EXPECT_LT(s.penetration(), 1e-3);
    EXPECT_LT(s.kineticEnergy() / static_cast<double>(s.positions().rows()), 1e-7);
    EXPECT_LT(s.maxEdgeStrain(), 0.05);
}

TEST(Interaction, GrabRefusesWhatItCannotHold) {
    sim::Simulation s(sheetOverBox());
    EXPECT_EQ(s.grab({-1, Vec3(1, 0, 0)}, Vec3::Zero()), 0);
    EXPECT_EQ(s.grab({static_cast<int>(s.clothTriangles().rows()), Vec3(1, 0, 0)}, Vec3::Zero()),
              0);
    EXPECT_EQ(s.grab({0, Vec3(1, 0, 0)}, Vec3(std::nan(""), 0, 0)), 0);
    for (int k = 0; k < 3; ++k) {
        ASSERT_TRUE(s.pin(s.clothTriangles()(0, k)));
    }
    EXPECT_EQ(s.grab({0, Vec3(1, 0, 0)}, Vec3::Zero()), 0) << "every corner is pinned";
    EXPECT_FALSE(s.moveGrab(12345, Vec3::Zero()));
}

TEST(Interaction, PinnedVertexStaysUnpinnedFalls) {
    sim::SceneSpec scene = test::smallSheet(sim::StretchModel::Fem, 8, 0.4, false, false);
    scene.integrator.kind = sim::IntegratorKind::ImplicitEuler;
    scene.integrator.dt = 1.0 / 200;
    sim::Simulation s(scene);
    const int top = 8 * 9 + 4; // middle of the top row
    ASSERT_EQ(s.run(0.1), sim::RunStatus::Finished);
    ASSERT_TRUE(s.pin(top));
    EXPECT_FALSE(s.pin(top));
    EXPECT_TRUE(s.pinned(top));
    const Vec3 at = s.positions().row(top).transpose();
    ASSERT_EQ(s.run(0.3), sim::RunStatus::Finished);
    EXPECT_EQ(Vec3(s.positions().row(top).transpose()), at);
    EXPECT_LT(s.positions().col(1).minCoeff(), at.y() - 0.01) << "the rest hangs from it";
    ASSERT_TRUE(s.unpin(top));
    EXPECT_FALSE(s.unpin(top));
    ASSERT_EQ(s.run(0.4), sim::RunStatus::Finished);
    EXPECT_LT(s.positions()(top, 1), at.y() - 0.05);
}

TEST(Interaction, MovedObstaclePushesTheClothWithoutPassingThrough) {
    sim::Simulation s(sheetOverBox());
    ASSERT_EQ(s.run(0.4), sim::RunStatus::Finished) << s.error();
    const double before = s.positions().col(1).mean();
    // Up by 5 cm over 0.1 s (a jerk no real body makes, well above the cloth's own motions).
    ASSERT_TRUE(s.setObstaclePose(0, Vec3(0, 0.05, 0), Vec3::Zero(), 0.1));
    EXPECT_FALSE(s.setObstaclePose(3, Vec3::Zero(), Vec3::Zero()));
    ASSERT_EQ(s.run(0.8), sim::RunStatus::Finished) << s.error();
    EXPECT_NEAR(s.obstaclePositions(0).col(1).maxCoeff(), 0.05, 1e-12);
    EXPECT_NEAR(s.positions().col(1).mean() - before, 0.05, 0.005);
    EXPECT_LT(s.penetration(), 1e-3);
    EXPECT_EQ(test::intersections(s), 0);
}

TEST(Interaction, SnapshotsHoldTheStateOfTheirStep) {
    sim::Simulation s(sheetOverBox());
    sim::SnapshotBuffer buffer;
    sim::Snapshot snap;
    EXPECT_FALSE(buffer.read(snap)) << "nothing published yet";
    s.publishTo(&buffer);
    ASSERT_TRUE(buffer.read(snap));
    EXPECT_EQ(snap.version, 1u);
    EXPECT_TRUE(sameBits(snap.clothPositions, s.positions()));
    ASSERT_EQ(snap.obstaclePositions.size(), 1u);
    const std::uint64_t boxVersion = snap.obstacleVersions[0];
    for (int k = 0; k < 5; ++k) {
        ASSERT_EQ(s.step(), sim::RunStatus::Finished);
    }
    ASSERT_TRUE(buffer.read(snap));
    EXPECT_EQ(snap.version, 6u);
    EXPECT_EQ(snap.steps, s.stats().steps);
    EXPECT_EQ(snap.time, s.time());
    EXPECT_TRUE(sameBits(snap.clothPositions, s.positions()));
    MatX3 normals;
    sim::vertexNormals(s.positions(), s.clothTriangles(), normals);
    EXPECT_TRUE(sameBits(snap.clothNormals, normals));
    EXPECT_EQ(snap.obstacleVersions[0], boxVersion) << "a static box is uploaded once";
    EXPECT_TRUE(sameBits(snap.obstaclePositions[0], s.obstaclePositions(0)));
    ASSERT_TRUE(s.setObstaclePose(0, Vec3(0, 0.01, 0), Vec3::Zero()));
    ASSERT_EQ(s.step(), sim::RunStatus::Finished);
    ASSERT_TRUE(buffer.read(snap));
    EXPECT_NE(snap.obstacleVersions[0], boxVersion);
    EXPECT_TRUE(sameBits(snap.obstaclePositions[0], s.obstaclePositions(0)));
    s.publishTo(nullptr);
    ASSERT_EQ(s.step(), sim::RunStatus::Finished);
    ASSERT_TRUE(buffer.read(snap));
    EXPECT_EQ(snap.version, 7u) << "no longer published";
}

} // namespace
} // namespace atelier
