#include "io/dxf_aama.h"
#include "io/project_file.h"

#include "patterns/curve.h"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace atelier::io {
namespace {

using patterns::SegmentKind;
using patterns::Vec2;

/// Writes DXF group pairs the way pattern CAD exports do (code and value on their own lines).
class DxfWriter {
  public:
    DxfWriter& group(int code, const std::string& value) {
        m_out << code << "\n" << value << "\n";
        return *this;
    }
    DxfWriter& group(int code, double value) {
        std::ostringstream v;
        v.precision(10);
        v << value;
        return group(code, v.str());
    }
    DxfWriter& polyline(int layer, const std::vector<Vec2>& points, bool closed,
                        const std::vector<double>& bulges = {}) {
        group(0, "POLYLINE").group(8, std::to_string(layer)).group(66, "1");
        group(70, closed ? "1" : "0");
        for (std::size_t i = 0; i < points.size(); ++i) {
            group(0, "VERTEX").group(8, std::to_string(layer));
            group(10, points[i].x()).group(20, points[i].y());
            if (i < bulges.size() && bulges[i] != 0) {
                group(42, bulges[i]);
            }
        }
        return group(0, "SEQEND");
    }
    DxfWriter& lwpolyline(int layer, const std::vector<Vec2>& points, bool closed) {
        group(0, "LWPOLYLINE").group(8, std::to_string(layer));
        group(90, std::to_string(points.size())).group(70, closed ? "1" : "0");
        for (const Vec2& p : points) {
            group(10, p.x()).group(20, p.y());
        }
        return *this;
    }
    DxfWriter& line(int layer, Vec2 a, Vec2 b) {
        group(0, "LINE").group(8, std::to_string(layer));
        return group(10, a.x()).group(20, a.y()).group(11, b.x()).group(21, b.y());
    }
    DxfWriter& point(int layer, Vec2 p) {
        return group(0, "POINT").group(8, std::to_string(layer)).group(10, p.x()).group(20, p.y());
    }
    DxfWriter& text(int layer, const std::string& t) {
        return group(0, "TEXT").group(8, std::to_string(layer)).group(1, t);
    }
    std::string str() const { return m_out.str(); }

