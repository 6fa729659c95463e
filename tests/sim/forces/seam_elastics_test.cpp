// Seam elastics as a force model: straight pairs and pairs routed through a via point.
#include "sim/constraints/seam_elastics.h"
#include "sim/forces/force_check.h"

#include <gtest/gtest.h>

namespace atelier::sim {
namespace {

TEST(SeamElastics, RoutedPairsAreTheGradientOfTheirEnergyWithExactJacobians) {
    // Two pairs, one on its straight chord and one routed through a via point: forces are
    // −∇E, the Jacobians match finite differences and the definite ones are negative
    // semi-definite; routing back to the chord restores the pair coupling.
    MatX3 x(4, 3), v(4, 3);
    x << 0, 0, 0, 0.1, 0.02, -0.03, 0.3, 0.1, 0.05, 0.25, -0.1, 0.2;
    v << 0.1, -0.2, 0.3, 0, 0.5, -0.1, -0.3, 0.2, 0.1, 0.4, 0, -0.2;
    const VecX masses = (VecX(4) << 0.01, 0.02, 0.015, 0.03).finished();
    SeamElastics seams({{0, 1}, {2, 3}}, masses, 0.04);
    const Vec3 via(0.2, 0.3, 0.1);
    seams.setVia(1, &via);
    EXPECT_TRUE(seams.routed(1));
    EXPECT_FALSE(seams.routed(0));
    test::expectForcesAreEnergyGradient(seams, x, 1e-6, 1e-7);
    test::expectExactJacobianMatchesFiniteDifferences(seams, x, v, 1e-6, 1e-6);
    test::expectDefiniteJacobian(seams, x, v);
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

} // namespace
} // namespace atelier::sim
