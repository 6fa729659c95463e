// GarmentCode / pygarment specifications: curves, units, orientation, stitches, placement,
// warnings and errors with their JSON pointer; the specifications in ../shared/data.
#include "io/garmentcode.h"

#include "patterns/curve.h"
#include "patterns/document.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

namespace atelier::io {
namespace {

using patterns::PanelSide;
using patterns::SegmentKind;
using sim::Vec2;
using sim::Vec3;

/// Slots of a standing figure (no mesh: placement reads only the slots).
patterns::Body slotBody() {
    patterns::Body body;
    auto add = [&](const std::string& name, const Vec3& origin, const Vec3& axis,
                   const Vec3& facing, double radius, double lo, double hi) {
        patterns::ArrangementSlot s;
        s.name = name;
        s.origin = origin;
        s.axis = axis;
        s.facing = facing;
        s.radius = radius;
        s.alongMin = lo;
        s.alongMax = hi;
        body.slots.push_back(s);
    };
    const std::pair<const char*, Vec3> facings[] = {{"front", Vec3::UnitZ()},
                                                    {"back", -Vec3::UnitZ()},
                                                    {"left", Vec3::UnitX()},
                                                    {"right", -Vec3::UnitX()}};
    for (const auto& [side, facing] : facings) {
        add(std::string("torso_") + side, {0, 1.0, 0}, Vec3::UnitY(), facing, 0.17, -0.25, 0.42);
        add(std::string("waist_") + side, {0, 1.0, 0}, Vec3::UnitY(), facing, 0.18, -0.27, 0.06);
    }
    const double a = 0.8; // arm angle from the vertical [rad]
    add("arm_left", {0.18, 1.38, 0}, Vec3(-std::sin(a), std::cos(a), 0),
        Vec3(std::cos(a), std::sin(a), 0), 0.05, -0.57, 0);
    add("arm_right", {-0.18, 1.38, 0}, Vec3(std::sin(a), std::cos(a), 0),
        Vec3(-std::cos(a), std::sin(a), 0), 0.05, -0.57, 0);
    return body;
}

Result<GarmentCodeImport> parseSpec(const std::string& text) {
    static const patterns::Body body = slotBody();
    return parseGarmentCode(text, "spec.json", body);
}

/// A square panel 60 cm wide (edges 0..3 counter-clockwise from the bottom left), in front of
/// the body, with `edge0` as the first edge's extra members.
std::string squareSpec(const std::string& edge0 = "", const std::string& units = "100",
                       const std::string& extraPanel = "") {
    return R"({"properties": {"units_in_meter": )" + units +
           R"(, "curvature_coords": "relative"},
  "pattern": {"panels": {"front": {
    "vertices": [[-30, -30], [30, -30], [30, 30], [-30, 30]],
    "edges": [{"endpoints": [0, 1])" +
           edge0 + R"(}, {"endpoints": [1, 2]}, {"endpoints": [2, 3]}, {"endpoints": [3, 0]}],
    "translation": [0, -20, 20], "rotation": [0, 0, 0]}
    )" + extraPanel +
           R"(}, "stitches": []}})";
}

TEST(GarmentCode, OldDatasetCurvatureIsAQuadraticInTheEdgeFrame) {
    // Edge (-0.3, -0.3) → (0.3, -0.3) m: control at 0.5 along and 0.1 chord lengths to its
    // left (a quarter turn counter-clockwise from the edge, here +y).
    auto r = parseSpec(squareSpec(R"(, "curvature": [0.5, 0.1])"));
    ASSERT_TRUE(r.ok()) << r.error().toString();
    const patterns::Segment& s = r.value().project.garment.panels[0].outline[0];
    EXPECT_EQ(s.kind, SegmentKind::Quadratic);
    EXPECT_NEAR((s.control1 - Vec2(0.0, -0.3 + 0.06)).norm(), 0, 1e-12);
    // B(½) = ¼ start + ½ control + ¼ end.
    EXPECT_NEAR((patterns::pointAt(s, 0.5) - Vec2(0.0, -0.3 + 0.03)).norm(), 0, 1e-12);
}

TEST(GarmentCode, QuadraticAndCubicCurvatureObjects) {
    auto q =
        parseSpec(squareSpec(R"(, "curvature": {"type": "quadratic", "params": [[0.25, -0.2]]})"));
    ASSERT_TRUE(q.ok()) << q.error().toString();
    const patterns::Segment& sq = q.value().project.garment.panels[0].outline[0];
    EXPECT_EQ(sq.kind, SegmentKind::Quadratic);
    EXPECT_NEAR((sq.control1 - Vec2(-0.3 + 0.15, -0.3 - 0.12)).norm(), 0, 1e-12);

    auto c = parseSpec(
        squareSpec(R"(, "curvature": {"type": "cubic", "params": [[0.3, 0.2], [0.7, -0.1]]})"));
    ASSERT_TRUE(c.ok()) << c.error().toString();
    const patterns::Segment& sc = c.value().project.garment.panels[0].outline[0];
    EXPECT_EQ(sc.kind, SegmentKind::Cubic);
    const Vec2 p0(-0.3, -0.3), p1(-0.3 + 0.18, -0.3 + 0.12), p2(-0.3 + 0.42, -0.3 - 0.06),
        p3(0.3, -0.3);
    const double t = 0.3;
    const Vec2 expected = std::pow(1 - t, 3) * p0 + 3 * std::pow(1 - t, 2) * t * p1 +
                          3 * (1 - t) * t * t * p2 + std::pow(t, 3) * p3;
    EXPECT_NEAR((patterns::pointAt(sc, t) - expected).norm(), 0, 1e-12);
}

TEST(GarmentCode, CircleArcBulgesToTheRightWhenAsked) {
    // Radius 30 cm on a 60 cm chord: a half circle; `right` puts its middle below the bottom
    // edge (the edge runs +x, its right is −y).
    auto r = parseSpec(squareSpec(R"(, "curvature": {"type": "circle", "params": [30, 0, 1]})"));
    ASSERT_TRUE(r.ok()) << r.error().toString();
    const patterns::Segment& s = r.value().project.garment.panels[0].outline[0];
    EXPECT_EQ(s.kind, SegmentKind::Arc);
    EXPECT_NEAR((patterns::pointAt(s, 0.5) - Vec2(0, -0.6)).norm(), 0, 1e-9);

    auto left = parseSpec(squareSpec(R"(, "curvature": {"type": "circle", "params": [50, 0, 0]})"));
    ASSERT_TRUE(left.ok()) << left.error().toString();
    // Sagitta of a 60 cm chord on a 50 cm radius: 50 − 40 = 10 cm, to the left (+y).
    const patterns::Segment& sl = left.value().project.garment.panels[0].outline[0];
    EXPECT_NEAR((patterns::pointAt(sl, 0.5) - Vec2(0, -0.2)).norm(), 0, 1e-9);
}

TEST(GarmentCode, UnitsInMeterScaleEverything) {
    auto cm = parseSpec(squareSpec("", "100"));
    auto third = parseSpec(squareSpec("", "300"));
    ASSERT_TRUE(cm.ok() && third.ok());
    const patterns::Segment& a = cm.value().project.garment.panels[0].outline[0];
    const patterns::Segment& b = third.value().project.garment.panels[0].outline[0];
    EXPECT_NEAR((a.end - a.start).norm(), 0.6, 1e-12);
    EXPECT_NEAR((b.end - b.start).norm(), 0.2, 1e-12);
}

TEST(GarmentCode, ClockwiseLoopsBecomeCounterClockwiseAndSeamsFollow) {
    // The back panel is drawn clockwise (its loop's normal faces −z, away from the body) and
    // unrotated: our outline runs the other way and the panel is placed mirrored.
    const std::string spec = R"({"properties": {"units_in_meter": 100},
      "pattern": {"panels": {
        "front": {"vertices": [[-20, 0], [20, 0], [20, 40], [-20, 40]],
                  "edges": [{"endpoints": [0, 1]}, {"endpoints": [1, 2]},
                            {"endpoints": [2, 3]}, {"endpoints": [3, 0]}],
                  "translation": [0, -40, 15], "rotation": [0, 0, 0]},
        "back": {"vertices": [[-20, 0], [-20, 40], [20, 40], [20, 0]],
                 "edges": [{"endpoints": [0, 1]}, {"endpoints": [1, 2]},
                           {"endpoints": [2, 3]}, {"endpoints": [3, 0]}],
                 "translation": [0, -40, -15], "rotation": [0, 0, 0]}},
      "stitches": [[{"panel": "front", "edge": 1}, {"panel": "back", "edge": 2}],
                   [{"panel": "front", "edge": 3}, {"panel": "back", "edge": 0}]]}})";
    auto r = parseSpec(spec);
    ASSERT_TRUE(r.ok()) << r.error().toString();
    const patterns::Garment& g = r.value().project.garment;
    ASSERT_EQ(g.panels.size(), 2u);
    for (const patterns::Panel& p : g.panels) {
        EXPECT_GT(patterns::loopArea(p.outline), 0) << p.name;
    }
    // Without panel_order, the panels come by name.
    EXPECT_EQ(g.panels[0].name, "back");
    const patterns::Panel& front = g.panels[1];
    const patterns::Panel& back = g.panels[0];
    EXPECT_EQ(front.side, PanelSide::Front);
    EXPECT_EQ(front.placement.slot, "waist_front");
    EXPECT_EQ(back.side, PanelSide::Back);
    EXPECT_EQ(back.placement.slot, "waist_back");
    // Stitch 0: front edge 1 ((20, 0) → (20, 40)) against back edge 2 ((20, 40) → (20, 0)),
    // segment 1 of the reversed back outline. Both lie at x = +20 cm in 3D and run against
    // each other, so the back's side is taken from the spec edge's end.
    ASSERT_EQ(g.seams.size(), 2u);
    const patterns::Seam& s = g.seams[0];
    EXPECT_EQ(s.a[0].panel, "front");
    EXPECT_EQ(s.a[0].segment, 1);
    EXPECT_EQ(s.b[0].panel, "back");
    EXPECT_EQ(s.b[0].segment, 1);
    const Vec2 a0 = patterns::pointAt(front.outline[1], s.a[0].t0);
    const Vec2 b0 = patterns::pointAt(back.outline[1], s.b[0].t0);
    // Both start at the bottom (y = 0 in their drawings), where they meet in 3D.
    EXPECT_NEAR(a0.y(), 0, 1e-12);
    EXPECT_NEAR(b0.y(), 0, 1e-12);
    // Placed: the same x in the world, so mirrored drawing (x → −x on the back slot's u).
    EXPECT_NEAR(front.placement.offset.x(), 0, 1e-9);
    EXPECT_NEAR(back.placement.offset.x(), 0, 1e-9);
    // The top of the garment at the waist (waist slots): centres 20 cm below it.
    EXPECT_NEAR(front.placement.offset.y(), -0.2, 1e-9);
    EXPECT_NEAR(back.placement.offset.y(), -0.2, 1e-9);
}

TEST(GarmentCode, RotatedBackPanelStaysFrontSide) {
    // The older dataset turns back panels 180° about y (as [180, 0, 180]): the drawing then
    // faces −z counter-clockwise, which is our back slot's own orientation.
    const std::string spec = R"({"properties": {"units_in_meter": 100},
      "pattern": {"panels": {
        "back": {"vertices": [[-20, 0], [20, 0], [20, 40], [-20, 40]],
                 "edges": [{"endpoints": [0, 1]}, {"endpoints": [1, 2]},
                           {"endpoints": [2, 3]}, {"endpoints": [3, 0]}],
                 "translation": [5, -40, -15], "rotation": [180, 0, 180]}}}})";
    auto r = parseSpec(spec);
    ASSERT_TRUE(r.ok()) << r.error().toString();
    const patterns::Panel& p = r.value().project.garment.panels[0];
    EXPECT_EQ(p.placement.slot, "waist_back");
    EXPECT_EQ(p.side, PanelSide::Front);
    EXPECT_NEAR(std::remainder(p.placement.rotation, 2 * M_PI), 0, 1e-9);
    // Alone, the panel is the garment's middle: centred on its slot.
    EXPECT_NEAR(p.placement.offset.x(), 0, 1e-9);
}