  private:
    std::ostringstream m_out;
};

/// The front: a 400 × 600 rectangle (file units) with a half-circle neckline of radius 80
/// scooped from the middle of its top edge, digitised at 40 spans; turn points at its six
/// corners, two notches on the hem, a grain line, an internal line and a square cut-out.
void writeFront(DxfWriter& w, double s) {
    std::vector<Vec2> cut = {Vec2(0, 0), Vec2(400, 0), Vec2(400, 600), Vec2(280, 600)};
    for (int k = 1; k < 40; ++k) { // from (280, 600) down round to (120, 600)
        const double a = -std::numbers::pi * k / 40;
        cut.emplace_back(200 + 80 * std::cos(a), 600 + 80 * std::sin(a));
    }
    cut.emplace_back(120, 600);
    cut.emplace_back(0, 600);
    for (Vec2& p : cut) {
        p *= s;
    }
    w.group(0, "BLOCK").group(8, "1").group(2, "FRONT-BLOCK").group(70, "0");
    w.group(10, 0.0).group(20, 0.0);
    w.polyline(1, cut, true);
    for (const Vec2& c :
         {Vec2(0, 0), Vec2(400, 0), Vec2(400, 600), Vec2(280, 600), Vec2(120, 600), Vec2(0, 600)}) {
        w.point(2, c * s);
    }
    for (int k = 1; k < 40; ++k) {
        const double a = -std::numbers::pi * k / 40;
        w.point(3, Vec2(200 + 80 * std::cos(a), 600 + 80 * std::sin(a)) * s);
    }
    w.line(4, Vec2(100, 0) * s, Vec2(100, 6) * s);
    w.line(4, Vec2(300, 0) * s, Vec2(300, 6) * s);
    w.line(7, Vec2(200, 100) * s, Vec2(200, 450) * s);
    w.line(8, Vec2(60, 300) * s, Vec2(340, 300) * s);
    w.polyline(11, {Vec2(180, 150) * s, Vec2(220, 150) * s, Vec2(220, 190) * s, Vec2(180, 190) * s},
               true);
    w.text(1, "Piece Name: FRONT").text(1, "Quantity: 1").text(1, "Size: M");
    w.group(0, "ENDBLK");
}

/// The back: a plain 400 × 600 rectangle drawn clockwise as an LWPOLYLINE, no turn points (its
/// corners are found from the turns), a sew line and a drill hole not imported, quantity 2.
void writeBack(DxfWriter& w, double s) {
    w.group(0, "BLOCK").group(8, "1").group(2, "BACK-BLOCK").group(70, "0");
    w.lwpolyline(1, {Vec2(0, 0) * s, Vec2(0, 600) * s, Vec2(400, 600) * s, Vec2(400, 0) * s}, true);
    w.polyline(14, {Vec2(10, 10) * s, Vec2(10, 590) * s}, false);
    w.point(13, Vec2(200, 300) * s);
    w.text(1, "Piece Name: BACK").text(1, "Quantity: 2");
    w.group(0, "ENDBLK");
}

std::string twoPieces(const std::string& units, double s, const std::string& insUnits = "") {
    DxfWriter w;
    w.group(999, "written by the Atelier tests");
    if (!insUnits.empty()) {
        w.group(0, "SECTION").group(2, "HEADER").group(9, "$INSUNITS").group(70, insUnits);
        w.group(0, "ENDSEC");
    }
    w.group(0, "SECTION").group(2, "BLOCKS");
    writeFront(w, s);
    writeBack(w, s);
    w.group(0, "ENDSEC");
    w.group(0, "SECTION").group(2, "ENTITIES");
    w.group(0, "INSERT").group(8, "1").group(2, "FRONT-BLOCK").group(10, 0.0).group(20, 0.0);
    w.group(0, "INSERT").group(8, "1").group(2, "BACK-BLOCK").group(10, 500.0).group(20, 0.0);
    if (!units.empty()) {
        w.text(1, "Style Name: TEE").text(1, "Units: " + units);
    }
    w.group(0, "ENDSEC").group(0, "EOF");
    return w.str();
}

/// The front's cut line length, exactly: the rectangle less the neckline's chord plus its
/// half circle [file units].
const double FRONT_CUT = 400 + 600 + 120 + 120 + 600 + std::numbers::pi * 80;

double signedArea(const patterns::Loop& loop) {
    double a = 0;
    for (const patterns::Segment& s : loop) {
        for (int k = 0; k < 64; ++k) {
            const Vec2 p = patterns::pointAt(s, k / 64.0);
            const Vec2 q = patterns::pointAt(s, (k + 1) / 64.0);
            a += p.x() * q.y() - p.y() * q.x();
        }
    }
    return 0.5 * a;
}

bool mentions(const std::vector<std::string>& warnings, const std::string& part) {
    for (const std::string& w : warnings) {
        if (w.find(part) != std::string::npos) {
            return true;
        }
    }
    return false;
}

TEST(DxfAama, TwoPiecesImportWithTheirOutlinesNotchesGrainAndHoles) {
    auto imported = parseDxfAama(twoPieces("METRIC", 1.0), "tee.dxf");
    ASSERT_TRUE(imported.ok()) << imported.error().toString();
    const DxfImport& r = imported.value();
    EXPECT_EQ(r.units, "mm (Units: METRIC)");
    ASSERT_EQ(r.pieces.size(), 2u);
    const auto& panels = r.project.garment.panels;
    ASSERT_EQ(panels.size(), 2u);
    EXPECT_EQ(panels[0].name, "FRONT");
    EXPECT_EQ(panels[1].name, "BACK");
    EXPECT_EQ(r.pieces[0].block, "FRONT-BLOCK");
    EXPECT_EQ(r.project.name, "tee");

    // FRONT: the digitised line (40 chords of the half circle) and the imported outline, whose
    // fitted curve follows the circle itself, both near the exact length.
    const DxfPiece& front = r.pieces[0];
    const double chords = 1840 + 2 * 40 * 80 * std::sin(std::numbers::pi / 80);
    EXPECT_NEAR(front.cutLength * 1000, chords, 1e-6);
    EXPECT_NEAR(front.outlineLength * 1000, FRONT_CUT, 0.3);
    EXPECT_LE(front.fitError, 0.0002);
    EXPECT_EQ(front.corners, 6);
    EXPECT_EQ(front.cutPoints, 45);
    // Five straight edges and a few cubics for the neckline, not 45 spans.
    EXPECT_LE(front.segments, 9);
    int lines = 0;
    int cubics = 0;
    for (const patterns::Segment& s : panels[0].outline) {
        lines += s.kind == SegmentKind::Line;
        cubics += s.kind == SegmentKind::Cubic;
        // Every point of the neckline's curves is on the circle within the tolerance.
        if (s.kind == SegmentKind::Cubic) {
            for (int k = 0; k <= 20; ++k) {
                const Vec2 p = patterns::pointAt(s, k / 20.0) * 1000 + Vec2(200, 300);
                EXPECT_NEAR((p - Vec2(200, 600)).norm(), 80, 0.25);
            }
        }
    }
    EXPECT_EQ(lines, 5);
    EXPECT_GE(cubics, 1);
    // Counter-clockwise, the area of the rectangle less the half disc [m²], within the band
    // the fit tolerance allows along the neckline (0.2 mm × 251 mm).
    EXPECT_NEAR(signedArea(panels[0].outline), 0.24 - std::numbers::pi * 0.08 * 0.08 / 2, 5e-5);
    // Notches on the hem at x = 100 and 300 (the piece is centred on its box: y = -300).
    ASSERT_EQ(panels[0].notches.size(), 2u);
    std::vector<double> xs;
    for (const patterns::Notch& n : panels[0].notches) {
        const Vec2 p =
            patterns::pointAt(panels[0].outline[static_cast<std::size_t>(n.segment)], n.t) * 1000;
        EXPECT_NEAR(p.y(), -300, 1e-6);
        xs.push_back(p.x());
    }
    std::sort(xs.begin(), xs.end());
    EXPECT_NEAR(xs[0], -100, 1e-6);
    EXPECT_NEAR(xs[1], 100, 1e-6);
    EXPECT_NEAR(panels[0].grainAngle, std::numbers::pi / 2, 1e-12);
    EXPECT_TRUE(front.grainLine);
    ASSERT_EQ(panels[0].internalLines.size(), 1u);
    EXPECT_NEAR(patterns::arcLength(panels[0].internalLines[0].path[0]), 0.28, 1e-12);
    ASSERT_EQ(panels[0].holes.size(), 1u);
    EXPECT_NEAR(std::abs(signedArea(panels[0].holes[0])), 0.04 * 0.04, 1e-12);

    // BACK: drawn clockwise, read counter-clockwise; four corners found from the turns.
    const DxfPiece& back = r.pieces[1];
    EXPECT_EQ(back.corners, 4);
    EXPECT_EQ(back.segments, 4);
    EXPECT_NEAR(signedArea(panels[1].outline), 0.24, 1e-12);
    EXPECT_NEAR(back.outlineLength, 2.0, 1e-12);
    EXPECT_EQ(back.quantity, 2);
    EXPECT_FALSE(back.grainLine);
    EXPECT_TRUE(mentions(r.warnings, "piece \"BACK\": Quantity 2"));
    EXPECT_TRUE(mentions(r.warnings, "sew lines (layer 14)"));
    EXPECT_TRUE(mentions(r.warnings, "drill holes (layer 13)"));
    EXPECT_TRUE(mentions(r.warnings, "piece \"BACK\": no grain line"));

    // Unsewn, laid front and back on the torso, in the cotton preset.
    EXPECT_TRUE(r.project.garment.seams.empty());
    EXPECT_EQ(panels[0].placement.slot, "torso_front");
    EXPECT_EQ(panels[1].placement.slot, "torso_back");
    EXPECT_EQ(panels[0].material, "fabric");
}

TEST(DxfAama, UnitsComeFromTheStyleTextTheHeaderOrTheCaller) {
    // ENGLISH: inches. The same shapes drawn at 1/25.4 give the same metres.
    auto english = parseDxfAama(twoPieces("ENGLISH", 1 / 25.4), "tee.dxf");
    ASSERT_TRUE(english.ok()) << english.error().toString();
    EXPECT_EQ(english.value().units, "in (Units: ENGLISH)");
    EXPECT_NEAR(english.value().pieces[1].outlineLength, 2.0, 1e-9);
    // $INSUNITS 5: centimetres.
    auto cm = parseDxfAama(twoPieces("", 0.1, "5"), "tee.dxf");
    ASSERT_TRUE(cm.ok()) << cm.error().toString();
    EXPECT_EQ(cm.value().units, "cm ($INSUNITS 5)");
    EXPECT_NEAR(cm.value().pieces[1].outlineLength, 2.0, 1e-9);
    // Nothing said: millimetres, with a warning.
    auto none = parseDxfAama(twoPieces("", 1.0), "tee.dxf");
    ASSERT_TRUE(none.ok()) << none.error().toString();
    EXPECT_EQ(none.value().units, "mm (assumed)");
    EXPECT_TRUE(mentions(none.value().warnings, "does not state its units"));
    // The caller overrides the file.
    DxfImportOptions options;
    options.units = "cm";
    auto asked = parseDxfAama(twoPieces("METRIC", 0.1), "tee.dxf", options);
    ASSERT_TRUE(asked.ok()) << asked.error().toString();
    EXPECT_NEAR(asked.value().pieces[1].outlineLength, 2.0, 1e-9);
}

TEST(DxfAama, BulgesBecomeArcs) {
    // A 200 × 100 piece whose top edge is a half circle (bulge 1) from (200, 100) to (0, 100).
    DxfWriter w;
    w.group(0, "SECTION").group(2, "BLOCKS").group(0, "BLOCK").group(2, "CAP");
    w.polyline(1, {Vec2(0, 0), Vec2(200, 0), Vec2(200, 100), Vec2(0, 100)}, true, {0, 0, 1, 0});
    w.group(0, "ENDBLK").group(0, "ENDSEC").group(0, "EOF");
    auto imported = parseDxfAama(w.str(), "cap.dxf", DxfImportOptions{.units = "mm"});
    ASSERT_TRUE(imported.ok()) << imported.error().toString();
    const auto& outline = imported.value().project.garment.panels[0].outline;
    int arcs = 0;
    for (const patterns::Segment& s : outline) {
        arcs += s.kind == SegmentKind::Arc;
    }
    EXPECT_EQ(arcs, 1);
    EXPECT_NEAR(imported.value().pieces[0].outlineLength, 0.2 + 0.1 + 0.1 + std::numbers::pi * 0.1,
                1e-9);
    // The area with the half disc above (64 chords per segment: 6e-6 m² short of the circle).
    EXPECT_NEAR(signedArea(outline), 0.02 + std::numbers::pi * 0.01 / 2, 1e-5);
    EXPECT_EQ(imported.value().project.garment.panels[0].name, "CAP");
}

void expectError(const std::string& text, const std::string& where, const std::string& part) {
    auto imported = parseDxfAama(text, "bad.dxf");
    ASSERT_FALSE(imported.ok()) << "expected an error about " << part;
    EXPECT_EQ(imported.error().file, "bad.dxf");
    EXPECT_EQ(imported.error().where, where) << imported.error().toString();
    EXPECT_NE(imported.error().message.find(part), std::string::npos)
        << imported.error().toString();
}

TEST(DxfAama, BrokenFilesAreRefusedNamingTheLine) {
    const std::string good = twoPieces("METRIC", 1.0);
    // A group code that is not a number, on line 3.
    expectError("0\nSECTION\nx1\nBLOCKS\n", "line 3", "group code \"x1\" is not a DXF group code");
    // A coordinate that is not a number: the value's line.
    std::string bad = good;
    const std::size_t at = bad.find("\n10\n400\n");
    ASSERT_NE(at, std::string::npos);
    bad.replace(at, 8, "\n10\n4o0\n");
    const int valueLine = static_cast<int>(std::count(bad.begin(), bad.begin() + at + 5, '\n')) + 1;
    expectError(bad, "line " + std::to_string(valueLine), "\"4o0\" is not a finite number");
    // Cut short inside a block.
    expectError(good.substr(0, good.find("\n0\nENDBLK") + 1), "", "the file ends before ENDBLK");
    // A code without its value.
    expectError("0\nSECTION\n2", "line 3", "has no value");
    // Not a pattern: no block with a closed cut line.
    DxfWriter w;
    w.group(0, "SECTION").group(2, "ENTITIES").line(1, Vec2(0, 0), Vec2(1, 1));
    w.group(0, "ENDSEC").group(0, "EOF");
    expectError(w.str(), "", "no pattern piece");
    // Coordinates far beyond any pattern.
    std::string far = good;
    far.replace(far.find("\n10\n400\n"), 8, "\n10\n4e12\n");
    auto refused = parseDxfAama(far, "bad.dxf");
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("scene-coordinate-m"), std::string::npos)
        << refused.error().toString();
    // A VERTEX with no POLYLINE.
    expectError("0\nSECTION\n2\nBLOCKS\n0\nBLOCK\n2\nA\n0\nVERTEX\n", "line 9",
                "VERTEX outside a POLYLINE");
}

