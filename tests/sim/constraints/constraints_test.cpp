// Kinematic corrections: pins (A + B), drives (exact and tracker-following), seam elastics (C)
// and high damping (A, purely dissipative); and the pipeline holds only the stages a scene needs.

#include "sim/collision/obstacle.h"
#include "sim/constraints/kinematic.h"
#include "sim/simulation.h"
#include "sim/test_scenes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace atelier::sim {
namespace {

bool hasStage(const Simulation& s, const std::string& name) {
    const auto st = s.activeStages();
    return std::find(st.begin(), st.end(), name) != st.end();
}

TEST(Constraints, PinsHoldExactly) {
    SceneSpec scene = test::smallSheet(StretchModel::Fem, 4, 1.0, true, true);
    scene.integrator.kind = IntegratorKind::Rk45;
    const MatX3 start = scene.cloths[0].position;
    Simulation sim(scene);
    ASSERT_EQ(sim.run(0.5), RunStatus::Finished) << sim.error();
    for (int p : scene.pins) {
        EXPECT_EQ((sim.positions().row(p) - start.row(p)).norm(), 0.0);
        EXPECT_EQ(sim.velocities().row(p).norm(), 0.0);
    }
    // The rest fell.
    EXPECT_LT(sim.positions().col(1).minCoeff(), start.col(1).minCoeff() - 0.01);
}

TEST(Constraints, ExactDriveFollowsItsPathThenReleases) {
    SceneSpec scene = test::smallSheet(StretchModel::Volino, 4);
    scene.integrator.kind = IntegratorKind::ImplicitEuler;
    scene.integrator.dt = 1e-3;
    Drive d;
    d.vertex = 0; // bottom-left corner
    const Vec3 p0 = scene.cloths[0].position.row(0).transpose();
    d.times = {0.0, 0.2};
    d.positions = {p0, p0 + Vec3(0, 0, 0.3)};
    d.releaseTime = 0.3;
    scene.drives.push_back(d);
    Simulation sim(scene);
    ASSERT_TRUE(hasStage(sim, "constraints.drives"));
    ASSERT_EQ(sim.advance(0.1), RunStatus::Finished) << sim.error();
    EXPECT_NEAR((sim.positions().row(0).transpose() - (p0 + Vec3(0, 0, 0.15))).norm(), 0.0, 1e-12);
    ASSERT_EQ(sim.advance(0.15), RunStatus::Finished);
    EXPECT_NEAR((sim.positions().row(0).transpose() - (p0 + Vec3(0, 0, 0.3))).norm(), 0.0, 1e-12);
    ASSERT_EQ(sim.advance(0.5), RunStatus::Finished);
    // Released at 0.3 s: the corner has swung away from where the drive left it.
    EXPECT_GT((sim.positions().row(0).transpose() - (p0 + Vec3(0, 0, 0.3))).norm(), 0.05);
}

TEST(Constraints, TrackerDriveSmoothsNoisyInput) {
    // A grab fed by a noisy tracker (±5 cm jitter at 60 Hz) follows through a critically damped
    // elastic: it stays finite and close to the mean path, and moves less than the raw input.
    SceneSpec scene = test::smallSheet(StretchModel::Fem, 4);
    scene.integrator.kind = IntegratorKind::Rk45;
    Drive d;
    d.vertex = 0;
    d.followTimeConstant = 0.05;
    const Vec3 p0 = scene.cloths[0].position.row(0).transpose();
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> noise(-0.05, 0.05);
    double inputPath = 0;
    Vec3 previous = p0;
    for (int k = 0; k <= 60; ++k) {
        d.times.push_back(k / 60.0);
        const Vec3 p = p0 + Vec3(0.5 * k / 60.0, 0, 0) + Vec3(noise(rng), noise(rng), noise(rng));
        inputPath += (p - previous).norm();
        previous = p;
        d.positions.push_back(p);
    }
    scene.drives.push_back(d);
    Simulation sim(scene);
    double outputPath = 0;
    Vec3 last = p0;
    ASSERT_EQ(sim.run(1.0,
                      [&](int, double) {
                          outputPath += (sim.positions().row(0).transpose() - last).norm();
                          last = sim.positions().row(0).transpose();
                      }),
              RunStatus::Finished)
        << sim.error();
    EXPECT_TRUE(sim.positions().allFinite());
    EXPECT_LT((sim.positions().row(0).transpose() - (p0 + Vec3(0.5, 0, 0))).norm(), 0.1);
    EXPECT_LT(outputPath, 0.5 * inputPath);
}

TEST(Constraints, SeamElasticsCloseWithTheirTimeConstant) {
    // Two free vertices of two separate sheets (no gravity, no stiffness coupling between them):
    // the gap closes like (1 + t/τ) e^(−t/τ), independent of mass.
    SceneSpec scene = test::smallSheet(StretchModel::Fem, 2, 0.2, false);
    ClothSpec second = scene.cloths[0];
    second.position.col(2).array() += 0.1;
    second.material.density *= 3.0; // masses differ: the closing must not depend on them
    scene.cloths.push_back(second);
    scene.gravity = false;
    const int a = 4;     // centre of the first sheet
    const int b = 9 + 4; // centre of the second
    scene.seams.push_back({a, b});
    scene.seamTimeConstant = 0.05;
    scene.integrator.kind = IntegratorKind::Rk45;
    scene.integrator.tolerance = 1e-7;
    Simulation sim(scene);
    ASSERT_TRUE(hasStage(sim, "seams"));
    const double gap0 = (sim.positions().row(a) - sim.positions().row(b)).norm();
    ASSERT_EQ(sim.advance(0.05), RunStatus::Finished) << sim.error();
    const double gap = (sim.positions().row(a) - sim.positions().row(b)).norm();
    // The sheets' own elasticity pulls the seamed vertices back a little: allow 15%.
    EXPECT_NEAR(gap / gap0, 2.0 * std::exp(-1.0), 0.15);
    ASSERT_EQ(sim.advance(0.45), RunStatus::Finished);
    EXPECT_LT((sim.positions().row(a) - sim.positions().row(b)).norm(), 0.1 * gap0);
    // Momentum is conserved (no gravity, no pins).
    const Vec3 momentum =
        (sim.velocities().array().colwise() * sim.masses().array()).colwise().sum();
    EXPECT_LT(momentum.norm(), 1e-9);
}

TEST(Constraints, ClosedSeamsWeldAndStayClosedUnderLoad) {
    // Sheet B hangs from sheet A by a seam along their facing edges, started 2 cm apart. The
    // elastics close the gap; once below the weld distance each pair moves as one vertex, so
    // B's weight cannot reopen the seam. Imposed seams close whatever the load (elastic ones
    // would be held open by B's weight, ~g·τ²·m_B/μ).
    const int cells = 4;
    SceneSpec scene = test::smallSheet(StretchModel::Fem, cells, 0.2, true);
    ClothSpec b = scene.cloths[0];
    b.name = "b";
    b.position.col(0).array() += 0.22;
    b.selfCollision = true;
    scene.cloths[0].selfCollision = true;
    scene.cloths.push_back(b);
    scene.pins = {cells * (cells + 1)}; // A's top-left corner only: the seam carries B
    const int nA = (cells + 1) * (cells + 1);
    for (int j = 0; j <= cells; ++j) {
        scene.seams.push_back({j * (cells + 1) + cells, nA + j * (cells + 1)});
    }
    scene.seamTimeConstant = 0.02;
    scene.seamMode = SeamMode::Imposed;
    scene.seamWeldDistance = 1e-3;
    for (IntegratorKind kind : {IntegratorKind::Rk45, IntegratorKind::ImplicitEuler}) {
        SCOPED_TRACE(std::string(integratorName(kind)));
        scene.integrator.kind = kind;
        scene.integrator.dt = kind == IntegratorKind::ImplicitEuler ? 2e-3 : 1e-4;
        Simulation sim(scene);
        ASSERT_TRUE(hasStage(sim, "constraints.seams"));
        ASSERT_TRUE(hasStage(sim, "constraints.seam-welds"));
        ASSERT_EQ(sim.advance(1.0), RunStatus::Finished) << sim.error();
        EXPECT_EQ(sim.stats().weldedSeamPairs, cells + 1);
        for (const SeamPair& p : scene.seams) {
            EXPECT_EQ((sim.positions().row(p.a) - sim.positions().row(p.b)).norm(), 0.0);
        }
        // B hangs below A's pin; the triangles meeting at the seam are not taken as crossing.
        EXPECT_LT(sim.positions().col(1).segment(nA, nA).maxCoeff(), 0.2 + 1e-9);
        EXPECT_EQ(sim.intersectingTrianglePairs(), 0);
        EXPECT_TRUE(sim.stats().finite);
    }
}

/// Two 0.2 m sheets of `cells`² cells side by side, `gap` apart along x, no gravity, the right
/// edge of the first sewn to the left edge of the second by elastic seams that weld below 1 mm;
/// implicit Euler at 10 ms.
SceneSpec twoSheetsSewn(int cells, double gap) {
    SceneSpec scene = test::smallSheet(StretchModel::Fem, cells, 0.2, false);
    ClothSpec b = scene.cloths[0];
    b.name = "b";
    b.position.col(0).array() += 0.2 + gap;
    scene.cloths.push_back(b);
    scene.gravity = false;
    const int nA = (cells + 1) * (cells + 1);
    for (int j = 0; j <= cells; ++j) {
        scene.seams.push_back({j * (cells + 1) + cells, nA + j * (cells + 1)});
    }
    scene.seamMode = SeamMode::Elastic;
    scene.seamWeldDistance = 1e-3;
    scene.integrator.kind = IntegratorKind::ImplicitEuler;
    scene.integrator.dt = 1e-2;
    return scene;
}

TEST(Constraints, SewingPhaseEndsWithEverySeamWelded) {
    // Elastic seams, slow to close (τ = 1 s), between two sheets 2 cm apart with no gravity:
    // at the sewing deadline every pair is welded whatever its gap, and the largest such gap
    // is reported.
    const int cells = 3;
    SceneSpec scene = twoSheetsSewn(cells, 0.02);
    scene.seamTimeConstant = 1.0;
    Simulation sim(scene);
    sim.setSewingDeadline(0.05);
    ASSERT_TRUE(hasStage(sim, "constraints.seam-welds"));
    ASSERT_EQ(sim.advance(0.04), RunStatus::Finished) << sim.error();
    EXPECT_EQ(sim.stats().weldedSeamPairs, 0);
    const double gapBefore =
        (sim.positions().row(scene.seams[0].a) - sim.positions().row(scene.seams[0].b)).norm();
    EXPECT_GT(gapBefore, 0.015); // still open: the elastic is slow
    ASSERT_EQ(sim.advance(0.06), RunStatus::Finished) << sim.error() << sim.stats().error;
    EXPECT_EQ(sim.stats().weldedSeamPairs, cells + 1);
    for (const SeamPair& p : scene.seams) {
        EXPECT_EQ((sim.positions().row(p.a) - sim.positions().row(p.b)).norm(), 0.0);
    }
    EXPECT_GT(sim.stats().largestForcedWeld, 0.015);
    EXPECT_LT(sim.stats().largestForcedWeld, 0.02 + 1e-9);
    EXPECT_TRUE(sim.stats().finite);
}

TEST(Constraints, AGrowingReachClosesSeamsBeforeTheForcedWeld) {
    // Two sheets 10 cm apart, no gravity, seams saturated at a 5 mm reach: the constant pull
    // closes the gap at about reach/(2τ) = 5 cm/s at best (the sheets' inertia slows it), too
    // slowly for a 1 s sewing phase. With the reach growing twentyfold over the phase the pairs
    // close and weld by themselves before it ends.
    const int cells = 3;
    auto run = [&](bool grow, std::vector<double>& gaps) {
        SceneSpec scene = twoSheetsSewn(cells, 0.1);
        scene.seamTimeConstant = 0.05;
        scene.seamReach = 0.005;
        Simulation sim(scene);
        sim.setSewingDeadline(1.0);
        while (sim.time() < 1.1 - 1e-12) {
            if (grow) { // the reach grows linearly to 20 times over the phase
                sim.setSeamReach(scene.seamReach * (1.0 + 19.0 * std::min(sim.time(), 1.0)));
            }
            EXPECT_EQ(sim.step(1.1), RunStatus::Finished) << sim.error() << sim.stats().error;
        }
        EXPECT_TRUE(sim.stats().finite);
        EXPECT_EQ(sim.stats().weldedSeamPairs, cells + 1);
        gaps = sim.stats().forcedWeldGaps;
        return sim.stats().largestForcedWeld;
    };
    std::vector<double> constant, growing;
    const double forcedConstant = run(false, constant);
    const double forcedGrowing = run(true, growing);
    EXPECT_GT(forcedConstant, 0.03);
    ASSERT_EQ(constant.size(), static_cast<std::size_t>(cells + 1));
    for (double g : constant) {
        EXPECT_GT(g, 0.03); // every pair still open when sewing ended
    }
    EXPECT_EQ(forcedGrowing, 0.0);
    for (double g : growing) {
        EXPECT_EQ(g, 0.0);
    }
}

TEST(Constraints, SeamBlockedByABodyIsLedAroundIt) {
    // Two small sheets face each other across a sphere; their top rows are sewn, and each
    // pair's chord runs through the sphere, just above its centre. Pulled straight, the
    // sheets press on the sphere where a little friction holds them; routed, each pair is led
    // over the sphere and closes. Routing is for the sewing phase, in which garments turn
    // friction off (sewingFrictionScale 0); μ = 0.05 is the friction that tells the two
    // apart (measured: with none the straight pull also slides round the sphere, and against
    // μ = 0.1 the routed pull stops 2 cm short, at 0.5 7–9 cm short, like a rope over a post).
    const int cells = 4;
    SceneSpec scene = test::smallSheet(StretchModel::Fem, cells, 0.1, false);
    scene.cloths[0].position.col(0).array() -= 0.05;
    scene.cloths[0].position.col(1).array() -= 0.08; // top row at y = 0.02
    ClothSpec back = scene.cloths[0];
    back.name = "back";
    scene.cloths[0].position.col(2).array() += 0.13;
    back.position.col(2).array() -= 0.13;
    scene.cloths.push_back(back);
    const int n = (cells + 1) * (cells + 1);
    for (int i = 0; i <= cells; ++i) {
        scene.seams.push_back({cells * (cells + 1) + i, n + cells * (cells + 1) + i});
    }
    ObstacleSpec sphere;
    sphere.name = "sphere";
    makeSphereMesh(0.1, 3, sphere.vertices, sphere.triangles);
    sphere.closed = true;
    sphere.staticFriction = 0.05;
    sphere.kineticFriction = 0.05;
    scene.obstacles.push_back(sphere);
    scene.gravity = false;
    scene.seamTimeConstant = 0.03;
    scene.seamMode = SeamMode::Elastic;
    scene.seamWeldDistance = 1e-3;
    scene.integrator.kind = IntegratorKind::ImplicitEuler;
    scene.integrator.dt = 5e-3;
    auto largestGap = [&](const Simulation& sim) {
        double gap = 0;
        for (const SeamPair& p : scene.seams) {
            gap = std::max(gap, (sim.positions().row(p.a) - sim.positions().row(p.b)).norm());
        }
        return gap;
    };
    {
        Simulation straight(scene);
        ASSERT_EQ(straight.advance(1.0), RunStatus::Finished) << straight.error();
        EXPECT_GT(largestGap(straight), 0.1);
        EXPECT_EQ(straight.stats().weldedSeamPairs, 0);
    }
    scene.seamRouteClearance = 0.01;
    Simulation routed(scene);
    ASSERT_EQ(routed.advance(1.0), RunStatus::Finished) << routed.error();
    EXPECT_EQ(routed.stats().weldedSeamPairs, cells + 1);
    EXPECT_EQ(largestGap(routed), 0.0);
    EXPECT_TRUE(routed.stats().finite);
    EXPECT_EQ(routed.intersectingTrianglePairs(), 0);
}

TEST(Constraints, GravityHeldUntilTheDeadline) {
    // A free sheet stays put while gravity is held (a sewing phase), then falls with g from
    // the deadline, where steps stop.
    SceneSpec scene = test::smallSheet(StretchModel::Fem, 2, 0.2, false);
    for (IntegratorKind kind : {IntegratorKind::Rk45, IntegratorKind::ImplicitEuler}) {
        scene.integrator.kind = kind;
        SCOPED_TRACE(std::string(integratorName(kind)));
        scene.integrator.dt = 0.007; // not a divisor of the deadline: steps must stop there
        Simulation sim(scene);
        sim.setGravity(false);
        sim.setSewingDeadline(0.1);
        while (sim.time() < 0.1 - 1e-12) {
            ASSERT_EQ(sim.step(), RunStatus::Finished) << sim.error();
        }
        EXPECT_NEAR(sim.time(), 0.1, 1e-15);
        EXPECT_EQ(sim.velocities().norm(), 0.0);
        sim.setGravity(true);
        sim.setSewingDeadline(-1);
        ASSERT_EQ(sim.advance(0.05), RunStatus::Finished) << sim.error();
        // Internal forces sum to zero: the momentum shows gravity alone, acting for 0.05 s.
        const double meanVy = sim.masses().dot(sim.velocities().col(1)) / sim.masses().sum();
        EXPECT_NEAR(meanVy, -STANDARD_GRAVITY * 0.05, 1e-9);
    }
}

TEST(Constraints, HighDampingIsPurelyDissipativeAndConservesMomentum) {
    std::mt19937 rng(3);
    std::normal_distribution<double> n01;
    const int n = 30;
    MatX3 v(n, 3);
    for (int i = 0; i < n; ++i) {
        v.row(i) << n01(rng), n01(rng), n01(rng);
    }
    VecX invMass(n);
    for (int i = 0; i < n; ++i) {
        invMass[i] = 1.0 / (0.5 + std::abs(n01(rng)));
    }
    std::vector<std::array<int, 2>> edges;
    for (int i = 0; i + 1 < n; ++i) {
        edges.push_back({i, i + 1});
        edges.push_back({i, (i * 7 + 3) % n});
    }
    auto energy = [&](const MatX3& w) {
        double e = 0;
        for (int i = 0; i < n; ++i) {
            e += 0.5 * w.row(i).squaredNorm() / invMass[i];
        }
        return e;
    };
    auto momentum = [&](const MatX3& w) {
        Vec3 p = Vec3::Zero();
        for (int i = 0; i < n; ++i) {
            p += w.row(i).transpose() / invMass[i];
        }
        return p;
    };
    for (double tau : {1e-6, 1e-3, 1.0}) { // far below, at and far above the step
        MatX3 w = v;
        double before = energy(w);
        const Vec3 p = momentum(w);
        for (int k = 0; k < 20; ++k) {
            applyHighDamping(edges, invMass, 1e-3, tau, w);
            const double after = energy(w);
            EXPECT_LE(after, before + 1e-12) << "tau " << tau;
            before = after;
        }
        EXPECT_LT((momentum(w) - p).norm(), 1e-9) << "tau " << tau;
        EXPECT_TRUE(w.allFinite());
    }
}

TEST(Pipeline, HoldsOnlyTheStagesTheSceneNeeds) {
    SceneSpec bare = test::smallSheet(StretchModel::Springs, 2, 1.0, false);
    bare.gravity = false;
    bare.cloths[0].bending = false;
    Simulation plain(bare);
    EXPECT_EQ(plain.activeStages(), (std::vector<std::string>{"stretch.springs", "integrator.rk45",
                                                              "step-control.error-estimate"}));

    SceneSpec full = test::smallSheet(StretchModel::Fem, 2);
    full.air.enabled = true;
    full.highDampingTimeConstant = 0.1;
    full.integrator.kind = IntegratorKind::ImplicitEuler;
    Simulation rich(full);
    for (const char* s : {"constraints.pins", "constraints.high-damping", "stretch.fem", "bending",
                          "air", "gravity", "integrator.implicit-euler"}) {
        EXPECT_TRUE(hasStage(rich, s)) << s;
    }
    EXPECT_FALSE(hasStage(rich, "seams"));
    EXPECT_FALSE(hasStage(rich, "constraints.drives"));
}

TEST(StepControl, DtFloorStopsWithAClearErrorAndAFiniteState) {
    // Euler far beyond its stability limit, with a floor it cannot get under: the run stops
    // with an error naming the floor, never with NaN.
    SceneSpec scene = test::smallSheet(StretchModel::Fem, 6);
    scene.cloths[0].material.stretchWeft = scene.cloths[0].material.stretchWarp = 1e6;
    scene.integrator.kind = IntegratorKind::Euler;
    scene.integrator.dt = 1e-2;
    scene.integrator.minDt = 1e-3;
    Simulation sim(scene);
    EXPECT_EQ(sim.run(1.0), RunStatus::Failed);
    EXPECT_NE(sim.error().find("floor"), std::string::npos) << sim.error();
    EXPECT_TRUE(sim.positions().allFinite());
    EXPECT_TRUE(sim.stats().finite);
}

TEST(Validation, RefusesBadScenesNamingTheProblem) {
    SceneSpec scene = test::smallSheet(StretchModel::Fem, 2);
    scene.cloths[0].material.density = -1;
    auto e = Simulation::validate(scene);
    ASSERT_TRUE(e.has_value());
    EXPECT_NE(e->find("density"), std::string::npos);

    scene = test::smallSheet(StretchModel::Fem, 2);
    scene.pins.push_back(1000);
    e = Simulation::validate(scene);
    ASSERT_TRUE(e.has_value());
    EXPECT_NE(e->find("1000"), std::string::npos);

    // Inverted rest triangle: refused when the mesh is built, naming it.
    MatX2 rest(3, 2);
    rest << 0, 0, 0, 1, 1, 0; // clockwise
    MatX3i tris(1, 3);
    tris << 0, 1, 2;
    ClothMesh mesh;
    const auto err = buildClothMesh(rest, tris, mesh);
    ASSERT_TRUE(err.has_value());
    EXPECT_NE(err->find("triangle 0"), std::string::npos);
}

} // namespace
} // namespace atelier::sim
