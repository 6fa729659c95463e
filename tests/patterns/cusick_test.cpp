// The Cusick drape test's measures on shapes whose answer is known: the shadow of a flat disc,
// the radius of a square, nodes of a profile with six folds and ripples smaller than a fold.

#include "patterns/cusick.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace atelier::patterns {
namespace {

/// A flat fan of `n` triangles round the origin, radius r, in the (x, z) plane.
void fan(double r, int n, sim::MatX3& x, sim::MatX3i& f) {
    x.resize(n + 1, 3);
    f.resize(n, 3);
    x.row(0) << 0, 0, 0;
    for (int k = 0; k < n; ++k) {
        const double a = 2 * std::numbers::pi * k / n;
        x.row(k + 1) << r * std::cos(a), 0.0, r * std::sin(a);
        f.row(k) << 0, k + 1, (k + 1) % n + 1;
    }
}

TEST(Cusick, TheShadowOfAFlatDiscIsItsArea) {
    sim::MatX3 x;
    sim::MatX3i f;
    fan(0.15, 256, x, f);
    const double polygon = 0.5 * 256 * 0.15 * 0.15 * std::sin(2 * std::numbers::pi / 256);
    EXPECT_NEAR(shadowArea(x, f, 0.001), polygon, 0.003 * polygon);
    // Folding half of it over onto the other half halves the shadow (the union counts once).
    sim::MatX3 folded = x;
    for (Eigen::Index i = 0; i < folded.rows(); ++i) {
        folded(i, 0) = -std::abs(folded(i, 0));
    }
    EXPECT_NEAR(shadowArea(folded, f, 0.001), polygon / 2, 0.003 * polygon);
    // Lifted or tilted out of the plane, the shadow is the projection.
    sim::MatX3 lifted = x;
    lifted.col(1).setConstant(0.4);
    EXPECT_DOUBLE_EQ(shadowArea(lifted, f, 0.001), shadowArea(x, f, 0.001));
}

TEST(Cusick, ShadowRadiusFollowsTheOutline) {
    sim::MatX3 x(4, 3);
    x << -0.1, 0, -0.1, 0.1, 0, -0.1, 0.1, 0, 0.1, -0.1, 0, 0.1;
    sim::MatX3i f(2, 3);
    f << 0, 1, 2, 0, 2, 3;
    const std::vector<double> r = shadowRadius(x, f, 0.0005);
    ASSERT_EQ(r.size(), 360U);
    EXPECT_NEAR(r[0], 0.1, 0.001);                   // the middle of a side
    EXPECT_NEAR(r[45], 0.1 * std::sqrt(2.0), 0.002); // a corner
    EXPECT_NEAR(r[90], 0.1, 0.001);
}

TEST(Cusick, NodesAreFoldsHigherThanTheRipples) {
    std::vector<double> six(360);
    for (int k = 0; k < 360; ++k) {
        const double a = k * std::numbers::pi / 180;
        six[static_cast<std::size_t>(k)] =
            0.12 + 0.02 * std::cos(6 * a + 0.3) + 0.001 * std::cos(47 * a); // ripples of 1 mm
    }
    EXPECT_EQ(countNodes(six, 0.005), 6);
    EXPECT_EQ(countNodes(std::vector<double>(360, 0.12), 0.005), 0);
    std::vector<double> one(360, 0.12);
    one[200] = 0.14;
    EXPECT_EQ(countNodes(one, 0.005), 1);
}

} // namespace
} // namespace atelier::patterns
