// The pattern as SVG (io/pattern_svg): written for every sample garment and for hand-made
// panels (arcs over 180°, a dart, a hole, a mirrored Back panel, names to escape), then read
// back with the test's own XML reader and path sampler: well-formed, real size in mm, every
// panel present, sewing lines as long as the outlines, cut lines the allowance outside them,
// no two panels overlapping.
#include "io/pattern_svg.h"
#include "io/svg_reader.h"
#include "io/temp_dir.h"
#include "io/xml_text.h"

#include "patterns/curve.h"
#include "patterns/loops.h"
#include "patterns/sample_garments.h"
#include "patterns/seam_allowance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

namespace atelier::io {
namespace {

using test::line;

using patterns::Segment;
using patterns::SegmentKind;
using sim::Vec2;
using test::SampledSubpath;
using test::samplePath;
using test::XmlNode;

Segment curve(SegmentKind kind, Vec2 a, Vec2 b, Vec2 c1, Vec2 c2 = Vec2::Zero(), double bulge = 0) {
    Segment s = line(a, b);
    s.kind = kind;
    s.control1 = c1;
    s.control2 = c2;
    s.bulge = bulge;
    return s;
}

/// Two panels: "<a&b>", with a cubic, a quadratic and an arc of 225°, drawn as Front; and a
/// Back panel with a dart, a square hole, notches and an internal fold; a seam between them
/// whose name needs escaping too.
patterns::Garment handMade() {
    patterns::Garment g;
    g.name = "hand & made";
    patterns::Panel a;
    a.name = "<a&b>";
    a.material = "main";
    a.outline = {line({0, 0}, {0.2, 0}),
                 curve(SegmentKind::Arc, {0.2, 0}, {0.2, 0.2}, Vec2::Zero(), Vec2::Zero(), 1.5),
                 curve(SegmentKind::Cubic, {0.2, 0.2}, {0, 0.2}, {0.15, 0.3}, {0.05, 0.3}),
                 curve(SegmentKind::Quadratic, {0, 0.2}, {0, 0}, {-0.05, 0.1})};
    a.notches = {{0, 0.5}, {2, 0.25}};
    patterns::Panel b;
    b.name = "darted";
    b.material = "main";
    b.side = patterns::PanelSide::Back;
    b.grainAngle = 0.3;
    b.outline = {line({0, 0}, {0.09, 0}),      line({0.09, 0}, {0.1, 0.08}),
                 line({0.1, 0.08}, {0.11, 0}), line({0.11, 0}, {0.2, 0}),
                 line({0.2, 0}, {0.2, 0.3}),   line({0.2, 0.3}, {0, 0.3}),
                 line({0, 0.3}, {0, 0})};
    b.darts = {{1}};
    b.holes = {{line({0.06, 0.15}, {0.06, 0.2}), line({0.06, 0.2}, {0.14, 0.2}),
                line({0.14, 0.2}, {0.14, 0.15}), line({0.14, 0.15}, {0.06, 0.15})}};
    b.notches = {{4, 0.5}};
    b.internalLines = {{{line({0.02, 0.25}, {0.18, 0.25})}, 0.5}};
    g.panels = {a, b};
    g.seams = {{"side \"1\" & <2>", {{"<a&b>", 1, 0, 1}}, {{"darted", 4, 0, 1}}}};
    patterns::GarmentMaterial main;
    main.name = "main";
    main.material.name = "cotton";
    g.materials = {main};
    return g;
}

double perimeterMm(const patterns::Loop& loop) {
    double length = 0;
    for (const Segment& s : loop) {
        length += patterns::arcLength(s);
    }
    return 1000 * length;
}

/// The sampled subpaths of a `<path>`, failing the test on bad path data.
std::vector<SampledSubpath> sampled(const XmlNode& path, int samplesPerCurve = 200) {
    auto sub = samplePath(path.attribute("d"), samplesPerCurve);
    EXPECT_TRUE(sub.has_value()) << "bad path data: " << path.attribute("d").substr(0, 200);
    return sub.value_or(std::vector<SampledSubpath>{});
}

/// The `<path>` children of a group with exactly this class.
std::vector<const XmlNode*> pathsOfClass(const XmlNode& group, const std::string& cls) {
    std::vector<const XmlNode*> out;
    for (const XmlNode* p : group.all("path")) {
        if (p->attribute("class") == cls) {
            out.push_back(p);
        }
    }
    return out;
}

double distanceToPolylines(const std::vector<std::vector<Vec2>>& polylines, const Vec2& p) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto& poly : polylines) {
        best = std::min(best, patterns::distanceToPolyline(poly, p));
    }
    return best;
}

