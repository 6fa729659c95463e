#include "sim/analysis/heavy_elastica.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

namespace atelier::sim {
namespace {

constexpr double DEG = 180.0 / std::numbers::pi;

TEST(HeavyElastica, PeirceBendingLengthGivesTheAstmAngle) {
    // ASTM D1388 / Peirce 1930: the overhang is twice the bending length (B/ρg)^{1/3}, i.e.
    // ρgL³/B = 8, when the tip line hangs 41.5° below the horizontal.
    const HeavyElastica e = solveHeavyElastica(8.0);
    ASSERT_TRUE(e.converged);
    EXPECT_NEAR(e.tipLineAngle * DEG, 41.5, 0.15);
}

TEST(HeavyElastica, SmallDeflectionsFollowTheLinearBeam) {
    // Euler–Bernoulli cantilever under a uniform load: tip drop wL⁴/(8B) = λL/8, tip slope
    // λ/6, root curvature λ/2 (in units of L).
    for (double lambda : {1e-4, 1e-2}) {
        const HeavyElastica e = solveHeavyElastica(lambda);
        ASSERT_TRUE(e.converged);
        EXPECT_NEAR(e.tipDrop / (lambda / 8), 1.0, 1e-2 * lambda + 1e-9) << lambda;
        EXPECT_NEAR(e.tipSlope / (lambda / 6), 1.0, 1e-2 * lambda + 1e-9) << lambda;
        EXPECT_NEAR(e.rootCurvature / (lambda / 2), 1.0, 1e-2 * lambda + 1e-9) << lambda;
    }
}

TEST(HeavyElastica, ConvergesUnderStepRefinementAndStaysBelowVertical) {
    double previous = 0;
    for (double lambda : {1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 50.0, 100.0}) {
        const HeavyElastica coarse = solveHeavyElastica(lambda, 1000);
        const HeavyElastica fine = solveHeavyElastica(lambda, 4000);
        ASSERT_TRUE(fine.converged) << lambda;
        EXPECT_NEAR(coarse.tipLineAngle, fine.tipLineAngle, 1e-9) << lambda;
        // Heavier strips hang lower, the tip line never past the vertical, and the strip is
        // inextensible: the tip stays within its length of the clamp.
        EXPECT_GT(fine.tipLineAngle, previous);
        EXPECT_LT(fine.tipSlope, std::numbers::pi / 2);
        EXPECT_LE(std::hypot(fine.tipX, fine.tipDrop), 1.0);
        previous = fine.tipLineAngle;
    }
}

TEST(HeavyElastica, BadInputGivesTheStraightStrip) {
    const HeavyElastica zero = solveHeavyElastica(0.0);
    EXPECT_TRUE(zero.converged);
    EXPECT_EQ(zero.tipLineAngle, 0.0);
    const HeavyElastica nan = solveHeavyElastica(std::numeric_limits<double>::quiet_NaN());
    EXPECT_FALSE(nan.converged);
    EXPECT_EQ(nan.tipDrop, 0.0);
}

} // namespace
} // namespace atelier::sim
