// Seam elastics as a force model: straight pairs and pairs routed through a via point.
#include "sim/constraints/seam_elastics.h"
#include "sim/forces/force_check.h"
#include "sim/simulation.h"
#include "sim/test_scenes.h"

#include <gtest/gtest.h>

#include <tuple>

namespace atelier::sim {
namespace {

/// Four vertices in two pairs (0–1, 2–3), 11–40 cm apart, moving, with unequal masses.
struct TwoPairs {
    MatX3 x{4, 3}, v{4, 3};
    VecX masses{4};
    TwoPairs() {
        x << 0, 0, 0, 0.1, 0.02, -0.03, 0.3, 0.1, 0.05, 0.25, -0.1, 0.2;
        v << 0.1, -0.2, 0.3, 0, 0.5, -0.1, -0.3, 0.2, 0.1, 0.4, 0, -0.2;
        masses << 0.01, 0.02, 0.015, 0.03;
    }
};

/// Forces are −∇E, exact Jacobians match finite differences (relative `tolerance`), and the
/// definite ones are negative semi-definite.
void expectConsistent(const SeamElastics& seams, const TwoPairs& state, double tolerance) {
    test::expectForcesAreEnergyGradient(seams, state.x, 1e-6, 0.1 * tolerance);
    test::expectExactJacobianMatchesFiniteDifferences(seams, state.x, state.v, 1e-6, tolerance);
    test::expectDefiniteJacobian(seams, state.x, state.v);
    test::expectDampingProduct(seams, state.x, state.v, 1e-12);
}

TEST(SeamElastics, RoutedPairsAreTheGradientOfTheirEnergyWithExactJacobians) {
    // Two pairs, one on its straight chord and one routed through a via point: forces are
    // −∇E, the Jacobians match finite differences and the definite ones are negative
    // semi-definite; routing back to the chord restores the pair coupling.
    const TwoPairs state;
    const MatX3& x = state.x;
    SeamElastics seams({{0, 1}, {2, 3}}, state.masses, 0.04);
    const Vec3 via(0.2, 0.3, 0.1);
    seams.setVia(1, &via);
    EXPECT_TRUE(seams.routed(1));
    EXPECT_FALSE(seams.routed(0));
    expectConsistent(seams, state, 1e-6);
    // The routed pair: both vertices pulled towards the via point, not towards each other.
    MatX3 f = MatX3::Zero(4, 3);
    seams.addForces(x, MatX3::Zero(4, 3), f);
    const double mu = 0.015 * 0.03 / 0.045;
    EXPECT_LT((f.row(2).transpose() - mu / (0.04 * 0.04) * (via - x.row(2).transpose())).norm(),
              1e-12);
    seams.setVia(1, nullptr);
    f.setZero();
    seams.addForces(x, MatX3::Zero(4, 3), f);
    EXPECT_LT((f.row(2) + f.row(3)).norm(), 1e-12); // action = reaction again
}

TEST(SeamElastics, SaturatedBeyondTheirReachWithExactJacobians) {
    // With a reach of 5 cm, gaps of 11–40 cm are pulled with the constant force the spring
    // has at 5 cm, along the gap; the energy, the Jacobians and their definiteness still hold,
    // and a gap within the reach is pulled linearly as before.
    const TwoPairs state;
    const MatX3& x = state.x;
    const VecX& masses = state.masses;
    const double tau = 0.04, reach = 0.05;
    SeamElastics seams({{0, 1}, {2, 3}}, masses, tau, reach);
    const Vec3 via(0.2, 0.3, 0.1);
    seams.setVia(1, &via);
    expectConsistent(seams, state, 1e-5);
    MatX3 f = MatX3::Zero(4, 3);
    seams.addForces(x, MatX3::Zero(4, 3), f);
    const double mu = 0.01 * 0.02 / 0.03;
    const Vec3 gap = (x.row(0) - x.row(1)).transpose();
    ASSERT_GT(gap.norm(), reach);
    EXPECT_LT((f.row(0).transpose() + mu / (tau * tau) * reach * gap.normalized()).norm(), 1e-12);
    SeamElastics linear({{0, 1}}, masses, tau, 1.0); // every gap here within a reach of 1 m
    SeamElastics plain({{0, 1}}, masses, tau);
    MatX3 f1 = MatX3::Zero(4, 3), f2 = MatX3::Zero(4, 3);
    linear.addForces(x, state.v, f1);
    plain.addForces(x, state.v, f2);
    EXPECT_EQ((f1 - f2).cwiseAbs().maxCoeff(), 0.0);
}

TEST(SeamElastics, StiffnessPerLengthOfSeamAddsToTheMassLaw) {
    // Each pair's stiffness is μ/τ² plus S times the seam length it stands for, with damping 2τ
    // times the stiffness (the same closing speed, more strength): a pull per metre of seam,
    // so two pairs standing for 1 cm pull half as hard as one standing for 2 cm.
    const TwoPairs state;
    const MatX3& x = state.x;
    const double tau = 0.004, reach = 0.5, S = 16000;
    SeamElastics seams({{0, 1, 0.01}, {2, 3, 0.02}}, state.masses, tau, reach, S);
    expectConsistent(seams, state, 1e-6);
    MatX3 f = MatX3::Zero(4, 3);
    seams.addForces(x, state.v, f);
    for (const auto& [a, b, length] : {std::tuple{0, 1, 0.01}, std::tuple{2, 3, 0.02}}) {
        const double mu = state.masses[a] * state.masses[b] / (state.masses[a] + state.masses[b]);
        const double k = mu / (tau * tau) + S * length;
        const Vec3 r = (x.row(a) - x.row(b)).transpose();
        const Vec3 rv = (state.v.row(a) - state.v.row(b)).transpose();
        ASSERT_LT(r.norm(), reach);
        const Vec3 expected = -k * r - 2.0 * tau * k * rv;
        EXPECT_LT((f.row(a).transpose() - expected).norm(), 1e-12 * expected.norm()) << a;
        EXPECT_LT((f.row(a) + f.row(b)).norm(), 1e-12 * expected.norm()) << a;
    }
}

TEST(SeamElastics, NegativeStrengthOrLengthIsRefusedWithItsName) {
    SceneSpec s = ::atelier::test::smallSheet(StretchModel::Fem, 2, 0.2);
    s.pins.clear();
    s.seams.push_back({0, 8, 0.01});
    s.seamStiffnessPerLength = -1;
    Simulation a(s);
    EXPECT_NE(a.error().find("seam stiffness per length"), std::string::npos) << a.error();
    s.seamStiffnessPerLength = 100;
    s.seams[0].length = -0.01;
    Simulation b(s);
    EXPECT_NE(b.error().find("seam pair 0: length"), std::string::npos) << b.error();
}

} // namespace
} // namespace atelier::sim
