// Pattern curves against closed forms: lengths, arc-length parameters, loop areas.

#include "patterns/curve.h"
#include "patterns/loops.h"

#include <gtest/gtest.h>

#include <cmath>

namespace atelier::patterns {
namespace {

using test::arc;
using test::line;

TEST(Curve, ArcByBulgeIsTheCircleThroughItsEnds) {
    // A quarter circle of radius 2 about the origin, counter-clockwise: bulge tan(π/8).
    const Segment s = arc(Vec2(2, 0), Vec2(0, 2), std::tan(M_PI / 8));
    Vec2 c;
    double r, a0, sweep;
    ASSERT_TRUE(arcGeometry(s, c, r, a0, sweep));
    EXPECT_NEAR(c.norm(), 0.0, 1e-12);
    EXPECT_NEAR(r, 2.0, 1e-12);
    EXPECT_NEAR(sweep, M_PI / 2, 1e-12);
    EXPECT_NEAR((pointAt(s, 0.5) - Vec2(std::sqrt(2.0), std::sqrt(2.0))).norm(), 0.0, 1e-12);
    EXPECT_NEAR(arcLength(s), M_PI, 1e-12);
    // A half circle (bulge 1) clockwise (bulge −1) bulges the other way.
    const Segment cw = arc(Vec2(-1, 0), Vec2(1, 0), -1.0);
    EXPECT_NEAR(pointAt(cw, 0.5).y(), 1.0, 1e-12);
    const Segment ccw = arc(Vec2(-1, 0), Vec2(1, 0), 1.0);
    EXPECT_NEAR(pointAt(ccw, 0.5).y(), -1.0, 1e-12);
}

TEST(Curve, BezierLengthsAndParameters) {
    // A cubic with collinear, evenly spaced controls is the straight line at uniform speed.
    Segment c = line(Vec2(0, 0), Vec2(3, 4));
    c.kind = SegmentKind::Cubic;
    c.control1 = Vec2(1, 4.0 / 3);
    c.control2 = Vec2(2, 8.0 / 3);
    EXPECT_NEAR(arcLength(c), 5.0, 1e-12);
    EXPECT_NEAR(parameterAtLength(c, 0, 1, 2.5), 0.5, 1e-10);
    // Backwards from t = 1.
    EXPECT_NEAR(parameterAtLength(c, 1, 0, 1.0), 0.8, 1e-10);
    // A quadratic parabola y = x² on [0, 1]: length (2√5 + asinh 2)/4.
    Segment q = line(Vec2(0, 0), Vec2(1, 1));
    q.kind = SegmentKind::Quadratic;
    q.control1 = Vec2(0.5, 0);
    EXPECT_NEAR(arcLength(q), (2 * std::sqrt(5.0) + std::asinh(2.0)) / 4, 1e-12);
    // Equal-length parameters split the length evenly.
    const auto ts = equalLengthParameters(q, 0, 1, 7);
    for (std::size_t i = 0; i + 1 < ts.size(); ++i) {
        EXPECT_NEAR(arcLength(q, ts[i], ts[i + 1]), arcLength(q) / 7, 1e-10);
    }
}

TEST(Curve, LoopAreasAreExact) {
    // Unit square, counter-clockwise: +1; clockwise: −1.
    const Loop square = {line({0, 0}, {1, 0}), line({1, 0}, {1, 1}), line({1, 1}, {0, 1}),
                         line({0, 1}, {0, 0})};
    EXPECT_NEAR(loopArea(square), 1.0, 1e-15);
    // A disc of radius 0.3 from two half-circle arcs.
    const Loop disc = {arc({0.3, 0}, {-0.3, 0}, 1.0), arc({-0.3, 0}, {0.3, 0}, 1.0)};
    EXPECT_NEAR(loopArea(disc), M_PI * 0.09, 1e-14);
    // The square with its top edge replaced by a parabola bulging up by 0.5 (a quadratic with
    // control 1 above the chord): extra area 2/3 × 1 × 0.5.
    Loop bulged = square;
    bulged[2].kind = SegmentKind::Quadratic;
    bulged[2].control1 = Vec2(0.5, 2.0);
    EXPECT_NEAR(loopArea(bulged), 1.0 + 2.0 / 3.0 * 0.5, 1e-14);
}

} // namespace
} // namespace atelier::patterns
