// The cut line's offset (patterns/seam_allowance): exact areas of offset squares, inner
// corners trimmed, regions swallowed or split by an inward offset, and the folds of corners
// that turn too little to resolve.
#include "patterns/seam_allowance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

namespace atelier::patterns {
namespace {

constexpr double TOLERANCE = 2e-5; // [m], as the pattern SVG uses

std::vector<Vec2> square(double side) {
    return {Vec2(0, 0), Vec2(side, 0), Vec2(side, side), Vec2(0, side)};
}

/// Every point of every loop is `distance` (within the tolerance) from `loop`.
void expectAtDistance(const std::vector<std::vector<Vec2>>& loops, const std::vector<Vec2>& loop,
                      double distance) {
    for (const auto& l : loops) {
        for (const Vec2& p : l) {
            const double d = distanceToPolyline(loop, p);
            EXPECT_GE(d, distance * (1 - 1e-9));
            EXPECT_LE(d, distance + TOLERANCE);
        }
    }
}

TEST(SeamAllowance, ASquareOffsetOutwardGainsItsRoundedBand) {
    const auto loop = square(0.1);
    const auto out = offsetPolyline(loop, 0.01, OffsetSide::Outside, TOLERANCE);
    ASSERT_EQ(out.size(), 1U);
    // 0.1² + 4 · 0.1 · 0.01 + π 0.01², the corners' circumscribed polygons a little more.
    const double exact = 0.01 + 0.004 + std::numbers::pi * 1e-4;
    EXPECT_GT(polylineArea(out[0]), exact);
    EXPECT_LT(polylineArea(out[0]), exact + TOLERANCE * (0.4 + 2 * std::numbers::pi * 0.01));
    expectAtDistance(out, loop, 0.01);
}

TEST(SeamAllowance, InnerCornersAreTrimmed) {
    // An L: its inner corner would make the offset cross itself.
    const std::vector<Vec2> ell = {Vec2(0, 0),       Vec2(0.2, 0),    Vec2(0.2, 0.05),
                                   Vec2(0.05, 0.05), Vec2(0.05, 0.2), Vec2(0, 0.2)};
    const auto out = offsetPolyline(ell, 0.01, OffsetSide::Outside, TOLERANCE);
    ASSERT_EQ(out.size(), 1U);
    expectAtDistance(out, ell, 0.01);
    // The inner corner of the offset is the mitre at (0.06, 0.06).
    double nearest = 1;
    for (const Vec2& p : out[0]) {
        nearest = std::min(nearest, (p - Vec2(0.06, 0.06)).norm());
    }
    EXPECT_LT(nearest, 1e-12);
}

TEST(SeamAllowance, InwardOffsetsShrinkSwallowAndSplit) {
    const auto loop = square(0.1);
    const auto in = offsetPolyline(loop, 0.01, OffsetSide::Inside, TOLERANCE);
    ASSERT_EQ(in.size(), 1U);
    EXPECT_NEAR(polylineArea(in[0]), 0.08 * 0.08, 1e-15);
    EXPECT_TRUE(offsetPolyline(loop, 0.06, OffsetSide::Inside, TOLERANCE).empty());
    // A dumbbell: two 0.1 m squares joined by a 0.02 m neck, offset inward by 0.015.
    const std::vector<Vec2> dumbbell = {Vec2(0, 0),      Vec2(0.1, 0),   Vec2(0.1, 0.04),
                                        Vec2(0.2, 0.04), Vec2(0.2, 0),   Vec2(0.3, 0),
                                        Vec2(0.3, 0.1),  Vec2(0.2, 0.1), Vec2(0.2, 0.06),
                                        Vec2(0.1, 0.06), Vec2(0.1, 0.1), Vec2(0, 0.1)};
    const auto split = offsetPolyline(dumbbell, 0.015, OffsetSide::Inside, TOLERANCE);
    ASSERT_EQ(split.size(), 2U);
    for (const auto& l : split) {
        // Each a 0.07 m square with a small bump toward the neck, where the nearest fabric
        // edge is the neck's corner, not its sides (less than 0.0038 × 0.02 m²).
        EXPECT_GT(polylineArea(l), 0.07 * 0.07);
        EXPECT_LT(polylineArea(l), 0.07 * 0.07 + 0.0038 * 0.02);
    }
    expectAtDistance(split, dumbbell, 0.015);
}

TEST(SeamAllowance, CornersTurningTooLittleLeaveNoFolds) {
    // A square whose sides bend outward by 1e-5 rad at their middles: offset inward, each bend
    // folds the offset by a depth (1.25e-11 of the distance) below the distance's rounding.
    const double bulge = 0.05 * std::tan(0.5e-5);
    const std::vector<Vec2> loop = {
        Vec2(0, 0),     Vec2(0.05, -bulge),      Vec2(0.1, 0), Vec2(0.1 + bulge, 0.05),
        Vec2(0.1, 0.1), Vec2(0.05, 0.1 + bulge), Vec2(0, 0.1), Vec2(-bulge, 0.05)};
    const auto in = offsetPolyline(loop, 0.01, OffsetSide::Inside, TOLERANCE);
    ASSERT_EQ(in.size(), 1U);
    expectAtDistance(in, loop, 0.01);
}

TEST(SeamAllowance, ZeroDistanceIsTheLoopAndCurvesAreSampledToTheTolerance) {
    const auto loop = square(0.1);
    const auto same = offsetPolyline(loop, 0, OffsetSide::Outside, TOLERANCE);
    ASSERT_EQ(same.size(), 1U);
    EXPECT_EQ(same[0], loop);
    Segment arc;
    arc.kind = SegmentKind::Arc;
    arc.start = Vec2(0.1, 0);
    arc.end = Vec2(-0.1, 0);
    arc.bulge = 1; // a half circle of radius 0.1 m
    Segment back;
    back.start = arc.end;
    back.end = arc.start;
    const auto poly = loopPolyline({arc, back}, TOLERANCE);
    for (std::size_t i = 0; i + 1 < poly.size(); ++i) {
        const Vec2 mid = 0.5 * (poly[i] + poly[i + 1]);
        EXPECT_LE(0.1 - mid.norm(), TOLERANCE);
    }
    EXPECT_GT(poly.size(), 10U);
}

} // namespace
} // namespace atelier::patterns
