// Placement: a panel wrapped on an arrangement slot lies on the slot's cylinder at radius +
// clearance, keeps its lengths along and around, and faces away from the body.

#include "patterns/placement.h"

#include "sim/mesh/cloth_mesh.h"

#include <gtest/gtest.h>

#include <cmath>

namespace atelier::patterns {
namespace {

/// A 0.3 × 0.2 m rectangle mesh (two triangles, counter-clockwise) drawn at (1, 2).
PanelMesh rectangleMesh() {
    PanelMesh m;
    m.pattern.resize(4, 2);
    m.pattern << 1.0, 2.0, 1.3, 2.0, 1.3, 2.2, 1.0, 2.2;
    m.rest = m.pattern;
    m.triangles.resize(2, 3);
    m.triangles << 0, 1, 2, 0, 2, 3;
    return m;
}

ArrangementSlot tiltedSlot() {
    ArrangementSlot s;
    s.name = "arm";
    s.origin = Vec3(0.3, 1.2, 0.05);
    s.axis = Vec3(-0.5, std::sqrt(3.0) / 2, 0); // 30° from vertical
    s.facing = Vec3(0, 0, 1);
    s.radius = 0.2;
    return s;
}

double distanceToAxis(const ArrangementSlot& s, const Vec3& p) {
    const Vec3 d = p - s.origin;
    return (d - d.dot(s.axis) * s.axis).norm();
}

TEST(Placement, CentredRotatedAndOffsetInThePanelPlane) {
    Panel panel;
    panel.placement.offset = Vec2(0.05, -0.1);
    panel.placement.rotation = M_PI / 2;
    const sim::MatX2 c = placementCoordinates(panel, rectangleMesh());
    // Corner (1, 2) is (−0.15, −0.1) from the centre; rotated 90°: (0.1, −0.15); then offset.
    EXPECT_NEAR(c(0, 0), 0.1 + 0.05, 1e-12);
    EXPECT_NEAR(c(0, 1), -0.15 - 0.1, 1e-12);
}

TEST(Placement, BackPanelsAreMirroredAndStayCounterClockwise) {
    Panel panel;
    panel.side = PanelSide::Back;
    // The mesher gives a Back panel triangles that are counter-clockwise in its mirrored rest
    // shape, i.e. clockwise as drawn.
    PanelMesh m = rectangleMesh();
    m.triangles << 0, 2, 1, 0, 3, 2;
    const sim::MatX2 c = placementCoordinates(panel, m);
    EXPECT_NEAR(c(0, 0), 0.15, 1e-12); // the left corner went right
    for (int t = 0; t < 2; ++t) {
        EXPECT_GT(sim::signedArea(c.row(m.triangles(t, 0)).transpose(),
                                  c.row(m.triangles(t, 1)).transpose(),
                                  c.row(m.triangles(t, 2)).transpose()),
                  0);
    }
}

TEST(Placement, WrapsOnTheSlotCylinderAtRadiusPlusClearanceFacingOut) {
    const ArrangementSlot slot = tiltedSlot();
    Panel panel;
    const PanelMesh m = rectangleMesh();
    const double clearance = 0.02;
    const sim::MatX3 x = wrapOnSlot(placementCoordinates(panel, m), slot, clearance);
    for (int i = 0; i < x.rows(); ++i) {
        EXPECT_NEAR(distanceToAxis(slot, x.row(i).transpose()), slot.radius + clearance, 1e-12);
    }
    // Lengths along the axis are kept; around, the arc length is kept.
    const Vec3 d01 = x.row(1) - x.row(0);
    EXPECT_NEAR(d01.dot(slot.axis), 0.0, 1e-12);
    const double r = slot.radius + clearance;
    EXPECT_NEAR(d01.norm(), 2 * r * std::sin(0.3 / (2 * r)), 1e-12); // chord of a 0.3 m arc
    EXPECT_NEAR((x.row(3) - x.row(0)).dot(slot.axis), 0.2, 1e-12);
    // Each counter-clockwise triangle's normal points away from the axis.
    for (int t = 0; t < m.triangles.rows(); ++t) {
        const Vec3 a = x.row(m.triangles(t, 0)), b = x.row(m.triangles(t, 1)),
                   c = x.row(m.triangles(t, 2));
        const Vec3 n = (b - a).cross(c - a);
        const Vec3 centre = (a + b + c) / 3.0;
        Vec3 out = centre - slot.origin;
        out -= out.dot(slot.axis) * slot.axis;
        EXPECT_GT(n.dot(out), 0) << "triangle " << t;
    }
    // The panel's centre faces the slot's facing direction.
    const Vec3 mid = 0.25 * (x.row(0) + x.row(1) + x.row(2) + x.row(3)).transpose();
    EXPECT_GT((mid - slot.origin).normalized().dot(slot.facing), 0.9);
}

/// A vertical slot 0.3 m long below its origin, with a 1 cm profile to be filled, panels
/// limited to ±π/2 around the facing (front and back share the circumference).
ArrangementSlot profiledSlot() {
    ArrangementSlot slot;
    slot.origin = Vec3::Zero();
    slot.axis = Vec3::UnitY();
    slot.facing = Vec3::UnitZ();
    slot.alongMin = -0.3;
    slot.alongMax = 0.0;
    slot.profileStep = 0.01;
    slot.maxAngle = 0.49 * std::acos(-1.0);
    return slot;
}

/// Placement coordinates of a panel 2·halfWidth wide and 0.3 m tall (v from −0.3 to 0),
/// nx × ny points row by row.
sim::MatX2 panelGrid(double halfWidth, int nx, int ny) {
    sim::MatX2 c(nx * ny, 2);
    for (int j = 0; j < ny; ++j) {
        for (int i = 0; i < nx; ++i) {
            c.row(j * nx + i) << -halfWidth + 2 * halfWidth * i / (nx - 1),
                -0.3 + 0.3 * j / (ny - 1);
        }
    }
    return c;
}

TEST(Placement, FollowsTheSlotsProfileAndStaysWithinItsAngle) {
    // A waist-like slot: radius 0.12 at the top widening to 0.2 at 0.3 m below.
    ArrangementSlot slot = profiledSlot();
    for (int k = 0; k <= 30; ++k) {
        slot.profile.push_back(0.2 - 0.08 * k / 30.0);
    }
    EXPECT_NEAR(slot.radiusAt(-0.3), 0.2, 1e-12);
    EXPECT_NEAR(slot.radiusAt(0.0), 0.12, 1e-12);
    EXPECT_NEAR(slot.radiusAt(-0.15), 0.16, 1e-12);
    // A panel 0.5 m wide and 0.3 m tall, its rows sampled every 5 mm.
    const int nx = 21, ny = 61;
    const sim::MatX2 c = panelGrid(0.25, nx, ny);
    const double clearance = 0.02;
    const sim::MatX3 x = wrapOnSlot(c, slot, clearance);
    for (int j = 0; j < ny; ++j) {
        for (int i = 0; i < nx; ++i) {
            const Vec3 p = x.row(j * nx + i);
            const double r = std::hypot(p.x(), p.z());
            // Clear of the body part everywhere, and within the angle.
            EXPECT_GE(r, slot.radiusAt(p.y()) + clearance - 1e-9);
            EXPECT_LE(std::abs(std::atan2(p.x(), p.z())), slot.maxAngle + 1e-9);
        }
    }
    // Around, the arc length is kept exactly: the centre column to the edge is 0.25 m of arc.
    for (int j = 0; j < ny; j += 10) {
        const Vec3 p = x.row(j * nx + nx - 1);
        const double r = std::hypot(p.x(), p.z());
        EXPECT_NEAR(r * std::atan2(p.x(), p.z()), 0.25, 1e-9);
    }
    // Along, the meridian keeps the panel's height within 1%.
    double meridian = 0;
    for (int j = 0; j + 1 < ny; ++j) {
        meridian += (x.row((j + 1) * nx + nx / 2) - x.row(j * nx + nx / 2)).norm();
    }
    EXPECT_NEAR(meridian, 0.3, 0.003);
    // The top row stays where the panel puts it.
    EXPECT_NEAR(x((ny - 1) * nx, 1), 0.0, 1e-12);
}

TEST(Placement, FollowsTheSlotsSectionCentres) {
    // A leg-like slot: radius 0.1 everywhere, its sections' centres moving along a parabola,
    // 5 cm to +x and 1 cm to −z from the top (along 0) down to along −0.3.
    ArrangementSlot slot = profiledSlot();
    for (int k = 0; k <= 30; ++k) {
        const double s = 1.0 - k / 30.0;
        slot.profile.push_back(0.1);
        slot.profileCentre.push_back(s * s * Vec3(0.05, 0, -0.01));
    }
    // Linear between bins, clamped beyond the ends.
    EXPECT_LT(
        (slot.centreAt(-0.155) - 0.5 * (slot.profileCentre[14] + slot.profileCentre[15])).norm(),
        1e-12);
    EXPECT_LT((slot.centreAt(-1.0) - Vec3(0.05, 0, -0.01)).norm(), 1e-12);
    EXPECT_LT(slot.centreAt(0.5).norm(), 1e-12);
    // Rows every 5 mm: half of them between the slot's bins.
    const int nx = 11, ny = 61;
    const sim::MatX2 c = panelGrid(0.15, nx, ny);
    const double clearance = 0.02;
    const sim::MatX3 x = wrapOnSlot(c, slot, clearance);
    for (int j = 0; j < ny; ++j) {
        for (int i = 0; i < nx; ++i) {
            const Vec3 p = x.row(j * nx + i);
            // The radius is constant, so every row stays at its own height; each point lies
            // at radius + clearance from its row's section centre, the arc around kept.
            EXPECT_NEAR(p.y(), c(j * nx + i, 1), 1e-12);
            const Vec3 q = p - slot.centreAt(p.y());
            EXPECT_NEAR(std::hypot(q.x(), q.z()), 0.12, 1e-9);
            EXPECT_NEAR(0.12 * std::atan2(q.x(), q.z()), c(j * nx + i, 0), 1e-9);
        }
    }
}

// Panels through each other: the triangle pairs of different panels that intersect, counted per
// pair of panels; a panel's own triangles and panels merely close are not counted.
TEST(PanelCrossings, CountsIntersectingTrianglesOfDifferentPanels) {
    auto square = [](const Vec3& o, const Vec3& u, const Vec3& v) {
        sim::MatX3 x(4, 3);
        x.row(0) = o.transpose();
        x.row(1) = (o + u).transpose();
        x.row(2) = (o + u + v).transpose();
        x.row(3) = (o + v).transpose();
        return x;
    };
    sim::MatX3i t(2, 3);
    t << 0, 1, 2, 0, 2, 3;
    // Panel 0 in the plane z = 0 over [0, 1]² (its diagonal from (0, 0) to (1, 1)); panel 1 in
    // the plane x = 0.25 through it, over y from 0.3 to 0.9: only panel 0's upper triangle
    // meets it, once per triangle of panel 1; panel 2 is panel 0 lifted by 1 mm.
    const std::vector<sim::MatX3> x = {
        square(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)),
        square(Vec3(0.25, 0.3, -0.5), Vec3(0, 0.6, 0), Vec3(0, 0, 1)),
        square(Vec3(0, 0, 0.001), Vec3(1, 0, 0), Vec3(0, 1, 0)),
    };
    const std::vector<PanelCrossing> c = panelCrossings(x, {t, t, t});
    ASSERT_EQ(c.size(), 2u);
    EXPECT_EQ(c[0].a, 0);
    EXPECT_EQ(c[0].b, 1);
    EXPECT_EQ(c[1].a, 1);
    EXPECT_EQ(c[1].b, 2);
    EXPECT_EQ(c[0].pairs, 2);
    EXPECT_EQ(c[1].pairs, 2);
    EXPECT_TRUE(panelCrossings({x[0], x[2]}, {t, t}).empty());
}

// A panel through itself counts only when its own pairs are asked for (withinPanels); panels
// sewn edge to edge touch along the seam, which counts unless the seam partners are joined.
TEST(PanelCrossings, APanelThroughItselfAndPanelsJoinedAtASeam) {
    // One panel of two separate triangles, the second through the first.
    sim::MatX3 self(6, 3);
    self << 0, 0, 0, 1, 0, 0, 0, 1, 0, //
        0.25, 0.1, -0.5, 0.25, 0.4, -0.5, 0.25, 0.1, 0.5;
    sim::MatX3i two(2, 3);
    two << 0, 1, 2, 3, 4, 5;
    EXPECT_TRUE(panelCrossings({self}, {two}).empty());
    const std::vector<PanelCrossing> within = panelCrossings({self}, {two}, nullptr, true);
    ASSERT_EQ(within.size(), 1u);
    EXPECT_EQ(within[0].a, 0);
    EXPECT_EQ(within[0].b, 0);
    EXPECT_EQ(within[0].pairs, 1);
    // A panel's own neighbours (sharing a vertex) never count.
    sim::MatX3 flat(4, 3);
    flat << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
    sim::MatX3i quad(2, 3);
    quad << 0, 1, 2, 0, 2, 3;
    EXPECT_TRUE(panelCrossings({flat}, {quad}, nullptr, true).empty());
    // A second panel sewn to the first's edge x = 1, folded up 45° from it: its triangles touch
    // the first's along the seam.
    sim::MatX3 folded(4, 3);
    folded << 1, 0, 0, 1.7, 0, 0.7, 1.7, 1, 0.7, 1, 1, 0;
    const std::vector<PanelCrossing> touching = panelCrossings({flat, folded}, {quad, quad});
    ASSERT_EQ(touching.size(), 1u);
    EXPECT_GT(touching[0].pairs, 0);
    // Joined: the seam partners (flat 1 ≡ folded 0, flat 2 ≡ folded 3) are one vertex each.
    const std::vector<std::vector<int>> joined = {{0, 1, 2, 3}, {1, 4, 5, 2}};
    EXPECT_TRUE(panelCrossings({flat, folded}, {quad, quad}, &joined, true).empty());
}

} // namespace
} // namespace atelier::patterns