TEST(GarmentCode, StitchesBecomeSeamsOnTheRightEdges) {
    const std::string spec = R"({"properties": {"units_in_meter": 100},
      "pattern": {"panels": {
        "a": {"vertices": [[0, 0], [30, 0], [30, 30], [0, 30]],
              "edges": [{"endpoints": [0, 1]}, {"endpoints": [1, 2]},
                        {"endpoints": [2, 3]}, {"endpoints": [3, 0]}],
              "translation": [0, 0, 15], "rotation": [0, 0, 0]},
        "b": {"vertices": [[0, 0], [30, 0], [30, 30], [0, 30]],
              "edges": [{"endpoints": [0, 1]}, {"endpoints": [1, 2]},
                        {"endpoints": [2, 3]}, {"endpoints": [3, 0]}],
              "translation": [-30, 0, 15], "rotation": [0, 0, 0]}},
      "panel_order": ["b", "a"],
      "stitches": [[{"panel": "a", "edge": 3}, {"panel": "b", "edge": 1}]]}})";
    auto r = parseSpec(spec);
    ASSERT_TRUE(r.ok()) << r.error().toString();
    const patterns::Garment& g = r.value().project.garment;
    EXPECT_EQ(g.panels[0].name, "b"); // panel_order
    ASSERT_EQ(g.seams.size(), 1u);
    const patterns::Seam& s = g.seams[0];
    EXPECT_EQ(s.name, "a.3-b.1");
    EXPECT_EQ(s.a[0].segment, 3);
    EXPECT_EQ(s.b[0].segment, 1);
    // a's edge 3 runs down x = 0 ((0, 30) → (0, 0)), b's edge 1 up x = 30 of b, the same line
    // in 3D: they run against each other, so b is taken from its end.
    EXPECT_DOUBLE_EQ(s.a[0].t0, 0);
    EXPECT_DOUBLE_EQ(s.b[0].t0, 1);
    EXPECT_DOUBLE_EQ(s.b[0].t1, 0);
    // The document keeps the seam on those edges.
    const patterns::GarmentDocument& d = r.value().project.document;
    ASSERT_EQ(d.seams.size(), 1u);
    EXPECT_TRUE(patterns::checkDocument(d).ok());
}

