#include "sim/forces/bending.h"
#include "sim/forces/force_check.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace atelier::sim {
namespace {

using test::PlacedCloth;

Material bendingMaterial() {
    Material m;
    m.bending = 2e-4;
    m.damping = 0.02;
    return m;
}

/// Two triangles sharing the edge (0, 1) along x: vertex 2 above it, vertex 3 below, in the
/// pattern. The hinge is (0, 1, 2, 3).
ClothMesh hingePair(double length = 0.1, double h0 = 0.08, double h1 = 0.05) {
    MatX2 rest(4, 2);
    rest << 0, 0, length, 0, 0.3 * length, h0, 0.6 * length, -h1;
    MatX3i tri(2, 3);
    tri << 0, 1, 2, 1, 0, 3;
    ClothMesh mesh;
    const auto error = buildClothMesh(rest, tri, mesh);
    EXPECT_FALSE(error.has_value());
    return mesh;
}

/// The pair with wing 3 rotated about the edge by `phi` (towards −z for phi > 0).
MatX3 foldedPair(const ClothMesh& mesh, double phi, int offset, int total) {
    MatX3 x = MatX3::Zero(total, 3);
    for (int i = 0; i < 4; ++i) {
        x.row(offset + i) << mesh.rest(i, 0), mesh.rest(i, 1), 0;
    }
    const double y = mesh.rest(3, 1);
    x.row(offset + 3) << mesh.rest(3, 0), y * std::cos(phi), -std::abs(y) * std::sin(phi);
    return x;
}

std::array<Vec3, 4> randomHinge(std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-1, 1);
    std::array<Vec3, 4> x;
    for (auto& p : x) {
        p = Vec3(u(rng), u(rng), u(rng));
    }
    return x;
}

TEST(DihedralAngle, SignConventionAndRange) {
    const Vec3 x0(0, 0, 0);
    const Vec3 x1(1, 0, 0);
    const Vec3 x2(0.3, 1, 0);
    const Vec3 x3(0.6, -1, 0);
    EXPECT_EQ(dihedralAngle(x0, x1, x2, x3), 0.0);
    for (double phi : {0.1, 1.0, 2.5, 3.0, -0.7, -2.9}) {
        // Rotate wing 3 about the edge: towards −n₀ = −z for phi > 0.
        const Vec3 y3(0.6, -std::cos(phi), -std::sin(phi));
        EXPECT_NEAR(dihedralAngle(x0, x1, x2, y3), phi, 1e-12) << phi;
        // Rotating wing 2 the other way folds the same.
        const Vec3 y2(0.3, std::cos(phi), -std::sin(phi));
        EXPECT_NEAR(dihedralAngle(x0, x1, y2, x3), phi, 1e-12) << phi;
    }
    // Degenerate: zero edge.
    EXPECT_EQ(dihedralAngle(x0, x0, x2, x3), 0.0);
}

TEST(DihedralAngle, GradientAndHessianMatchFiniteDifferences) {
    std::mt19937 rng(3);
    const double h = 1e-6;
    for (int trial = 0; trial < 50; ++trial) {
        const auto x = randomHinge(rng);
        std::array<Vec3, 4> g;
        ASSERT_TRUE(dihedralAngleGradient(x, g));
        Eigen::Matrix<double, 12, 12> H;
        ASSERT_TRUE(dihedralAngleHessian(x, H));
        double gradScale = 0;
        double hessScale = H.cwiseAbs().maxCoeff();
        for (auto& gi : g) {
            gradScale = std::max(gradScale, gi.cwiseAbs().maxCoeff());
        }
        for (int a = 0; a < 4; ++a) {
            for (int k = 0; k < 3; ++k) {
                auto xp = x;
                auto xm = x;
                xp[static_cast<std::size_t>(a)][k] += h;
                xm[static_cast<std::size_t>(a)][k] -= h;
                const double dp = dihedralAngle(xp[0], xp[1], xp[2], xp[3]);
                const double dm = dihedralAngle(xm[0], xm[1], xm[2], xm[3]);
                // Skip the ±π branch cut.
                if (std::abs(dp - dm) < 1.0) {
                    EXPECT_NEAR(g[static_cast<std::size_t>(a)][k], (dp - dm) / (2 * h),
                                1e-6 * gradScale);
                }
                std::array<Vec3, 4> gp;
                std::array<Vec3, 4> gm;
                dihedralAngleGradient(xp, gp);
                dihedralAngleGradient(xm, gm);
                for (int b = 0; b < 4; ++b) {
                    const Vec3 col =
                        (gp[static_cast<std::size_t>(b)] - gm[static_cast<std::size_t>(b)]) /
                        (2 * h);
                    for (int l = 0; l < 3; ++l) {
                        EXPECT_NEAR(H(3 * b + l, 3 * a + k), col[l], 1e-5 * hessScale);
                    }
                }
            }
        }
    }
}