struct Box {
    Vec2 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
    Vec2 hi = -lo;
    void add(const Vec2& p) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    bool overlaps(const Box& o) const {
        return lo.x() < o.hi.x() && o.lo.x() < hi.x() && lo.y() < o.hi.y() && o.lo.y() < hi.y();
    }
};

/// Reads `svg` back and checks everything the writer promises for `garment` at `allowanceMm`.
void checkPattern(const PatternSvg& svg, const patterns::Garment& garment, double allowanceMm) {
    test::XmlReader reader(svg.text);
    const std::optional<XmlNode> root = reader.parse();
    ASSERT_TRUE(root.has_value()) << "not well-formed XML: " << reader.error();
    ASSERT_EQ(root->name, "svg");
    EXPECT_EQ(root->attribute("xmlns"), "http://www.w3.org/2000/svg");

    // Real size: width and height in mm, and a viewBox of as many units.
    const std::string width = root->attribute("width"), height = root->attribute("height");
    ASSERT_TRUE(width.ends_with("mm") && height.ends_with("mm")) << width << " " << height;
    const double w = std::stod(width), h = std::stod(height);
    EXPECT_DOUBLE_EQ(w, svg.widthMm);
    EXPECT_DOUBLE_EQ(h, svg.heightMm);
    std::istringstream viewBox(root->attribute("viewBox"));
    double vx = -1, vy = -1, vw = -1, vh = -1;
    viewBox >> vx >> vy >> vw >> vh;
    EXPECT_EQ(vx, 0);
    EXPECT_EQ(vy, 0);
    EXPECT_EQ(vw, w);
    EXPECT_EQ(vh, h);

    // Every panel: a group with the panel's name as title, in order.
    std::vector<const XmlNode*> panels;
    const XmlNode* calibration = nullptr;
    for (const XmlNode* g : root->all("g")) {
        if (g->attribute("class") == "panel") {
            panels.push_back(g);
        } else if (g->attribute("id") == "calibration") {
            calibration = g;
        }
    }
    ASSERT_EQ(panels.size(), garment.panels.size());
    ASSERT_NE(calibration, nullptr);

    std::vector<Box> boxes;
    for (std::size_t i = 0; i < panels.size(); ++i) {
        const patterns::Panel& panel = garment.panels[i];
        SCOPED_TRACE("panel " + panel.name);
        const XmlNode& group = *panels[i];
        const auto titles = group.all("title");
        ASSERT_EQ(titles.size(), 1U);
        EXPECT_EQ(titles[0]->allText(), panel.name);
        const std::string labels = [&] {
            std::string s;
            for (const XmlNode* t : group.all("text")) {
                if (t->attribute("class") == "label") {
                    s += t->allText() + "|";
                }
            }
            return s;
        }();
        EXPECT_NE(labels.find(panel.name), std::string::npos) << labels;
        EXPECT_NE(labels.find(panel.side == patterns::PanelSide::Back ? "cut 1 mirrored" : "cut 1"),
                  std::string::npos)
            << labels;

        // The sewing line is the outline, as long as it.
        const auto sewing = pathsOfClass(group, "sewing-line");
        ASSERT_EQ(sewing.size(), 1U);
        const auto outline = sampled(*sewing[0], 2000);
        ASSERT_EQ(outline.size(), 1U);
        EXPECT_TRUE(outline[0].closed);
        const double expected = perimeterMm(panel.outline);
        EXPECT_NEAR(test::pathLength(outline[0]), expected, std::max(0.01, 1e-5 * expected));
        const auto holes = pathsOfClass(group, "sewing-line hole");
        ASSERT_EQ(holes.size(), panel.holes.size());

        // The fabric's edges as polylines (outline and holes) [mm].
        std::vector<std::vector<Vec2>> edges = {sampled(*sewing[0])[0].points};
        for (std::size_t k = 0; k < holes.size(); ++k) {
            const auto hole = sampled(*holes[k], 2000);
            ASSERT_EQ(hole.size(), 1U);
            EXPECT_NEAR(test::pathLength(hole[0]), perimeterMm(panel.holes[k]), 0.01);
            edges.push_back(sampled(*holes[k])[0].points);
        }
        auto inFabric = [&](const Vec2& p) {
            if (!patterns::insidePolyline(edges[0], p)) {
                return false;
            }
            for (std::size_t k = 1; k < edges.size(); ++k) {
                if (patterns::insidePolyline(edges[k], p)) {
                    return false;
                }
            }
            return true;
        };

        // The cut line: every point (vertices and the middles between them) the allowance
        // away from the fabric, outside it.
        const auto cut = pathsOfClass(group, "cut-line");
        ASSERT_EQ(cut.size(), 1U);
        const auto cutLoops = sampled(*cut[0]);
        ASSERT_GE(cutLoops.size(), 1U);
        double worst = 0;
        int inside = 0, points = 0;
        for (const SampledSubpath& loop : cutLoops) {
            EXPECT_TRUE(loop.closed);
            for (std::size_t k = 0; k < loop.points.size(); ++k) {
                const Vec2& p = loop.points[k];
                const Vec2 mid = 0.5 * (p + loop.points[(k + 1) % loop.points.size()]);
                for (const Vec2& q : {p, mid}) {
                    worst = std::max(worst, std::abs(distanceToPolylines(edges, q) - allowanceMm));
                    inside += allowanceMm > 0 && inFabric(q) ? 1 : 0;
                    ++points;
                }
            }
        }
        // 0.02 mm curve tolerance of the offset, 0.001 mm rounding, chords of the samples.
        EXPECT_LT(worst, 0.05) << "over " << points << " points";
        std::string key = "cut_line_error_mm_" + garment.name + "_" + panel.name;
        std::replace_if(
            key.begin(), key.end(), [](char c) { return !std::isalnum(c); }, '_');
        ::testing::Test::RecordProperty(key, std::to_string(worst));
        EXPECT_EQ(inside, 0);
        if (allowanceMm > 0) {
            // The outline lies inside the outermost cut loop.
            const auto outer = std::max_element(
                cutLoops.begin(), cutLoops.end(), [](const auto& a, const auto& b) {
                    return std::abs(patterns::polylineArea(a.points)) <
                           std::abs(patterns::polylineArea(b.points));
                });
            for (const Vec2& p : edges[0]) {
                ASSERT_TRUE(patterns::insidePolyline(outer->points, p));
            }
        }

        // Everything drawn within the sheet; no two panels' drawings overlap.
        Box box;
        for (const XmlNode* path : group.all("path")) {
            for (const SampledSubpath& sub : sampled(*path)) {
                for (const Vec2& p : sub.points) {
                    box.add(p);
                }
            }
        }
        EXPECT_GE(box.lo.x(), 0);
        EXPECT_GE(box.lo.y(), 0);
        EXPECT_LE(box.hi.x(), w);
        EXPECT_LE(box.hi.y(), h);
        EXPECT_GE(box.lo.x(), svg.panels[i].minX - 1e-3);
        EXPECT_LE(box.hi.x(), svg.panels[i].maxX + 1e-3);
        boxes.push_back(box);
        // The grain line along the warp (mirrored for a Back panel; y down the sheet), from
        // in the fabric; the label in it too.
        const auto grain = pathsOfClass(group, "grain-line");
        ASSERT_EQ(grain.size(), 1U);
        const auto arrow = sampled(*grain[0]);
        ASSERT_GE(arrow.size(), 1U);
        const Vec2 along = (arrow[0].points.back() - arrow[0].points.front()).normalized();
        const double sx = panel.side == patterns::PanelSide::Back ? -1 : 1;
        const Vec2 warp(sx * std::cos(panel.grainAngle), -std::sin(panel.grainAngle));
        EXPECT_NEAR(std::abs(along.dot(warp)), 1, 1e-6);
        EXPECT_TRUE(inFabric(arrow[0].points.front()));
        EXPECT_TRUE(inFabric(arrow[0].points.back()));
        for (const XmlNode* t : group.all("text")) {
            if (t->attribute("class") == "label") {
                const auto lines = t->all("tspan");
                ASSERT_EQ(lines.size(), 3U);
                const Vec2 at(std::stod(lines[1]->attribute("x")),
                              std::stod(lines[1]->attribute("y")));
                EXPECT_TRUE(inFabric(at));
            }
        }
    }
    Box square;
    for (const XmlNode* path : calibration->all("path")) {
        for (const SampledSubpath& sub : sampled(*path)) {
            for (const Vec2& p : sub.points) {
                square.add(p);
            }
        }
    }
    EXPECT_NEAR(square.hi.x() - square.lo.x(), 100, 1e-9);
    EXPECT_NEAR(square.hi.y() - square.lo.y(), 100, 1e-9);
    boxes.push_back(square);
    for (std::size_t i = 0; i < boxes.size(); ++i) {
        for (std::size_t j = i + 1; j < boxes.size(); ++j) {
            EXPECT_FALSE(boxes[i].overlaps(boxes[j])) << "drawings " << i << " and " << j;
        }
    }
}