TEST(GarmentCode, WarningsNameThePanelAndEdge) {
    auto r = parseSpec(squareSpec(R"(, "curvature": {"type": "spline", "params": []})"));
    ASSERT_TRUE(r.ok()) << r.error().toString();
    EXPECT_EQ(r.value().project.garment.panels[0].outline[0].kind, SegmentKind::Line);
    ASSERT_EQ(r.value().warnings.size(), 1u);
    EXPECT_NE(r.value().warnings[0].find("panel \"front\": edge 0: curvature type \"spline\""),
              std::string::npos)
        << r.value().warnings[0];

    // A stitch between a 60 cm and a 20 cm edge.
    const std::string other = R"(, "small": {"vertices": [[0, 0], [20, 0], [20, 20], [0, 20]],
        "edges": [{"endpoints": [0, 1]}, {"endpoints": [1, 2]}, {"endpoints": [2, 3]},
                  {"endpoints": [3, 0]}], "translation": [30, -20, 20], "rotation": [0, 0, 0]})";
    std::string spec = squareSpec("", "100", other);
    const std::string empty = R"("stitches": [])";
    spec.replace(spec.find(empty), empty.size(),
                 R"("stitches": [[{"panel": "front", "edge": 1}, {"panel": "small", "edge": 3}]])");
    auto s = parseSpec(spec);
    ASSERT_TRUE(s.ok()) << s.error().toString();
    ASSERT_EQ(s.value().warnings.size(), 1u);
    const std::string& w = s.value().warnings[0];
    EXPECT_NE(w.find("panel \"front\": edge 1"), std::string::npos) << w;
    EXPECT_NE(w.find("panel \"small\": edge 3"), std::string::npos) << w;
    EXPECT_NE(w.find("differ"), std::string::npos) << w;
}