TEST(DihedralAngle, DegenerateHingesGiveZeroGradient) {
    const Vec3 o(0, 0, 0);
    const Vec3 e(1, 0, 0);
    std::array<Vec3, 4> g;
    Eigen::Matrix<double, 12, 12> H;
    // Collapsed edge, and a wing lying on the edge line.
    for (const auto& x : {std::array<Vec3, 4>{o, o, Vec3(0, 1, 0), Vec3(0, -1, 0)},
                          std::array<Vec3, 4>{o, e, Vec3(0.5, 0, 0), Vec3(0, -1, 0)},
                          std::array<Vec3, 4>{o, o, o, o}}) {
        EXPECT_FALSE(dihedralAngleGradient(x, g));
        EXPECT_FALSE(dihedralAngleHessian(x, H));
        for (const auto& gi : g) {
            EXPECT_TRUE(gi.isZero(0.0));
        }
        EXPECT_TRUE(H.isZero(0.0));
        EXPECT_TRUE(std::isfinite(dihedralAngle(x[0], x[1], x[2], x[3])));
    }
}

class DihedralBendingTest : public ::testing::TestWithParam<Triangulation> {};

TEST_P(DihedralBendingTest, PassesForceChecks) {
    const PlacedCloth c = test::placeCloth(test::makeTestMesh(GetParam()));
    const DihedralBending model(c.mesh, c.offset, bendingMaterial(), VecX(), false);
    test::ForceCheckOptions o;
    o.restTolerance = 1e-14;
    for (std::uint32_t seed : {1u, 2u}) {
        SCOPED_TRACE("seed " + std::to_string(seed));
        const auto [x, v] = test::randomState(c, 0.03, 0.5, seed);
        test::checkForceModel(model, c, x, v, o);
    }
}