TEST(PatternSvg, EverySampleGarmentAtTheDefaultAllowance) {
    const auto& samples = test::sampleGarments();
    ASSERT_EQ(samples.size(), 4U);
    for (const auto& [name, garment] : samples) {
        SCOPED_TRACE(name);
        const auto svg = patternSvg(garment, {});
        ASSERT_TRUE(svg.ok()) << svg.error().toString();
        checkPattern(svg.value(), garment, 10.0);
    }
}

TEST(PatternSvg, HandMadePanelsAtSeveralAllowances) {
    const patterns::Garment garment = handMade();
    for (double allowance : {0.0, 3.0, 10.0, 25.0}) {
        SCOPED_TRACE("allowance " + std::to_string(allowance));
        PatternSvgOptions options;
        options.seamAllowanceMm = allowance;
        const auto svg = patternSvg(garment, options);
        ASSERT_TRUE(svg.ok()) << svg.error().toString();
        checkPattern(svg.value(), garment, allowance);
    }
}

TEST(PatternSvg, ASheetWidthAskedForIsKeptOrRefusedNamingTheWidestPanel) {
    const patterns::Garment& trousers = test::sampleGarments().at("trousers");
    PatternSvgOptions options;
    options.sheetWidthMm = 914; // a 36-inch plotter roll
    const auto svg = patternSvg(trousers, options);
    ASSERT_TRUE(svg.ok()) << svg.error().toString();
    EXPECT_EQ(svg.value().widthMm, 914);
    checkPattern(svg.value(), trousers, 10.0);
    // The chosen width gives a smaller sheet than the roll.
    const auto chosen = patternSvg(trousers, {});
    ASSERT_TRUE(chosen.ok());
    EXPECT_LT(chosen.value().widthMm * chosen.value().heightMm,
              svg.value().widthMm * svg.value().heightMm);
    options.sheetWidthMm = 300;
    const auto narrow = patternSvg(trousers, options);
    ASSERT_FALSE(narrow.ok());
    EXPECT_EQ(narrow.error().where.rfind("panel \"", 0), 0U) << narrow.error().toString();
    EXPECT_NE(narrow.error().message.find("300 mm sheet"), std::string::npos);
}