struct BadGarmentCode {
    const char* name;
    std::string text;
    std::string where;
    std::string message; ///< a part of the message
};

TEST(GarmentCode, BadInputNamesTheJsonPointer) {
    const std::string square = squareSpec();
    auto replaced = [&](const std::string& from, const std::string& to) {
        std::string s = square;
        const std::size_t at = s.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        return s.replace(at, from.size(), to);
    };
    const BadGarmentCode cases[] = {
        {"not json", "{\"pattern\": ", "line 1, column 13", "invalid JSON"},
        {"no pattern", R"({"properties": {}})", "/", "missing \"pattern\""},
        {"vertex out of range", replaced("[3, 0]", "[3, 9]"),
         "/pattern/panels/front/edges/3/endpoints/1", "vertex 9 does not exist"},
        {"open loop", replaced(R"({"endpoints": [2, 3]})", R"({"endpoints": [2, 0]})"),
         "/pattern/panels/front/edges/3/endpoints", "must form one loop"},
        {"coordinate text", replaced("[30, 30]", "[30, \"a\"]"),
         "/pattern/panels/front/vertices/2/1", "expected a number"},
        {"units", replaced(R"("units_in_meter": 100)", R"("units_in_meter": -1)"),
         "/properties/units_in_meter", "within"},
        {"huge", replaced("[30, 30]", "[30, 1e9]"), "/pattern/panels/front/vertices/2",
         "coordinate beyond"},
        {"stitch panel",
         replaced(R"("stitches": [])",
                  R"("stitches": [[{"panel": "nope", "edge": 0},
                                                   {"panel": "front", "edge": 1}]])"),
         "/pattern/stitches/0/0/panel", "no panel named \"nope\""},
        {"stitch edge",
         replaced(R"("stitches": [])",
                  R"("stitches": [[{"panel": "front", "edge": 7},
                                                  {"panel": "front", "edge": 1}]])"),
         "/pattern/stitches/0/0/edge", "has no edge 7"},
        {"cubic params",
         replaced(R"({"endpoints": [0, 1]})",
                  R"({"endpoints": [0, 1], "curvature": {"type": "cubic",
                                      "params": [[0.3, 0.1]]}})"),
         "/pattern/panels/front/edges/0/curvature/params", "needs 2 control points"},
        {"no panels", R"({"pattern": {"panels": {}}})", "/pattern/panels", "no panels"},
    };
    for (const BadGarmentCode& c : cases) {
        auto r = parseSpec(c.text);
        ASSERT_FALSE(r.ok()) << c.name;
        EXPECT_EQ(r.error().file, "spec.json") << c.name;
        EXPECT_EQ(r.error().where, c.where) << c.name << ": " << r.error().toString();
        EXPECT_NE(r.error().message.find(c.message), std::string::npos)
            << c.name << ": " << r.error().toString();
    }
}

