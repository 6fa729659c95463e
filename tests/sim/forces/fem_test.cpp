#include "sim/core/parallel.h"
#include "sim/forces/fem.h"
#include "sim/forces/force_check.h"

#include <gtest/gtest.h>

namespace atelier::sim {
namespace {

using test::PlacedCloth;

Material anisotropicMaterial() {
    Material m;
    m.stretchWeft = 3000;
    m.stretchWarp = 1200;
    m.shear = 400;
    m.poisson = 0.35;
    m.damping = 0.01;
    return m;
}

/// The anisotropic material stiffening 4× (weft) and 6× (warp) beyond 1% Green strain, a knee
/// the random states of the force checks cross.
Material stiffeningMaterial() {
    Material m = anisotropicMaterial();
    m.stretchKnee = 0.01;
    m.stretchWeftBeyond = 4 * m.stretchWeft;
    m.stretchWarpBeyond = 6 * m.stretchWarp;
    return m;
}

class FemStretchTest : public ::testing::TestWithParam<Triangulation> {};

TEST_P(FemStretchTest, PassesForceChecks) {
    const PlacedCloth c = test::placeCloth(test::makeTestMesh(GetParam()));
    for (const Material& m : {anisotropicMaterial(), Material{}, stiffeningMaterial()}) {
        const FemStretch model(c.mesh, c.offset, m);
        for (std::uint32_t seed : {1u, 2u}) {
            SCOPED_TRACE("seed " + std::to_string(seed));
            const auto [x, v] = test::randomState(c, 0.02, 0.5, seed);
            test::checkForceModel(model, c, x, v);
        }
    }
}

TEST_P(FemStretchTest, LargeCompressionAndInversionStayConsistent) {
    // Strongly compressed and partly inverted state: the Exact Jacobian still matches and the
    // Definite one stays NSD (compressive stress clamped).
    const PlacedCloth c = test::placeCloth(test::makeTestMesh(GetParam()));
    const FemStretch model(c.mesh, c.offset, anisotropicMaterial());
    MatX3 x = test::restPositions(c) * 0.5;
    x = test::perturbed(c, x, 0.05, 9);
    const MatX3 v = test::perturbed(c, MatX3::Zero(x.rows(), 3), 1.0, 10);
    test::expectExactJacobianMatchesFiniteDifferences(model, x, v, 1e-6, 1e-5);
    test::expectDefiniteJacobian(model, x, v);
}

INSTANTIATE_TEST_SUITE_P(Meshes, FemStretchTest,
                         ::testing::Values(Triangulation::Regular, Triangulation::Irregular));

/// Homogeneous uniaxial weft stretch with the lateral contraction of zero lateral stress:
/// X ↦ ((1+ε)X, λY) with Green strain E_yy = −ν₁₂ E_xx. Then S = (E₁ E_xx, 0, 0) in every
/// triangle, interior nodes are in equilibrium, and the right edge carries −P_xx·H.
TEST(FemStretch, UniaxialWeftTensionGivesTheAnalyticStress) {
    const Material m = anisotropicMaterial();
    for (auto tri : {Triangulation::Regular, Triangulation::Irregular}) {
        const double width = 0.4;
        const double height = 0.3;
        const PlacedCloth c = test::placeCloth(test::makeTestMesh(tri, 4, 3, width, height));
        const FemStretch model(c.mesh, c.offset, m);
        for (double eps : {1e-3, 0.05}) {
            const double exx = 0.5 * ((1 + eps) * (1 + eps) - 1);
            const double eyy = -m.poisson * exx;
            const double lambda = std::sqrt(1 + 2 * eyy);
            MatX3 x = test::restPositions(c);
            for (int i = 0; i < c.mesh.vertexCount(); ++i) {
                x(c.offset + i, 0) *= 1 + eps;
                x(c.offset + i, 1) *= lambda;
            }
            for (int t = 0; t < c.mesh.triangleCount(); ++t) {
                const Vec3 s = model.stress(x, t);
                EXPECT_NEAR(s.x(), m.stretchWeft * exx, 1e-9 * m.stretchWeft);
                EXPECT_NEAR(s.y(), 0.0, 1e-9 * m.stretchWeft);
                EXPECT_NEAR(s.z(), 0.0, 1e-9 * m.stretchWeft);
            }
            const MatX3 f = test::forces(model, x, MatX3::Zero(x.rows(), 3));
            double right = 0;
            double left = 0;
            for (int i = 0; i < c.mesh.vertexCount(); ++i) {
                const double X = c.mesh.rest(i, 0);
                const Vec3 fi = f.row(c.offset + i).transpose();
                EXPECT_NEAR(fi.y(), 0.0, 1e-9) << "vertex " << i;
                EXPECT_NEAR(fi.z(), 0.0, 1e-9) << "vertex " << i;
                if (X > 1e-9 && X < width - 1e-9) {
                    EXPECT_NEAR(fi.x(), 0.0, 1e-9) << "interior vertex " << i;
                }
                (X > width / 2 ? right : left) += fi.x();
            }
            const double pxx = (1 + eps) * m.stretchWeft * exx; // first Piola–Kirchhoff
            // The internal force pulls the stretched edges back: −P·N·H on the right edge.
            EXPECT_NEAR(right, -pxx * height, 1e-9 * m.stretchWeft);
            EXPECT_NEAR(left, pxx * height, 1e-9 * m.stretchWeft);
            // Small-strain reading: stress / strain = E₁, lateral / axial strain = −ν₁₂.
            if (eps < 0.01) {
                EXPECT_NEAR(-right / height / eps, m.stretchWeft, 0.005 * m.stretchWeft);
                EXPECT_NEAR((lambda - 1) / eps, -m.poisson, 0.005);
            }
        }
    }
}

// Beyond the knee the tangent modulus is the one given for large strain (exactly, with ν = 0),
// below it the small-strain one; the stress is continuous at the knee. Warp stays linear
// where only the weft stiffens.
TEST(FemStretch, StiffensBeyondTheKneeToTheGivenModulus) {
    Material m = anisotropicMaterial();
    m.poisson = 0.0;
    m.stretchKnee = 0.03;
    m.stretchWeftBeyond = 5 * m.stretchWeft;
    const PlacedCloth c = test::placeCloth(test::makeTestMesh(Triangulation::Irregular));
    const FemStretch model(c.mesh, c.offset, m);
    const auto weftStress = [&](double exx) {
        MatX3 x = test::restPositions(c);
        for (int i = 0; i < c.mesh.vertexCount(); ++i) {
            x(c.offset + i, 0) *= std::sqrt(1 + 2 * exx);
        }
        const Vec3 s = model.stress(x, 0);
        EXPECT_NEAR(s.y(), 0.0, 1e-9 * m.stretchWeftBeyond);
        return s.x();
    };
    const double h = 1e-4;
    EXPECT_NEAR((weftStress(0.01 + h) - weftStress(0.01 - h)) / (2 * h), m.stretchWeft,
                1e-6 * m.stretchWeft);
    EXPECT_NEAR((weftStress(0.06 + h) - weftStress(0.06 - h)) / (2 * h), m.stretchWeftBeyond,
                1e-6 * m.stretchWeftBeyond);
    EXPECT_NEAR(weftStress(0.03), m.stretchWeft * 0.03, 1e-9 * m.stretchWeft);
    EXPECT_NEAR(weftStress(0.05), m.stretchWeft * 0.05 + 4 * m.stretchWeft * 0.02,
                1e-9 * m.stretchWeft);
    // Warp: linear at any strain.
    MatX3 x = test::restPositions(c);
    for (int i = 0; i < c.mesh.vertexCount(); ++i) {
        x(c.offset + i, 1) *= std::sqrt(1 + 2 * 0.08);
    }
    EXPECT_NEAR(model.stress(x, 0).y(), m.stretchWarp * 0.08, 1e-9 * m.stretchWarp);
    // Energy: the stiffening's share beyond the knee, ½Δ(E − κ)² per area.
    x = test::restPositions(c);
    for (int i = 0; i < c.mesh.vertexCount(); ++i) {
        x(c.offset + i, 0) *= std::sqrt(1 + 2 * 0.05);
    }
    Material linear = m;
    linear.stretchKnee = 0;
    const FemStretch linearModel(c.mesh, c.offset, linear);
    double area = 0;
    for (int t = 0; t < c.mesh.triangleCount(); ++t) {
        const Vec2 a = c.mesh.rest.row(c.mesh.triangles(t, 0)).transpose();
        const Vec2 b = c.mesh.rest.row(c.mesh.triangles(t, 1)).transpose();
        const Vec2 d = c.mesh.rest.row(c.mesh.triangles(t, 2)).transpose();
        area += 0.5 * std::abs((b - a).x() * (d - a).y() - (b - a).y() * (d - a).x());
    }
    EXPECT_NEAR(model.energy(x) - linearModel.energy(x),
                0.5 * 4 * m.stretchWeft * 0.02 * 0.02 * area, 1e-9 * m.stretchWeft * area);
}

TEST(FemStretch, WarpTensionAndShearUseTheirModuli) {
    const Material m = anisotropicMaterial();
    const PlacedCloth c = test::placeCloth(test::makeTestMesh(Triangulation::Irregular));
    const FemStretch model(c.mesh, c.offset, m);
    // Warp: E_yy = e, E_xx = −ν₂₁ e gives S = (0, E₂ e, 0).
    const double e = 1e-3;
    const double nu21 = m.poisson * m.stretchWarp / m.stretchWeft;
    MatX3 x = test::restPositions(c);
    for (int i = 0; i < c.mesh.vertexCount(); ++i) {
        x(c.offset + i, 0) *= std::sqrt(1 - 2 * nu21 * e);
        x(c.offset + i, 1) *= std::sqrt(1 + 2 * e);
    }
    for (int t = 0; t < c.mesh.triangleCount(); ++t) {
        const Vec3 s = model.stress(x, t);
        EXPECT_NEAR(s.x(), 0.0, 1e-9);
        EXPECT_NEAR(s.y(), m.stretchWarp * e, 1e-9);
    }
    // Simple shear x += γ y: 2E_xy = γ, S_xy = G γ (E_yy = γ²/2 adds normal stress).
    const double gamma = 1e-3;
    x = test::restPositions(c);
    for (int i = 0; i < c.mesh.vertexCount(); ++i) {
        x(c.offset + i, 0) += gamma * c.mesh.rest(i, 1);
    }
    for (int t = 0; t < c.mesh.triangleCount(); ++t) {
        const Vec3 strain = model.greenStrain(x, t);
        EXPECT_NEAR(strain.z(), gamma, 1e-12);
        EXPECT_NEAR(model.stress(x, t).z(), m.shear * gamma, 1e-9);
    }
}

TEST(FemStretch, StrainRateDampingOpposesStretching) {
    const Material m = anisotropicMaterial();
    const PlacedCloth c = test::placeCloth(test::makeTestMesh(Triangulation::Regular));
    const FemStretch model(c.mesh, c.offset, m);
    const MatX3 x = test::restPositions(c);
    // Stretching along weft at rate r: Ė_xx = r, damping stress τ E₁' r, force on the right edge
    // −τ·C₁₁·r·H pulls back.
    const double rate = 2.0;
    MatX3 v = MatX3::Zero(x.rows(), 3);
    for (int i = 0; i < c.mesh.vertexCount(); ++i) {
        v(c.offset + i, 0) = rate * c.mesh.rest(i, 0);
    }
    const MatX3 f = test::forces(model, x, v);
    double right = 0;
    for (int i = 0; i < c.mesh.vertexCount(); ++i) {
        if (c.mesh.rest(i, 0) > 0.2) {
            right += f(c.offset + i, 0);
        }
    }
    const Mat3 C = orthotropicStiffness(m);
    EXPECT_NEAR(right, -m.damping * C(0, 0) * rate * 0.3, 1e-9);
}

TEST(FemStretch, DegenerateStatesStayFinite) {
    const PlacedCloth c = test::placeCloth(test::makeTestMesh(Triangulation::Irregular));
    const FemStretch model(c.mesh, c.offset, anisotropicMaterial());
    // Everything collapsed to one point, and everything on a line.
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
    EXPECT_TRUE(test::forces(model, point, MatX3::Zero(point.rows(), 3)).isZero(0.0));
}

TEST(FemStretch, ParallelEvaluationIsDeterministic) {
    // Large enough (> PARALLEL_GRAIN triangles) for the parallel loops to engage.
    const PlacedCloth c =
        test::placeCloth(test::makeTestMesh(Triangulation::Irregular, 40, 30, 1.0, 0.75));
    const FemStretch model(c.mesh, c.offset, anisotropicMaterial());
    const auto [x, v] = test::randomState(c, 0.005, 0.3, 3);
    const int threads = threadCount();
    setThreadCount(1);
    const MatX3 serial = test::forces(model, x, v);
    setThreadCount(std::max(2, threads));
    const MatX3 parallel = test::forces(model, x, v);
    setThreadCount(0);
    EXPECT_EQ((serial - parallel).cwiseAbs().maxCoeff(), 0.0);
}

} // namespace
} // namespace atelier::sim