TEST(PatternSvg, NamesAreEscapedAndReadBackWhole) {
    const patterns::Garment garment = handMade();
    const auto svg = patternSvg(garment, {});
    ASSERT_TRUE(svg.ok()) << svg.error().toString();
    EXPECT_EQ(svg.value().text.find("<a&b>"), std::string::npos);
    const auto root = test::XmlReader(svg.value().text).parse();
    ASSERT_TRUE(root.has_value());
    EXPECT_EQ(root->all("title")[0]->allText(), "hand & made pattern");
    std::vector<std::string> seamLabels;
    for (const XmlNode* t : root->all("text")) {
        if (t->attribute("class") == "seam-label") {
            seamLabels.push_back(t->allText());
        }
    }
    // One label per seam edge: the seam has one edge on each panel.
    ASSERT_EQ(seamLabels.size(), 2U);
    EXPECT_EQ(seamLabels[0], "side \"1\" & <2>");
    EXPECT_EQ(xmlEscape(std::string("a\x01<\"'>&") + "\t"), "a &lt;&quot;&apos;&gt;&amp;\t");
    // Bytes that are not UTF-8 become U+FFFD; valid sequences pass.
    EXPECT_EQ(xmlEscape("\xC3\xA9t\xE9"), "\xC3\xA9t\xEF\xBF\xBD");
}