TEST(GarmentCode, CommentsAreAllowed) {
    const std::string spec = "// a comment\n" + squareSpec() + "\n/* and a block */\n";
    auto r = parseSpec(spec);
    ASSERT_TRUE(r.ok()) << r.error().toString();
    EXPECT_EQ(r.value().project.garment.panels.size(), 1u);
}

// ---- The specifications of ../shared/data/garmentcode ----

std::filesystem::path sharedSpec(const std::string& name) {
    return std::filesystem::path(ATELIER_SOURCE_DIR) / "../shared/data/garmentcode" / name;
}

#define REQUIRE_SPEC(path)                                                                         \
    if (!std::filesystem::is_regular_file(path)) {                                                 \
        GTEST_SKIP() << "test data absent: " << (path) << " (../shared/data beside the checkout)"; \
    }

TEST(GarmentCodeShared, SkirtTwoPanels) {
    const auto path = sharedSpec("skirt_2_panels.json");
    REQUIRE_SPEC(path);
    auto r = importGarmentCode(path, slotBody());
    ASSERT_TRUE(r.ok()) << r.error().toString();
    const patterns::Garment& g = r.value().project.garment;
    EXPECT_TRUE(r.value().warnings.empty()) << r.value().warnings.front();
    ASSERT_EQ(g.panels.size(), 2u);
    EXPECT_EQ(g.panels[0].name, "back"); // panel_order
    EXPECT_EQ(g.panels[0].placement.slot, "waist_back");
    EXPECT_EQ(g.panels[1].placement.slot, "waist_front");
    EXPECT_EQ(g.seams.size(), 4u);
    // units_in_meter 100: the hem (edge 0, 66.6 cm chord) in metres.
    const patterns::Segment& hem = g.panels[1].outline[0];
    EXPECT_NEAR((hem.end - hem.start).norm(), 0.666, 1e-9);
    EXPECT_EQ(hem.kind, SegmentKind::Quadratic);
}

