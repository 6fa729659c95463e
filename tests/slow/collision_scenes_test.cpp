// The bundled collision scenes, run whole: no penetration beyond 10% of the obstacle's
// thickness at any frame, friction carrying a sheet on a spinning sphere, trapped cloth coming
// out the side it entered within 1 s, and no intersecting triangle pair at the end.

#include "io/scene_file.h"

#include "sim/collision/collision_stage.h"
#include "sim/collision/geometry.h"
#include "sim/simulation.h"
#include "sim/test_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace atelier {
namespace {

namespace fs = std::filesystem;

sim::SceneSpec load(const std::string& relative) {
    const fs::path path = fs::path(ATELIER_SOURCE_DIR) / "assets/scenes" / relative;
    auto loaded = io::loadScene(path.string());
    EXPECT_TRUE(loaded.ok()) << loaded.error().toString();
    return loaded.ok() ? loaded.value() : sim::SceneSpec{};
}

double smallestObstacleThickness(const sim::SceneSpec& s) {
    double t = 1e300;
    for (const auto& o : s.obstacles) {
        t = std::min(t, o.thickness);
    }
    return t;
}

/// Cloth–obstacle intersecting triangle pairs now (cloth–cloth pairs are left out: these scenes
/// run without self-collision, or self-collision does not yet keep every dense fold apart).
long obstacleIntersections(const sim::Simulation& simulation) {
    long withObstacles = -1;
    test::intersections(simulation, &withObstacles);
    return withObstacles;
}

class RestingScene : public ::testing::TestWithParam<std::string> {};

TEST_P(RestingScene, PenetrationStaysWithinTenPercentOfThicknessAtEveryFrame) {
    const sim::SceneSpec scene = load(GetParam());
    sim::Simulation simulation(scene);
    ASSERT_TRUE(simulation.error().empty()) << simulation.error();
    double worst = 0;
    const auto status = simulation.run(
        scene.duration, [&](int, double) { worst = std::max(worst, simulation.penetration()); });
    ASSERT_EQ(status, sim::RunStatus::Finished) << simulation.stats().error;
    EXPECT_TRUE(simulation.stats().finite);
    const double limit = 0.1 * smallestObstacleThickness(scene);
    EXPECT_LE(worst, limit);
    EXPECT_LE(simulation.stats().maxPenetration, limit);
    EXPECT_EQ(obstacleIntersections(simulation), 0);
    EXPECT_EQ(simulation.intersectingTrianglePairs(), 0);
    EXPECT_GT(simulation.stats().contacts, 0);
}

INSTANTIATE_TEST_SUITE_P(Scenes, RestingScene,
                         ::testing::Values("sheet-on-sphere.json", "sheet-on-box-edge.json",
                                           "hard/stack-on-box.json"),
                         [](const auto& info) {
                             std::string n = fs::path(info.param).stem().string();
                             std::replace(n.begin(), n.end(), '-', '_');
                             return n;
                         });

TEST(FastRotatingSphere, FrictionCarriesTheSheetAroundWithoutTunnelling) {
    const sim::SceneSpec scene = load("hard/fast-rotating-sphere.json");
    sim::Simulation simulation(scene);
    ASSERT_TRUE(simulation.error().empty()) << simulation.error();
    double worst = 0;
    ASSERT_EQ(simulation.run(
                  1.0, [&](int, double) { worst = std::max(worst, simulation.penetration()); }),
              sim::RunStatus::Finished)
        << simulation.stats().error;
    // Angular velocity of the sheet about the sphere's vertical axis: mass-weighted
    // L_y / I_y. The sphere turns at 1.5π rad/s (+Y).
    const sim::MatX3& x = simulation.positions();
    const sim::MatX3& v = simulation.velocities();
    const sim::VecX& m = simulation.masses();
    double angular = 0, inertia = 0;
    for (int i = 0; i < x.rows(); ++i) {
        const double rx = x(i, 0), rz = x(i, 2);
        angular += m[i] * (rz * v(i, 0) - rx * v(i, 2));
        inertia += m[i] * (rx * rx + rz * rz);
    }
    const double omega = angular / inertia;
    EXPECT_GT(omega, 0.25 * 1.5 * M_PI) << "the sheet should be carried along by friction";
    EXPECT_LE(worst, 0.1 * smallestObstacleThickness(scene));
    EXPECT_EQ(obstacleIntersections(simulation), 0);
    EXPECT_EQ(simulation.intersectingTrianglePairs(), 0);
    // Nothing fell through: every vertex is outside the sphere.
    for (int i = 0; i < x.rows(); ++i) {
        EXPECT_GT((x.row(i) - sim::Vec3(0, 0.3, 0).transpose()).norm(), 0.3) << i;
    }
}

TEST(ThroughBody, TrappedClothComesOutTheSideItEnteredWithinOneSecond) {
    const sim::SceneSpec scene = load("hard/through-body.json");
    sim::Simulation simulation(scene);
    ASSERT_TRUE(simulation.error().empty()) << simulation.error();
    EXPECT_GT(simulation.collision()->figures().trappedVertices, 20) << "the scene starts trapped";
    // The side it entered from is +x (the sheet's free part): when the last trapped vertex is
    // out, nothing is at x < −0.15 (beyond the torso's far side). Afterwards the sheet slides
    // off the torso and may swing round it as it falls.
    double outAt = -1, xMinWhenOut = 0;
    ASSERT_EQ(simulation.run(1.0,
                             [&](int, double t) {
                                 if (outAt < 0 &&
                                     simulation.collision()->figures().trappedVertices == 0) {
                                     outAt = t;
                                     xMinWhenOut = simulation.positions().col(0).minCoeff();
                                 }
                             }),
              sim::RunStatus::Finished)
        << simulation.stats().error;
    ASSERT_GE(outAt, 0) << "still trapped after 1 s";
    EXPECT_GT(xMinWhenOut, -0.15);
    EXPECT_EQ(simulation.collision()->figures().trappedVertices, 0);
    EXPECT_LE(simulation.penetration(), 0.1 * smallestObstacleThickness(scene));
    // Nothing stays pierced: neither a cloth triangle by the body (all its vertices outside) nor
    // the sheet by itself (self-collision is on).
    EXPECT_EQ(obstacleIntersections(simulation), 0);
    EXPECT_EQ(simulation.intersectingTrianglePairs(), 0);
    EXPECT_LT(simulation.maxEdgeStrain(), 0.10);
}

/// The curtain hangs in the plane z = 0; its bottom-left corner is dragged in front (+z) and
/// then back to 0.15 m behind the plane, and released at 0.8 s. Checked at the release and at
/// `endTime`.
void checkPulledThroughSelf(sim::SceneSpec scene, double endTime) {
    ASSERT_EQ(scene.drives.size(), 1u);
    const int corner = scene.drives[0].vertex;
    const sim::MatX2& rest = scene.cloths[0].mesh.rest;
    sim::Simulation simulation(scene);
    ASSERT_TRUE(simulation.error().empty()) << simulation.error();
    ASSERT_EQ(simulation.run(0.8), sim::RunStatus::Finished) << simulation.stats().error;
    // Pushed back, not crossed: the corner is on the front (+z at rest) of the curtain
    // triangle nearest to it, among those far from it in the pattern (not the dragged flap).
    {
        const sim::MatX3& x = simulation.positions();
        const sim::MatX3i& tri = scene.cloths[0].mesh.triangles;
        const sim::Vec3 p = x.row(corner).transpose();
        double nearest = 1e300, side = 0;
        for (int t = 0; t < tri.rows(); ++t) {
            bool far = true;
            for (int k = 0; k < 3; ++k) {
                far = far && (rest.row(tri(t, k)) - rest.row(corner)).norm() > 0.35;
            }
            if (!far) {
                continue;
            }
            const sim::Vec3 a = x.row(tri(t, 0)), b = x.row(tri(t, 1)), c = x.row(tri(t, 2));
            const sim::TrianglePoint cp = sim::closestPointOnTriangle(p, a, b, c);
            if (cp.distance < nearest) {
                nearest = cp.distance;
                side = sim::triangleNormal(a, b, c).dot(p - cp.point);
            }
        }
        EXPECT_LT(nearest, 0.02) << "the corner should be against the curtain at the release";
        EXPECT_GT(side, 0.0) << "the corner went through the curtain";
        EXPECT_EQ(simulation.intersectingTrianglePairs(), 0);
    }
    ASSERT_EQ(simulation.run(endTime), sim::RunStatus::Finished) << simulation.stats().error;
    EXPECT_TRUE(simulation.stats().finite);
    EXPECT_EQ(simulation.intersectingTrianglePairs(), 0);
    // Fallen back out on the side it came from (the front), the curtain unstretched.
    EXPECT_GT(simulation.positions()(corner, 2), 0.0);
    EXPECT_LT(simulation.maxEdgeStrain(), 0.10);
}

TEST(PulledThroughSelf, TheFoldStaysOnItsSideAndIsFreeOfIntersectionsOneSecondAfterRelease) {
    checkPulledThroughSelf(load("hard/pulled-through-self.json"), 1.8);
}

// With the continuum plate's bending (softer than the hinges at this mesh) the dragged corner
// folds over within a cell and winds round onto the next cells, a patch whose normals still
// fit in the culling cone: without the fail-safe's watched pairs the detection never saw that
// pair, the fail-safe put the corner back every step, and the flap hung frozen behind the
// curtain after the release. The softer flap takes longer to fall out: 1.5 s.
TEST(PulledThroughSelf, WithContinuumBendingTheFoldIsNotFrozenAndFallsOutWithinOneAndAHalfSeconds) {
    sim::SceneSpec scene = load("hard/pulled-through-self.json");
    scene.cloths[0].bendingModel = sim::BendingModel::Continuum;
    checkPulledThroughSelf(scene, 2.3);
}

} // namespace
} // namespace atelier
