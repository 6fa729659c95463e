// The collision stage in the step loop: only when needed, no penetration on obstacles, Coulomb
// friction against its closed form, continuous detection against tunnelling, the contact
// region vote putting pushed-through vertices back, and the fail-safe leaving no crossing (nor
// one a drive makes).

#include "sim/collision/collision_stage.h"
#include "sim/collision/fail_safe.h"
#include "sim/collision/obstacle.h"
#include "sim/core/parallel.h"
#include "sim/simulation.h"
#include "sim/test_scenes.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

namespace atelier {
namespace sim {

/// Runs CollisionStage's re-detection after the corrections (Detection::Again) on its own,
/// either as it runs (only triangles moved since the step's first detection tested again) or
/// testing every candidate pair (every triangle counted as moved), and returns its contacts.
struct CollisionStageProbe {
    static std::vector<Contact> again(CollisionStage& stage, std::size_t k, double h,
                                      const MatX3& xe, bool testEveryPair) {
        CollisionStage::ObstacleData& o = stage.m_obstacles[k];
        const MatX3 firstPositions = o.firstPositions;
        if (testEveryPair) {
            o.firstPositions.setConstant(std::numeric_limits<double>::quiet_NaN());
        }
        const std::size_t first = stage.m_contacts.size();
        stage.detectObstacle(k, h, xe, xe, CollisionStage::Detection::Again);
        std::vector<Contact> found(stage.m_contacts.begin() + static_cast<std::ptrdiff_t>(first),
                                   stage.m_contacts.end());
        stage.m_contacts.resize(first);
        stage.m_contactKey.resize(first);
        stage.m_contactSide.resize(first);
        stage.m_contactReliable.resize(first);
        o.firstPositions = firstPositions;
        return found;
    }
    /// Where the cloth was at the step's first detection against obstacle k.
    static const MatX3& firstPositions(const CollisionStage& stage, std::size_t k) {
        return stage.m_obstacles[k].firstPositions;
    }
};

} // namespace sim

namespace {

using sim::Vec3;

sim::ObstacleSpec sphereObstacle(double radius, const Vec3& centre, double thickness = 0.003) {
    sim::ObstacleSpec o;
    o.name = "sphere";
    sim::makeSphereMesh(radius, 3, o.vertices, o.triangles);
    o.closed = true;
    o.keys.push_back(sim::ObstacleKey{0.0, centre, Vec3::Zero()});
    o.thickness = thickness;
    return o;
}

sim::ObstacleSpec planeObstacle(double size, const Vec3& position, const Vec3& rotation,
                                double friction) {
    sim::ObstacleSpec o;
    o.name = "plane";
    sim::makePlaneMesh(size, 1, o.vertices, o.triangles);
    o.keys.push_back(sim::ObstacleKey{0.0, position, rotation});
    o.thickness = 0.002;
    o.staticFriction = friction;
    o.kineticFriction = friction;
    return o;
}

/// A horizontal sheet (y = height) of `size` centred over the origin.
sim::SceneSpec sheetAbove(double size, int cells, double height) {
    sim::SceneSpec s = test::smallSheet(sim::StretchModel::Fem, cells, size, false, true);
    for (int i = 0; i < s.cloths[0].position.rows(); ++i) {
        s.cloths[0].position.row(i) += Vec3(-size / 2, height, size / 2).transpose();
    }
    s.cloths[0].thickness = 0.002;
    s.integrator.kind = sim::IntegratorKind::ImplicitEuler;
    s.integrator.dt = 1.0 / 240;
    s.integrator.maxDt = 1.0 / 240;
    return s;
}

/// Two self-colliding horizontal sheets of 0.2 m, `cells` per side, the second 1 cm above the
/// first; `x` gets both sheets' positions (the lower first).
sim::SceneSpec twoSheets(int cells, sim::MatX3& x) {
    sim::SceneSpec s = sheetAbove(0.2, cells, 0.0);
    sim::ClothSpec upper = s.cloths[0];
    upper.position.col(1).array() += 0.01;
    s.cloths.push_back(upper);
    for (sim::ClothSpec& c : s.cloths) {
        c.selfCollision = true;
    }
    const int n = s.cloths[0].position.rows();
    x.resize(2 * n, 3);
    x << s.cloths[0].position, s.cloths[1].position;
    return s;
}

TEST(CollisionStage, OnlyInThePipelineWhenTheSceneNeedsIt) {
    sim::SceneSpec plain = sheetAbove(0.5, 4, 1.0);
    sim::Simulation a(plain);
    const auto stagesA = a.activeStages();
    EXPECT_EQ(a.collision(), nullptr);
    EXPECT_TRUE(std::none_of(stagesA.begin(), stagesA.end(),
                             [](const std::string& s) { return s.rfind("collision", 0) == 0; }));

    sim::SceneSpec withBall = plain;
    withBall.obstacles.push_back(sphereObstacle(0.2, Vec3(0, 0.5, 0)));
    sim::Simulation b(withBall);
    const auto stagesB = b.activeStages();
    ASSERT_NE(b.collision(), nullptr);
    EXPECT_NE(std::find(stagesB.begin(), stagesB.end(), "collision.obstacles"), stagesB.end());
    EXPECT_EQ(std::find(stagesB.begin(), stagesB.end(), "collision.self"), stagesB.end());

    sim::SceneSpec selfOnly = plain;
    selfOnly.cloths[0].selfCollision = true;
    sim::Simulation c(selfOnly);
    const auto stagesC = c.activeStages();
    EXPECT_NE(std::find(stagesC.begin(), stagesC.end(), "collision.self"), stagesC.end());
    EXPECT_EQ(std::find(stagesC.begin(), stagesC.end(), "collision.obstacles"), stagesC.end());
}

TEST(CollisionStage, CrossingVerticesFindsAMotionThroughTheCloth) {
    // Two self-colliding sheets 1 cm apart: moving one vertex of the upper sheet 2 cm down
    // carries it (and its triangles) through the lower one; 5 mm down does not. Only the
    // triangles around the listed moved vertices are tested (a weld's merge moves a few).
    sim::MatX3 x;
    const sim::SceneSpec s = twoSheets(4, x);
    const int n = s.cloths[0].position.rows();
    sim::CollisionStage stage(s, {0, n, 2 * n}, x);
    const int centre = n + 12; // the upper sheet's middle vertex (5×5 grid)
    ASSERT_NEAR(x(centre, 0), 0.0, 1e-12);
    sim::MatX3 through = x;
    through(centre, 1) -= 0.02;
    const std::vector<int> crossing = stage.crossingVertices(x, through, {centre});
    EXPECT_NE(std::find(crossing.begin(), crossing.end(), centre), crossing.end());
    bool lower = false;
    for (int v : crossing) {
        lower = lower || v < n;
        // The vertex, its edges' other ends (edge–edge crossings), and the lower sheet.
        EXPECT_TRUE(v < n || (x.row(v) - x.row(centre)).norm() < 0.0708) << v; // a cell diagonal
    }
    EXPECT_TRUE(lower);
    EXPECT_TRUE(stage.crossingVertices(x, through, {}).empty());
    sim::MatX3 short_ = x;
    short_(centre, 1) -= 0.005;
    EXPECT_TRUE(stage.crossingVertices(x, short_, {centre}).empty());
}

TEST(CollisionStage, CrossingVerticesFindsAMotionIntoAnObstacle) {
    // A self-colliding sheet 1 cm above the top of a sphere: moving its middle vertex 2 cm down
    // brings its triangles into the sphere (a weld's merge carrying cloth into the body); 5 mm
    // down does not, nor does the way back out.
    sim::SceneSpec s = sheetAbove(0.2, 4, 0.31);
    s.cloths[0].selfCollision = true;
    s.obstacles.push_back(sphereObstacle(0.3, Vec3(0, 0, 0)));
    const sim::MatX3 x = s.cloths[0].position;
    const int n = static_cast<int>(x.rows());
    sim::CollisionStage stage(s, {0, n}, x);
    sim::MatX3 xe = x, ve = sim::MatX3::Zero(n, 3);
    stage.update(0.0, 0.0, x, xe, ve, sim::VecX::Ones(n));
    ASSERT_EQ(xe, x);      // clear of the sphere: the start is left as it is
    const int centre = 12; // the middle vertex of the 5×5 grid
    ASSERT_NEAR(x(centre, 0), 0.0, 1e-12);
    sim::MatX3 into = x;
    into(centre, 1) -= 0.02;
    const std::vector<int> crossing = stage.crossingVertices(x, into, {centre});
    EXPECT_EQ(crossing, std::vector<int>{centre});
    EXPECT_TRUE(stage.crossingVertices(into, x, {centre}).empty()); // out again
    sim::MatX3 short_ = x;
    short_(centre, 1) -= 0.005;
    EXPECT_TRUE(stage.crossingVertices(x, short_, {centre}).empty());
}

TEST(CollisionStage, DetectionInParallelGivesExactlyTheSerialResult) {
    // A self-colliding sheet falling onto a sphere, large enough for detection to run in
    // parallel pieces: positions after the contacts begin must be bitwise those of one thread.
    sim::SceneSpec s = sheetAbove(0.8, 40, 0.52);
    s.cloths[0].selfCollision = true;
    s.obstacles.push_back(sphereObstacle(0.25, Vec3(0, 0.25, 0)));
    const int threads = sim::threadCount();
    std::vector<sim::MatX3> results;
    std::vector<long> contacts;
    for (int t : {1, 2}) {
        sim::setThreadCount(t);
        sim::Simulation simulation(s);
        ASSERT_TRUE(simulation.error().empty()) << simulation.error();
        ASSERT_EQ(simulation.run(0.2), sim::RunStatus::Finished) << simulation.stats().error;
        results.push_back(simulation.positions());
        contacts.push_back(simulation.stats().contacts);
    }
    sim::setThreadCount(threads);
    EXPECT_GT(contacts[0], 100);
    EXPECT_EQ(contacts[1], contacts[0]);
    EXPECT_TRUE((results[1].array() == results[0].array()).all());
}

TEST(CollisionStage, RedetectionAfterTheCorrectionsFindsWhatTestingEveryPairFinds) {
    // A self-colliding sheet lying 6 mm over a moving sphere, within the proximity margin
    // (7.5 mm) but not the contact distance (5 mm), so the corrections leave most of it where
    // it is; one step, then a fifth of the vertices moved by up to 3 mm, as the cloth–cloth
    // corrections would. The re-detection tests only the moved triangles and takes the others'
    // contacts from the step's first detection (re-testing their face–vertex and edge–edge
    // features): it must give exactly the contacts, in the same order, that testing every
    // candidate pair gives. (Their normals differ between the two ways only where a pair
    // turned over during the step, which this scene does not produce.)
    sim::SceneSpec s = sheetAbove(0.5, 24, 0.0);
    s.cloths[0].selfCollision = true;
    sim::ObstacleSpec sphere = sphereObstacle(0.25, Vec3::Zero());
    sphere.keys.push_back(sim::ObstacleKey{1.0, Vec3(0.2, 0.1, 0.0), Vec3(0.0, 0.5, 0.0)});
    s.obstacles.push_back(sphere);
    sim::MatX3& x = s.cloths[0].position;
    const double r = 0.25 + 0.003 + 0.002 + 0.001; // 1 mm outside the contact distance
    for (int i = 0; i < x.rows(); ++i) {
        const Vec3 flat(x(i, 0), 0.0, x(i, 2));
        const double lift = std::sqrt(std::max(0.0, r * r - flat.squaredNorm()));
        x.row(i) = (flat.norm() < r ? Vec3(flat.x(), lift, flat.z()) : flat).transpose();
    }
    const int n = static_cast<int>(x.rows());
    sim::CollisionStage stage(s, {0, n}, x);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    sim::MatX3 xe = x, ve = sim::MatX3::Zero(n, 3);
    for (int i = 0; i < n; ++i) {
        xe.row(i) += 0.0003 * Vec3(u(rng), u(rng), u(rng)).transpose();
    }
    const double h = 1.0 / 240;
    stage.update(0.0, h, x, xe, ve, sim::VecX::Ones(n));
    int moved = 0;
    for (int i = 0; i < n; i += 5) {
        xe.row(i) += 0.003 * Vec3(u(rng), u(rng), u(rng)).transpose();
        ++moved;
    }
    const std::vector<sim::Contact> fast = sim::CollisionStageProbe::again(stage, 0, h, xe, false);
    const std::vector<sim::Contact> full = sim::CollisionStageProbe::again(stage, 0, h, xe, true);
    ASSERT_GT(moved, 50);
    ASSERT_EQ(fast.size(), full.size());
    // Per kind, the contacts all of whose cloth vertices are where the first detection saw
    // them: those come from the first detection's list, not from a new test.
    const sim::MatX3& first = sim::CollisionStageProbe::firstPositions(stage, 0);
    int kinds[3] = {0, 0, 0};
    for (std::size_t i = 0; i < full.size(); ++i) {
        const sim::Contact& a = fast[i];
        const sim::Contact& b = full[i];
        bool unmoved = true;
        for (int k = 0; k < 4; ++k) {
            unmoved = unmoved && (b.vertex[k] < 0 || xe.row(b.vertex[k]) == first.row(b.vertex[k]));
        }
        kinds[std::min(2, static_cast<int>(b.kind))] += unmoved ? 1 : 0;
        EXPECT_TRUE(a.kind == b.kind && a.obstacle == b.obstacle && a.distance == b.distance &&
                    a.normal == b.normal && a.obstaclePoint == b.obstaclePoint &&
                    a.obstacleVelocity == b.obstacleVelocity &&
                    a.staticFriction == b.staticFriction && a.kineticFriction == b.kineticFriction)
            << "contact " << i;
        for (int k = 0; k < 4; ++k) {
            EXPECT_EQ(a.vertex[k], b.vertex[k]) << "contact " << i;
            EXPECT_EQ(a.weight[k], b.weight[k]) << "contact " << i;
        }
        for (int k = 0; k < 3; ++k) {
            EXPECT_EQ(a.obstacleVertex[k], b.obstacleVertex[k]) << "contact " << i;
            EXPECT_EQ(a.obstacleWeight[k], b.obstacleWeight[k]) << "contact " << i;
        }
    }
    // Every kind of obstacle contact comes from the first detection's list too.
    EXPECT_GT(kinds[0], 100); // vertex–face
    EXPECT_GT(kinds[1], 0);   // face–vertex
    EXPECT_GT(kinds[2], 100); // edge–edge
}

TEST(CollisionStage, FailSafeLeavesNoCrossingOverTheStep) {
    // Two self-colliding sheets 1 cm apart; in one step the upper one is carried 8–12 cm
    // down (tilted), through the lower one. Whatever the corrections do, the fail-safe's rounds
    // (the first over every pair, the later ones only around the vertices put back) must leave
    // no feature crossing over xs → xe.
    sim::MatX3 xs;
    const sim::SceneSpec s = twoSheets(8, xs);
    const int n = s.cloths[0].position.rows();
    sim::CollisionStage stage(s, {0, n, 2 * n}, xs);
    sim::MatX3 xe = xs;
    for (int i = n; i < 2 * n; ++i) {
        xe(i, 1) -= 0.1 + 0.2 * xs(i, 0);
    }
    sim::MatX3 ve = (xe - xs) / 0.01;
    const sim::VecX invMass = sim::VecX::Ones(2 * n);
    std::vector<int> all(static_cast<std::size_t>(2 * n));
    std::iota(all.begin(), all.end(), 0);
    ASSERT_FALSE(stage.crossingVertices(xs, xe, all).empty());
    stage.update(0.0, 0.01, xs, xe, ve, invMass);
    EXPECT_GT(stage.figures().rolledBack, 0);
    EXPECT_TRUE(stage.crossingVertices(xs, xe, all).empty());
    EXPECT_EQ(stage.intersectingTrianglePairs(xe, {}), 0);
    for (int i : stage.crossingVertices(xs, xs, all)) {
        ADD_FAILURE() << "the start crosses at " << i;
    }
}

TEST(CrossingFailSafe, CarriesClothAlongADriveInsteadOfLeavingItCrossed) {
    // A drive (a held vertex: zero inverse mass) pulls the upper sheet's middle vertex 5 cm
    // down in one step, through the lower sheet 1 cm below, and nothing else moves. Putting
    // the lower sheet back at its start cannot undo that crossing: the fail-safe alone (no
    // corrections before it) carries the lower sheet's vertices along with the drive, and the
    // drive keeps its path.
    sim::MatX3 xs;
    const sim::SceneSpec s = twoSheets(8, xs);
    const int n = s.cloths[0].position.rows();
    const int driven = n + n / 2; // the upper sheet's middle vertex (9×9 grid)
    const int below = n / 2;      // the lower sheet's, 1 cm under it
    ASSERT_NEAR(xs(driven, 0), 0.0, 1e-12);
    ASSERT_NEAR(xs(below, 0), 0.0, 1e-12);
    const sim::CollisionMesh mesh(s, {0, n, 2 * n});
    sim::SurfaceBvh bvh(mesh.triangles, xs);
    sim::DetectionScratch scratch;
    sim::CrossingFailSafe failSafe;
    sim::MatX3 xe = xs;
    xe.row(driven) += Vec3(0.004, -0.05, 0.003).transpose(); // not exactly through a vertex
    const Vec3 drive = xe.row(driven).transpose();
    sim::MatX3 ve = (xe - xs) / 0.01;
    sim::VecX invMass = sim::VecX::Ones(2 * n);
    invMass[driven] = 0;
    std::vector<int> all(static_cast<std::size_t>(2 * n));
    std::iota(all.begin(), all.end(), 0);
    ASSERT_FALSE(failSafe.crossingVertices(mesh, bvh, xs, xe, all).empty());
    EXPECT_GT(failSafe.rollBack(mesh, bvh, scratch, xs, xe, ve, invMass), 0);
    EXPECT_TRUE(failSafe.crossingVertices(mesh, bvh, xs, xe, all).empty());
    EXPECT_EQ(Vec3(xe.row(driven).transpose()), drive); // the drive is where its path puts it
    // The lower sheet's middle vertex went down with it, still below it, at its velocity.
    EXPECT_NEAR(xe(below, 1), xs(below, 1) - 0.05, 1e-12);
    EXPECT_EQ(Vec3(ve.row(below).transpose()), Vec3(ve.row(driven).transpose()));
    // A second call over the same step finds nothing left to undo.
    EXPECT_EQ(failSafe.rollBack(mesh, bvh, scratch, xs, xe, ve, invMass), 0);
}

class SheetOnSphere : public ::testing::TestWithParam<sim::IntegratorKind> {};

TEST_P(SheetOnSphere, NeverPenetratesBeyondTenPercentOfThickness) {
    sim::SceneSpec s = sheetAbove(0.8, 16, 0.55);
    s.cloths[0].selfCollision = true; // the draped skirt folds onto itself
    s.obstacles.push_back(sphereObstacle(0.25, Vec3(0, 0.25, 0)));
    s.integrator.kind = GetParam();
    if (GetParam() == sim::IntegratorKind::Rk45) {
        s.integrator.dt = 1e-4;
        s.integrator.tolerance = 1e-3;
        s.integrator.maxDt = 1.0 / 120;
    }
    sim::Simulation simulation(s);
    ASSERT_TRUE(simulation.error().empty()) << simulation.error();
    double worst = 0;
    const double until = GetParam() == sim::IntegratorKind::Rk45 ? 0.4 : 0.8;
    const auto status = simulation.run(
        until, [&](int, double) { worst = std::max(worst, simulation.penetration()); });
    ASSERT_EQ(status, sim::RunStatus::Finished) << simulation.stats().error;
    EXPECT_TRUE(simulation.stats().finite);
    EXPECT_LE(worst, 0.1 * 0.003);
    EXPECT_LE(simulation.stats().maxPenetration, 0.1 * 0.003);
    EXPECT_GT(simulation.stats().contacts, 3); // it rests on the sphere
    long withObstacle = -1;
    const long all = test::intersections(simulation, &withObstacle);
    EXPECT_EQ(all, 0);
    EXPECT_EQ(withObstacle, 0);
    // The centre vertex sits on top of the sphere at the contact distance, or a little above
    // where the 5 cm cloth triangles bridge over the faceted sphere's vertices.
    const int centre = 8 * 17 + 8;
    const double top = simulation.positions()(centre, 1);
    EXPECT_GE(top, 0.5 + 0.005 - 0.0003);
    EXPECT_LE(top, 0.5 + 0.005 + 0.006);
}

INSTANTIATE_TEST_SUITE_P(Integrators, SheetOnSphere,
                         ::testing::Values(sim::IntegratorKind::ImplicitEuler,
                                           sim::IntegratorKind::Rk45),
                         [](const auto& info) {
                             return info.param == sim::IntegratorKind::Rk45
                                        ? std::string("rk45")
                                        : std::string("implicit");
                         });

/// Mean position of the cloth's vertices.
Vec3 centroid(const sim::MatX3& x) {
    return x.colwise().mean().transpose();
}

struct SlopeCase {
    double friction;
    sim::IntegratorKind integrator;
};

class SlopeFriction : public ::testing::TestWithParam<SlopeCase> {};

/// A sheet resting on a plane tilted by 20°: displacement along the slope after `t` seconds.
/// `sewingEnd`, `sewingScale`: until then (a sewing phase), friction multiplied by the scale.
double slideOnSlope(double friction, sim::IntegratorKind kind, double t, double* accel,
                    double sewingEnd = -1.0, double sewingScale = 1.0) {
    const double theta = 20.0 * M_PI / 180.0;
    const Vec3 normal(-std::sin(theta), std::cos(theta), 0);
    const Vec3 downhill = -Vec3(std::cos(theta), std::sin(theta), 0);
    sim::SceneSpec s = test::smallSheet(sim::StretchModel::Fem, 6, 0.3, false, true);
    sim::ClothSpec& c = s.cloths[0];
    c.thickness = 0.002;
    c.material.staticFriction = friction;
    c.material.kineticFriction = friction;
    // Lay the sheet on the slope at the contact distance: pattern x along the slope.
    for (int i = 0; i < c.position.rows(); ++i) {
        const double u = c.mesh.rest(i, 0) - 0.15, w = c.mesh.rest(i, 1) - 0.15;
        const Vec3 p = -u * downhill + Vec3(0, 0, -w) + 0.004 * normal;
        c.position.row(i) = p.transpose();
    }
    s.obstacles.push_back(planeObstacle(3.0, Vec3::Zero(), Vec3(0, 0, theta), friction));
    s.integrator.kind = kind;
    s.integrator.dt = kind == sim::IntegratorKind::Rk45 ? 1e-4 : 1.0 / 480;
    s.integrator.maxDt = kind == sim::IntegratorKind::Rk45 ? 1.0 / 240 : 1.0 / 480;
    s.integrator.tolerance = 1e-4;
    sim::Simulation simulation(s);
    EXPECT_TRUE(simulation.error().empty()) << simulation.error();
    simulation.setFrictionScale(sewingScale);
    auto runTo = [&](double time) {
        if (sewingEnd >= 0 && sewingEnd < time) {
            EXPECT_EQ(simulation.run(sewingEnd), sim::RunStatus::Finished);
            simulation.setFrictionScale(1.0); // the sewing phase is over
            sewingEnd = -1;
        }
        EXPECT_EQ(simulation.run(time), sim::RunStatus::Finished) << simulation.stats().error;
    };
    const Vec3 start = centroid(simulation.positions());
    // Let the contact settle for a short while, then measure the acceleration from the
    // displacement between two times (constant acceleration: d = v0 t + a t²/2).
    const double t1 = 0.1;
    runTo(t1);
    const double d1 = (centroid(simulation.positions()) - start).dot(downhill);
    const double v1 = centroid(simulation.velocities()).dot(downhill);
    runTo(t1 + t);
    const double d2 = (centroid(simulation.positions()) - start).dot(downhill);
    if (accel != nullptr) {
        *accel = 2.0 * ((d2 - d1) - v1 * t) / (t * t);
    }
    EXPECT_LE(simulation.stats().maxPenetration, 0.0002);
    return d2;
}

TEST_P(SlopeFriction, HoldsAboveTheThresholdAndSlidesAtTheCoulombRateBelow) {
    const SlopeCase c = GetParam();
    double accel = 0;
    const double moved = slideOnSlope(c.friction, c.integrator, 0.4, &accel);
    const double theta = 20.0 * M_PI / 180.0;
    if (c.friction > std::tan(theta)) {
        EXPECT_LT(std::abs(moved), 1e-3) << "the sheet should stick";
    } else {
        const double expected =
            sim::STANDARD_GRAVITY * (std::sin(theta) - c.friction * std::cos(theta));
        EXPECT_NEAR(accel, expected, 0.05 * expected);
    }
}

INSTANTIATE_TEST_SUITE_P(Cases, SlopeFriction,
                         ::testing::Values(SlopeCase{0.5, sim::IntegratorKind::ImplicitEuler},
                                           SlopeCase{0.2, sim::IntegratorKind::ImplicitEuler},
                                           SlopeCase{0.5, sim::IntegratorKind::Rk45},
                                           SlopeCase{0.2, sim::IntegratorKind::Rk45}),
                         [](const auto& info) {
                             return std::string(info.param.integrator == sim::IntegratorKind::Rk45
                                                    ? "rk45"
                                                    : "implicit") +
                                    (info.param.friction > 0.3 ? "_sticks" : "_slides");
                         });

/// A 0.2 m sheet on a floor, squeezed by a box 7 mm above the floor (it needs 8 mm: its own
/// and the two obstacles' thicknesses), the box sweeping 0.1 m along x in 0.25 s: how far the
/// sheet's centroid moved along x after 0.35 s.
double squeezedSheetMoves(double boxFriction, double floorFriction) {
    sim::SceneSpec s = sheetAbove(0.2, 8, 0.004);
    s.cloths[0].material.staticFriction = 1.0; // the obstacles' coefficients decide
    s.cloths[0].material.kineticFriction = 1.0;
    s.cloths[0].selfCollision = false;
    sim::ObstacleSpec box;
    box.name = "press";
    sim::makeBoxMesh(Vec3(0.6, 0.1, 0.4), 2, box.vertices, box.triangles);
    box.closed = true;
    box.thickness = 0.002;
    box.staticFriction = box.kineticFriction = boxFriction;
    box.keys.push_back(sim::ObstacleKey{0.0, Vec3(0, 0.057, 0), Vec3::Zero()});
    box.keys.push_back(sim::ObstacleKey{0.05, Vec3(0, 0.057, 0), Vec3::Zero()});
    box.keys.push_back(sim::ObstacleKey{0.30, Vec3(0.1, 0.057, 0), Vec3::Zero()});
    s.obstacles.push_back(box);
    s.obstacles.push_back(planeObstacle(2.0, Vec3::Zero(), Vec3::Zero(), floorFriction));
    sim::Simulation simulation(s);
    EXPECT_TRUE(simulation.error().empty()) << simulation.error();
    const Vec3 start = centroid(simulation.positions());
    EXPECT_EQ(simulation.run(0.35), sim::RunStatus::Finished) << simulation.stats().error;
    EXPECT_EQ(simulation.intersectingTrianglePairs(), 0);
    EXPECT_LT(simulation.maxEdgeStrain(), 0.05);
    return (centroid(simulation.positions()) - start).x();
}

TEST(SqueezeFriction, ASqueezedSheetMovesWithTheSurfaceThatGripsHarder) {
    // Pressed by both with the same force, the sheet slides on the surface with the lower
    // coefficient: carried along by a press that grips harder than the floor, left in place
    // by one that grips less.
    EXPECT_NEAR(squeezedSheetMoves(0.8, 0.2), 0.1, 0.01);
    EXPECT_NEAR(squeezedSheetMoves(0.2, 0.8), 0.0, 0.005);
}

TEST(SewingFriction, ScalesFrictionWhileSewingAndRestoresItAfter) {
    const double theta = 20.0 * M_PI / 180.0;
    // μ = 0.5 holds the sheet; while sewing with a scale of 0.4 it slides at the μ = 0.2 rate.
    double accel = 0;
    slideOnSlope(0.5, sim::IntegratorKind::ImplicitEuler, 0.4, &accel, 10.0, 0.4);
    const double expected = sim::STANDARD_GRAVITY * (std::sin(theta) - 0.2 * std::cos(theta));
    EXPECT_NEAR(accel, expected, 0.05 * expected);
    // Sewing over at 0.05 s: the sheet slid while it lasted, then the full friction stops it
    // and holds it: between 0.3 s and 0.5 s it does not move (sliding at the μ = 0.2 rate it
    // would go 12 cm).
    const double at03 =
        slideOnSlope(0.5, sim::IntegratorKind::ImplicitEuler, 0.2, nullptr, 0.05, 0.4);
    const double at05 =
        slideOnSlope(0.5, sim::IntegratorKind::ImplicitEuler, 0.4, nullptr, 0.05, 0.4);
    EXPECT_GT(at03, 1e-3);
    EXPECT_LT(std::abs(at05 - at03), 1e-4);
}

TEST(ContinuousDetection, AFastSheetDoesNotTunnelThroughAThinPlaneAtALargeStep) {
    // 20 m/s toward a plane with one step of 1/60 s: 33 cm per step, a hundred times the
    // thickness. Without the swept test the sheet would pass through in one step.
    sim::SceneSpec s = sheetAbove(0.4, 6, 0.2);
    s.cloths[0].velocity = sim::MatX3::Zero(s.cloths[0].position.rows(), 3);
    s.cloths[0].velocity.col(1).setConstant(-20.0);
    s.gravity = false;
    s.obstacles.push_back(planeObstacle(2.0, Vec3::Zero(), Vec3::Zero(), 0.3));
    s.integrator.dt = 1.0 / 60;
    s.integrator.maxDt = 1.0 / 60;
    sim::Simulation simulation(s);
    ASSERT_TRUE(simulation.error().empty()) << simulation.error();
    ASSERT_EQ(simulation.run(0.1), sim::RunStatus::Finished) << simulation.stats().error;
    EXPECT_GT(simulation.positions().col(1).minCoeff(), 0.0);
    EXPECT_LE(simulation.stats().maxPenetration, 0.0002);
    EXPECT_EQ(simulation.intersectingTrianglePairs(), 0);
    EXPECT_GT(simulation.collision()->figures().continuousHits, 0);

    sim::SceneSpec off = s;
    off.collision.continuous = false;
    sim::Simulation tunnel(off);
    ASSERT_EQ(tunnel.run(0.1), sim::RunStatus::Finished);
    EXPECT_LT(tunnel.positions().col(1).maxCoeff(), 0.0) << "without the swept test it tunnels";
}

TEST(ContactRegions, VerticesPushedThroughALayerGoBackToTheMajoritySide) {
    // Two parallel sheets 4 mm apart (contact distance 4 mm), self-collision on. A few vertices of
    // the upper sheet are moved 1 mm below the lower sheet in one jump (no history, no swept
    // crossing to tell which side they came from). The contact region they belong to votes
    // "above" and puts them back there.
    sim::SceneSpec s = sheetAbove(0.3, 10, 0.0);
    s.gravity = false;
    sim::ClothSpec upper = s.cloths[0];
    for (int i = 0; i < upper.position.rows(); ++i) {
        upper.position(i, 1) = 0.0035;
        upper.position(i, 0) += 0.3 / 20; // offset half a cell so vertices lie over faces
        upper.position(i, 2) -= 0.3 / 20;
    }
    upper.name = "upper";
    s.cloths[0].selfCollision = true;
    upper.selfCollision = true;
    s.cloths.push_back(upper);
    const int n0 = s.cloths[0].mesh.vertexCount();
    const std::vector<int> pushed = {n0 + 5 * 11 + 5, n0 + 5 * 11 + 4, n0 + 4 * 11 + 5};
    for (int p : pushed) {
        s.cloths[1].position(p - n0, 1) = -0.001;
    }
    sim::Simulation simulation(s);
    ASSERT_TRUE(simulation.error().empty()) << simulation.error();
    // The start state has been resolved by the constructor.
    for (int p : pushed) {
        EXPECT_GT(simulation.positions()(p, 1), simulation.positions()(5 * 11 + 5, 1) + 0.0035)
            << "vertex " << p;
    }
    EXPECT_GT(simulation.collision()->figures().regionFlips, 0);
    ASSERT_EQ(simulation.advance(0.05), sim::RunStatus::Finished) << simulation.stats().error;
    EXPECT_EQ(simulation.intersectingTrianglePairs(), 0);
    for (int p : pushed) {
        EXPECT_GT(simulation.positions()(p, 1), simulation.positions()(5 * 11 + 5, 1))
            << "vertex " << p;
    }
}

TEST(TrappedCloth, ComesOutOnItsEntrySideUnstretched) {
    // A horizontal sheet whose first third lies inside a closed capsule (axis y, radius 0.1 m),
    // entering it from +x: the trapped part is carried out toward where the cloth enters, and
    // within 0.3 s nothing stays inside, pierced or stretched. (Sent each to the entry found
    // first by a breadth-first walk, and released to the contacts while still inside, the
    // vertices were pulled apart and the sheet ended stretched.)
    sim::SceneSpec s = sheetAbove(0.3, 12, 1.0);
    for (int i = 0; i < s.cloths[0].position.rows(); ++i) {
        s.cloths[0].position(i, 0) += 0.15 - 0.05; // x from −0.05 to 0.25
    }
    s.cloths[0].selfCollision = false;
    sim::ObstacleSpec capsule;
    capsule.name = "torso";
    sim::makeCapsuleMesh(0.1, 0.4, 24, capsule.vertices, capsule.triangles);
    capsule.closed = true;
    capsule.thickness = 0.003;
    capsule.keys.push_back(sim::ObstacleKey{0.0, Vec3(0, 1.0, 0), Vec3::Zero()});
    s.obstacles.push_back(capsule);
    sim::Simulation simulation(s);
    ASSERT_TRUE(simulation.error().empty()) << simulation.error();
    ASSERT_GT(simulation.collision()->figures().trappedVertices, 10);
    ASSERT_EQ(simulation.run(0.3), sim::RunStatus::Finished) << simulation.stats().error;
    EXPECT_EQ(simulation.collision()->figures().trappedVertices, 0);
    EXPECT_GT(simulation.positions().col(0).minCoeff(), -0.1) << "out on the entry side (+x)";
    long withObstacles = -1;
    test::intersections(simulation, &withObstacles);
    EXPECT_EQ(withObstacles, 0);
    EXPECT_LT(simulation.maxEdgeStrain(), 0.1);
}

TEST(CollisionStage, SeamRoutesGoAroundAClosedObstacle) {
    // A sphere of 10 cm; chords from x = -0.3 to 0.3 at various heights. One through the
    // sphere just above its centre is routed over the top; one through its cap is lifted to
    // the clearance; one that passes within the clearance but outside the sphere is not
    // routed (a seam lying on the body), nor is one clear of it.
    sim::SceneSpec scene = sheetAbove(0.2, 2, 1.0);
    scene.obstacles.push_back(sphereObstacle(0.1, Vec3::Zero()));
    sim::Simulation simulation(scene);
    ASSERT_NE(simulation.collision(), nullptr);
    const sim::CollisionStage& stage = *simulation.collision();
    const double clearance = 0.01;
    Vec3 via;
    ASSERT_TRUE(stage.routeAround(Vec3(-0.3, 0.02, 0), Vec3(0.3, 0.02, 0), clearance, via));
    // Outside by the clearance (the mesh is inscribed in the sphere: within 2 mm of it).
    EXPECT_GE(via.norm(), 0.1 + clearance - 0.002) << via.transpose();
    EXPECT_LT(std::abs(via.x()), 0.01) << via.transpose(); // over the top, not to one end
    EXPECT_GT(via.y(), 0.1) << via.transpose();
    ASSERT_TRUE(stage.routeAround(Vec3(-0.3, 0.095, 0), Vec3(0.3, 0.095, 0), clearance, via));
    EXPECT_GE(via.y(), 0.1 + clearance - 0.002);
    EXPECT_FALSE(stage.routeAround(Vec3(-0.3, 0.105, 0), Vec3(0.3, 0.105, 0), clearance, via));
    EXPECT_FALSE(stage.routeAround(Vec3(-0.3, 0.2, 0), Vec3(0.3, 0.2, 0), clearance, via));
}

TEST(Obstacles, GeneratedShapesAreClosedAndOriented) {
    sim::MatX3 v;
    sim::MatX3i f;
    sim::makeSphereMesh(1.0, 3, v, f);
    EXPECT_TRUE(sim::isClosedOriented(f, static_cast<int>(v.rows())));
    // Outward: the signed volume is positive.
    auto volume = [&]() {
        double vol = 0;
        for (int t = 0; t < f.rows(); ++t) {
            vol += v.row(f(t, 0)).dot(v.row(f(t, 1)).cross(v.row(f(t, 2)))) / 6.0;
        }
        return vol;
    };
    EXPECT_NEAR(volume(), 4.0 / 3.0 * M_PI, 0.05);
    sim::makeBoxMesh(Vec3(1, 2, 3), 2, v, f);
    EXPECT_TRUE(sim::isClosedOriented(f, static_cast<int>(v.rows())));
    EXPECT_NEAR(volume(), 6.0, 1e-12);
    sim::makeCapsuleMesh(0.5, 1.0, 24, v, f);
    EXPECT_TRUE(sim::isClosedOriented(f, static_cast<int>(v.rows())));
    EXPECT_NEAR(volume(), M_PI * 0.25 * 1.0 + 4.0 / 3.0 * M_PI * 0.125, 0.05);
    EXPECT_GT(volume(), 0);
    // Length 0: a latitude–longitude sphere, with no degenerate band at the equator.
    sim::makeCapsuleMesh(0.5, 0.0, 48, v, f);
    EXPECT_TRUE(sim::isClosedOriented(f, static_cast<int>(v.rows())));
    EXPECT_NEAR(volume(), 4.0 / 3.0 * M_PI * 0.125, 0.01);
    for (int t = 0; t < f.rows(); ++t) {
        const Vec3 a = v.row(f(t, 0)), b = v.row(f(t, 1)), c = v.row(f(t, 2));
        EXPECT_GT((b - a).cross(c - a).norm(), 1e-6) << "triangle " << t;
    }
    sim::makePlaneMesh(2.0, 3, v, f);
    EXPECT_FALSE(sim::isClosedOriented(f, static_cast<int>(v.rows())));
    for (int t = 0; t < f.rows(); ++t) {
        const Vec3 n =
            (v.row(f(t, 1)) - v.row(f(t, 0))).cross(v.row(f(t, 2)) - v.row(f(t, 0))).transpose();
        EXPECT_GT(n.y(), 0) << "plane normals face +Y";
    }
}

TEST(Obstacles, RigidKeysInterpolateTranslationAndManyTurns) {
    sim::ObstacleSpec o;
    o.vertices.resize(1, 3);
    o.vertices.row(0) << 1, 0, 0;
    o.triangles.resize(0, 3);
    o.keys.push_back(sim::ObstacleKey{0.0, Vec3(0, 1, 0), Vec3::Zero()});
    o.keys.push_back(sim::ObstacleKey{2.0, Vec3(0, 1, 0), Vec3(0, 4 * M_PI, 0)});
    sim::MatX3 x;
    sim::obstaclePositionsAt(o, 0.25, x); // a quarter turn about +Y: x → −z
    EXPECT_NEAR(x(0, 0), 0.0, 1e-12);
    EXPECT_NEAR(x(0, 1), 1.0, 1e-12);
    EXPECT_NEAR(x(0, 2), -1.0, 1e-12);
    sim::obstaclePositionsAt(o, 1.0, x); // two full turns
    EXPECT_NEAR(x(0, 0), 1.0, 1e-12);
    EXPECT_TRUE(sim::obstacleMoves(o));
}

} // namespace
} // namespace atelier