TEST(GarmentCodeShared, ShirtMean) {
    const auto path = sharedSpec("shirt_mean_specification.json");
    REQUIRE_SPEC(path);
    auto r = importGarmentCode(path, slotBody());
    ASSERT_TRUE(r.ok()) << r.error().toString();
    const patterns::Garment& g = r.value().project.garment;
    EXPECT_TRUE(r.value().warnings.empty()) << r.value().warnings.front();
    ASSERT_EQ(g.panels.size(), 8u);
    EXPECT_EQ(g.seams.size(), 18u);
    int arms = 0, cubic = 0;
    for (const patterns::Panel& p : g.panels) {
        EXPECT_GT(patterns::loopArea(p.outline), 0) << p.name;
        const bool sleeve = p.name.find("sleeve") != std::string::npos;
        arms += sleeve;
        EXPECT_EQ(p.placement.slot.starts_with("arm_"), sleeve) << p.name;
        if (!sleeve) {
            EXPECT_TRUE(p.placement.slot.starts_with("torso_")) << p.name;
        }
        for (const patterns::Segment& s : p.outline) {
            cubic += s.kind == SegmentKind::Cubic;
        }
    }
    EXPECT_EQ(arms, 4);
    EXPECT_EQ(cubic, 16);
    // Left and right mirror each other.
    const auto& lf = g.panels[static_cast<std::size_t>(g.panelIndex("left_ftorso"))];
    const auto& rf = g.panels[static_cast<std::size_t>(g.panelIndex("right_ftorso"))];
    EXPECT_NEAR(lf.placement.offset.x(), -rf.placement.offset.x(), 1e-6);
    EXPECT_NEAR(lf.placement.offset.y(), rf.placement.offset.y(), 1e-6);
}

TEST(GarmentCodeShared, AnnotatedTemplateWithComments) {
    const auto path = sharedSpec("template_spec_with_comments.json");
    REQUIRE_SPEC(path);
    auto r = importGarmentCode(path, slotBody());
    ASSERT_TRUE(r.ok()) << r.error().toString();
    EXPECT_EQ(r.value().project.garment.panels.size(), 2u);
    // units_in_meter 300: the front's top edge (110 units) is 36.7 cm.
    const auto& g = r.value().project.garment;
    const auto& front = g.panels[static_cast<std::size_t>(g.panelIndex("front"))];
    double longest = 0;
    for (const patterns::Segment& s : front.outline) {
        longest = std::max(longest, (s.end - s.start).norm());
    }
    EXPECT_NEAR(longest, 264.0 / 300, 1e-9);
}

} // namespace
} // namespace atelier::io