TEST(PatternSvg, CurvesAreTrueCurvesAndBackPanelsAreMirrored) {
    patterns::Garment garment = handMade();
    for (const auto side : {patterns::PanelSide::Front, patterns::PanelSide::Back}) {
        SCOPED_TRACE(side == patterns::PanelSide::Back ? "back" : "front");
        garment.panels[0].side = side;
        const auto svg = patternSvg(garment, {});
        ASSERT_TRUE(svg.ok()) << svg.error().toString();
        const auto root = test::XmlReader(svg.value().text).parse();
        ASSERT_TRUE(root.has_value());
        const XmlNode* group = nullptr;
        for (const XmlNode* g : root->all("g")) {
            if (g->attribute("id") == "panel-0") {
                group = g;
            }
        }
        ASSERT_NE(group, nullptr);
        const auto sewing = pathsOfClass(*group, "sewing-line");
        ASSERT_EQ(sewing.size(), 1U);
        const std::string d = sewing[0]->attribute("d");
        // One command per segment: a line, two arc halves (225° > 180°), a cubic, a quadratic.
        EXPECT_EQ(std::count(d.begin(), d.end(), 'L'), 1);
        EXPECT_EQ(std::count(d.begin(), d.end(), 'A'), 2);
        EXPECT_EQ(std::count(d.begin(), d.end(), 'C'), 1);
        EXPECT_EQ(std::count(d.begin(), d.end(), 'Q'), 1);
        // Each point of the outline, mapped (y down, x mirrored for Back) and moved as the
        // first one was, lies on the drawn path.
        const auto drawn = sampled(*sewing[0], 2000);
        ASSERT_EQ(drawn.size(), 1U);
        const double sx = side == patterns::PanelSide::Back ? -1 : 1;
        auto map = [&](const Vec2& p) { return Vec2(1000 * sx * p.x(), -1000 * p.y()); };
        const Vec2 shift = drawn[0].points.front() - map(garment.panels[0].outline[0].start);
        double worst = 0;
        for (const Segment& s : garment.panels[0].outline) {
            for (int k = 0; k <= 50; ++k) {
                const Vec2 expected = map(patterns::pointAt(s, k / 50.0)) + shift;
                worst = std::max(worst, patterns::distanceToPolyline(drawn[0].points, expected));
            }
        }
        EXPECT_LT(worst, 0.01);
    }
}

TEST(PatternSvg, BadOptionsAndGarmentsAreErrors) {
    const patterns::Garment garment = handMade();
    for (double bad : {-1.0, std::numeric_limits<double>::quiet_NaN(), MAX_SEAM_ALLOWANCE_MM + 1}) {
        PatternSvgOptions options;
        options.seamAllowanceMm = bad;
        const auto svg = patternSvg(garment, options);
        ASSERT_FALSE(svg.ok());
        EXPECT_NE(svg.error().message.find("seam allowance"), std::string::npos);
    }
    EXPECT_FALSE(patternSvg(patterns::Garment{}, {}).ok());
    patterns::Garment broken = garment;
    broken.seams[0].a[0].segment = 9;
    const auto svg = patternSvg(broken, {});
    ASSERT_FALSE(svg.ok());
    EXPECT_EQ(svg.error().where, "seam \"side \"1\" & <2>\"");
}

/// A regular polygon of `n` corners and radius 0.5 m as line segments.
patterns::Panel polygonPanel(int n) {
    patterns::Panel panel;
    panel.name = "polygon";
    for (int k = 0; k < n; ++k) {
        const double a0 = 2 * std::numbers::pi * k / n, a1 = 2 * std::numbers::pi * (k + 1) / n;
        panel.outline.push_back(
            line(0.5 * Vec2(std::cos(a0), std::sin(a0)), 0.5 * Vec2(std::cos(a1), std::sin(a1))));
    }
    return panel;
}

TEST(PatternSvg, APanelOverThePointLimitIsRefusedBeforeTheOffset) {
    patterns::Garment garment;
    garment.panels = {polygonPanel(static_cast<int>(MAX_PANEL_POINTS) + 1)};
    const auto svg = patternSvg(garment, {});
    ASSERT_FALSE(svg.ok());
    EXPECT_EQ(svg.error().where, "panel \"polygon\"");
    EXPECT_NE(svg.error().message.find("more than 20000"), std::string::npos)
        << svg.error().message;
}

TEST(PatternSvg, WrittenAtomicallyAndRefusedWhereTheFolderIsMissing) {
    const test::TempDir dir;
    const auto path = dir / "pattern.svg";
    const auto written = writePatternSvg(path, handMade(), {});
    ASSERT_TRUE(written.ok()) << written.error().toString();
    EXPECT_EQ(test::readText(path), written.value().text);
    EXPECT_FALSE(writePatternSvg(dir / "missing" / "pattern.svg", handMade(), {}).ok());
}

} // namespace
} // namespace atelier::io