TEST(DxfAamaCli, ImportWritesAProjectThatLoadsAndReportsThePieces) {
    const std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("atelier-dxf-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    const std::filesystem::path dxf = dir / "tee.dxf";
    std::ofstream(dxf) << twoPieces("METRIC", 1.0);
    const std::filesystem::path project = dir / "tee.atelier";
    const std::filesystem::path log = dir / "log.txt";
    const std::string command = std::string(ATELIER_CLI) + " import dxf " + dxf.string() +
                                " --out " + project.string() + " --particle-distance 20 2> " +
                                log.string();
    ASSERT_EQ(std::system(command.c_str()), 0);
    std::ifstream in(log);
    const std::string text((std::istreambuf_iterator<char>(in)), {});
    EXPECT_NE(text.find("import: 2 pieces, units mm (Units: METRIC)"), std::string::npos) << text;
    EXPECT_NE(text.find("FRONT"), std::string::npos) << text;
    EXPECT_NE(text.find("warning: " + dxf.string() + ": piece \"BACK\": Quantity 2"),
              std::string::npos)
        << text;
    auto loaded = loadProject(project);
    ASSERT_TRUE(loaded.ok()) << loaded.error().toString();
    ASSERT_EQ(loaded.value().garment.panels.size(), 2u);
    EXPECT_EQ(loaded.value().garment.panels[0].notches.size(), 2u);
    EXPECT_EQ(loaded.value().garment.panels[0].holes.size(), 1u);
    EXPECT_NEAR(loaded.value().drape.particleDistance, 0.02, 1e-12);
    // A file that is not DXF: exit 2, the file and line named, nothing written.
    const std::filesystem::path junk = dir / "junk.dxf";
    std::ofstream(junk) << "{\"not\": \"dxf\"}\n";
    const std::string bad = std::string(ATELIER_CLI) + " import dxf " + junk.string() + " --out " +
                            (dir / "junk.atelier").string() + " 2> " + log.string();
    EXPECT_EQ(WEXITSTATUS(std::system(bad.c_str())), 2);
    std::ifstream in2(log);
    const std::string text2((std::istreambuf_iterator<char>(in2)), {});
    EXPECT_NE(text2.find(junk.string() + ": line 1: group code"), std::string::npos) << text2;
    EXPECT_FALSE(std::filesystem::exists(dir / "junk.atelier"));
    std::filesystem::remove_all(dir);
}

} // namespace
} // namespace atelier::io