TEST_P(DihedralBendingTest, PassesForceChecksWithRestAngles) {
    const PlacedCloth c = test::placeCloth(test::makeTestMesh(GetParam()));
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    VecX rest(c.mesh.hinges.rows());
    for (auto& r : rest) {
        r = u(rng);
    }
    const DihedralBending model(c.mesh, c.offset, bendingMaterial(), rest, true);
    const auto [x, v] = test::randomState(c, 0.03, 0.5, 6);
    test::expectForcesAreEnergyGradient(model, x, 1e-6, 1e-5);
    test::expectExactJacobianMatchesFiniteDifferences(model, x, v, 1e-6, 1e-5);
    test::expectDefiniteJacobian(model, x, v);
    test::expectRigidInvariance(model, x, v, 8, 1e-9);
    test::expectMomentumConserved(model, x, v, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Meshes, DihedralBendingTest,
                         ::testing::Values(Triangulation::Regular, Triangulation::Irregular));

TEST(DihedralBending, FoldedPairEnergyFollowsTheDocumentedFormula) {
    const ClothMesh mesh = hingePair(0.1, 0.08, 0.05);
    ASSERT_EQ(mesh.hinges.rows(), 1);
    ASSERT_EQ(mesh.hinges(0, 0), 0);
    ASSERT_EQ(mesh.hinges(0, 1), 1);
    ASSERT_EQ(mesh.hinges(0, 2), 2);
    ASSERT_EQ(mesh.hinges(0, 3), 3);
    Material m = bendingMaterial();
    const DihedralBending model(mesh, 1, m, VecX(), false);
    // w = 3|ē|²/(Ā₀+Ā₁), Ā_i = ½|ē|h_i.
    const double w = 3 * 0.1 * 0.1 / (0.5 * 0.1 * 0.08 + 0.5 * 0.1 * 0.05);
    EXPECT_NEAR(model.weights()[0], w, 1e-12 * w);
    for (double phi : {0.2, -0.9, 2.0}) {
        const MatX3 x = foldedPair(mesh, phi, 1, 6);
        EXPECT_NEAR(model.angle(x, 0), phi, 1e-12);
        EXPECT_NEAR(model.energy(x), m.bending * w * (1.0 - std::cos(phi)), 1e-12 * m.bending * w);
        // Moment about the edge: the force on the folded wing tip is k·w·sin θ/h₁ against the
        // fold (≈ k·w·θ/h₁ for small folds).
        const MatX3 f = test::forces(model, x, MatX3::Zero(6, 3));
        EXPECT_NEAR(f.row(1 + 3).norm(), m.bending * w * std::abs(std::sin(phi)) / 0.05,
                    1e-9 * m.bending * w / 0.05);
    }
}

TEST(DihedralBending, CylinderEnergyMatchesTheContinuumOnARegularGrid) {
    // Rolling the pattern about the warp axis with radius R bends only along weft. The
    // continuum energy is ½ k A / R². On the grid only the warp-parallel hinges fold, each by
    // θ = h_x/R with weight 3h_y/h_x: 3× the continuum per interior strip (19 of 20 strips),
    // the mesh factor documented on DihedralBending.
    const ClothMesh mesh = test::makeTestMesh(Triangulation::Regular, 20, 20, 0.2, 0.2);
    const Material m = bendingMaterial();
    const DihedralBending model(mesh, 0, m, VecX(), false);
    const double radius = 0.5;
    MatX3 x(mesh.vertexCount(), 3);
    for (int i = 0; i < mesh.vertexCount(); ++i) {
        const double a = mesh.rest(i, 0) / radius;
        x.row(i) << radius * std::sin(a), mesh.rest(i, 1), radius * (1 - std::cos(a));
    }
    const double continuum = 0.5 * m.bending * 0.2 * 0.2 / (radius * radius);
    const double ratio = model.energy(x) / continuum;
    EXPECT_NEAR(ratio, 3.0 * 19.0 / 20.0, 0.01);
}

TEST(DihedralBending, RestAnglesAreHonoured) {
    const ClothMesh mesh = hingePair();
    const double phi = 0.6;
    VecX rest(1);
    rest << phi;
    const DihedralBending model(mesh, 0, bendingMaterial(), rest, false);
    const MatX3 folded = foldedPair(mesh, phi, 0, 4);
    EXPECT_NEAR(model.energy(folded), 0.0, 1e-20);
    test::expectZeroForce(model, folded, MatX3::Zero(4, 3), 1e-15);
    // Flat is now strained.
    EXPECT_GT(model.energy(foldedPair(mesh, 0.0, 0, 4)), 0.0);

    // A rectangle folded along the grid line X = 0.2 (a line of vertical edges).
    const PlacedCloth c = test::placeCloth(test::makeTestMesh(Triangulation::Regular));
    MatX3 x = test::restPositions(c);
    const double fold = 0.8;
    for (int i = 0; i < c.mesh.vertexCount(); ++i) {
        const double X = c.mesh.rest(i, 0) - 0.2;
        if (X > 0) {
            x.row(c.offset + i) << 0.2 + X * std::cos(fold), c.mesh.rest(i, 1), X * std::sin(fold);
        }
    }
    const DihedralBending flat(c.mesh, c.offset, bendingMaterial(), VecX(), false);
    VecX angles(c.mesh.hinges.rows());
    int onFold = 0;
    for (int h = 0; h < angles.size(); ++h) {
        angles[h] = flat.angle(x, h);
        const bool onLine = std::abs(c.mesh.rest(c.mesh.hinges(h, 0), 0) - 0.2) < 1e-12 &&
                            std::abs(c.mesh.rest(c.mesh.hinges(h, 1), 0) - 0.2) < 1e-12;
        onFold += onLine ? 1 : 0;
        EXPECT_NEAR(std::abs(angles[h]), onLine ? fold : 0.0, 1e-12) << "hinge " << h;
    }
    EXPECT_EQ(onFold, 3);
    EXPECT_GT(test::forces(flat, x, MatX3::Zero(x.rows(), 3)).cwiseAbs().maxCoeff(), 1e-6);
    const DihedralBending shaped(c.mesh, c.offset, bendingMaterial(), angles, false);
    test::expectZeroForce(shaped, x, MatX3::Zero(x.rows(), 3), 1e-14);
    EXPECT_NEAR(shaped.energy(x), 0.0, 1e-20);
}

TEST(DihedralBending, PlasticityMovesTheRestAngleBeyondTheYield) {
    const ClothMesh mesh = hingePair();
    Material m = bendingMaterial();
    m.plasticYieldAngle = 0.1;
    m.plasticRate = 10.0;
    const MatX3 x = foldedPair(mesh, 0.5, 0, 4);

    DihedralBending off(mesh, 0, m, VecX(), false);
    off.acceptStep(x, 0.01);
    EXPECT_EQ(off.restAngles()[0], 0.0);

    DihedralBending model(mesh, 0, m, VecX(), true);
    model.acceptStep(x, 0.01); // fraction 0.1 of the excess 0.4
    EXPECT_NEAR(model.restAngles()[0], 0.04, 1e-12);
    for (int i = 0; i < 500; ++i) {
        model.acceptStep(x, 0.01);
    }
    // Converges to the angle at the yield limit, never past it.
    EXPECT_NEAR(model.restAngles()[0], 0.4, 1e-9);
    // Within the yield: no change.
    model.acceptStep(foldedPair(mesh, 0.45, 0, 4), 0.01);
    EXPECT_NEAR(model.restAngles()[0], 0.4, 1e-9);
    // Folding the other way yields back.
    model.acceptStep(foldedPair(mesh, -0.5, 0, 4), 1.0);
    EXPECT_NEAR(model.restAngles()[0], -0.4, 1e-9);
    // Disabled when the yield angle is 0.
    m.plasticYieldAngle = 0;
    DihedralBending noYield(mesh, 0, m, VecX(), true);
    noYield.acceptStep(x, 0.01);
    EXPECT_EQ(noYield.restAngles()[0], 0.0);
}

TEST(DihedralBending, DegenerateStatesStayFinite) {
    const PlacedCloth c = test::placeCloth(test::makeTestMesh(Triangulation::Irregular));
    const DihedralBending model(c.mesh, c.offset, bendingMaterial(), VecX(), false);
    MatX3 point = MatX3::Zero(c.totalVertices, 3);
    MatX3 line = test::restPositions(c);
    line.col(1).setZero();
    for (const MatX3& x : {point, line}) {
        const MatX3 v = MatX3::Ones(x.rows(), 3);
        EXPECT_TRUE(test::forces(model, x, v).allFinite());
        EXPECT_TRUE(std::isfinite(model.energy(x)));
        for (auto mode : {JacobianMode::Exact, JacobianMode::Definite}) {
            EXPECT_TRUE(test::denseJacobian(model, x, v, 1, 1, mode).allFinite());
        }
    }
}

} // namespace
} // namespace atelier::sim
