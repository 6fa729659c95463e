// Edits of the garment document: they keep references valid (split edge keeps seam coverage,
// rename keeps seams), refused edits leave the document untouched, and undoing random edit
// sequences over the samples gives back the document byte for byte.

#include "io/project_file.h"

#include "patterns/curve.h"
#include "patterns/document.h"
#include "patterns/document_edit.h"
#include "patterns/mesh.h"
#include "patterns/sample_garments.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <tuple>

namespace atelier::patterns {
namespace {

GarmentDocument tshirt() {
    return fromGarment(test::sampleGarments().at("tshirt"));
}

double sideLength(const GarmentDocument& d, const std::vector<doc::SeamRange>& side) {
    double total = 0;
    for (const doc::SeamRange& r : side) {
        const doc::Panel& p = *d.panel(r.panel);
        total += arcLength(
            contourSegment(p.outline, static_cast<std::size_t>(outlineEdgeIndex(p, r.edge))), r.t0,
            r.t1);
    }
    return total;
}

Vec2 rangePoint(const GarmentDocument& d, const doc::SeamRange& r, double t) {
    const doc::Panel& p = *d.panel(r.panel);
    return pointAt(contourSegment(p.outline, static_cast<std::size_t>(outlineEdgeIndex(p, r.edge))),
                   t);
}

TEST(DocumentEdits, SplitEdgeKeepsSeamCoverage) {
    GarmentDocument d = tshirt();
    const doc::Seam before = d.seams.front();
    const doc::SeamRange r = before.a.front();
    const double t = r.t0 + 0.37 * (r.t1 - r.t0);
    const std::string dump = dumpDocument(d);
    const auto edit = splitEdge(d, r.panel, r.edge, t);
    ASSERT_TRUE(edit.ok()) << edit.error().toString();
    const doc::Seam& after = *d.seam(before.id);
    ASSERT_EQ(after.a.size(), before.a.size() + 1);
    EXPECT_NEAR(sideLength(d, after.a),
                sideLength(fromGarment(test::sampleGarments().at("tshirt")), before.a), 1e-9);
    const GarmentDocument original = tshirt();
    EXPECT_LT((rangePoint(d, after.a[0], after.a[0].t0) - rangePoint(original, r, r.t0)).norm(),
              1e-12);
    EXPECT_LT((rangePoint(d, after.a[1], after.a[1].t1) - rangePoint(original, r, r.t1)).norm(),
              1e-12);
    EXPECT_LT((rangePoint(d, after.a[0], after.a[0].t1) - rangePoint(d, after.a[1], after.a[1].t0))
                  .norm(),
              1e-12);
    EXPECT_LT((rangePoint(d, after.a[0], after.a[0].t1) - rangePoint(original, r, t)).norm(), 1e-9);
    EXPECT_TRUE(checkDocument(d).ok());
    // The garment still meshes, its seams matched.
    EXPECT_FALSE(test::meshAt20mm(toGarment(d)).seamPairs.empty());
    undo(d, edit.value());
    EXPECT_EQ(dumpDocument(d), dump);
}

TEST(DocumentEdits, SplitCurvedEdgesKeepsTheCurve) {
    GarmentDocument d = tshirt();
    for (const doc::Panel& panel : std::vector<doc::Panel>(d.panels)) {
        for (const doc::Edge& e : panel.outline.edges) {
            const doc::Panel& p = *d.panel(panel.id);
            const Segment s =
                contourSegment(p.outline, static_cast<std::size_t>(outlineEdgeIndex(p, e.id)));
            const auto edit = splitEdge(d, panel.id, e.id, 0.3);
            ASSERT_TRUE(edit.ok()) << edit.error().toString();
            const doc::Panel& q = *d.panel(panel.id);
            const auto i = static_cast<std::size_t>(outlineEdgeIndex(q, e.id));
            const Segment first = contourSegment(q.outline, i),
                          second = contourSegment(q.outline, i + 1);
            EXPECT_LT((pointAt(first, 0.5) - pointAt(s, 0.15)).norm(), 1e-12);
            EXPECT_LT((pointAt(second, 0.5) - pointAt(s, 0.65)).norm(), 1e-12);
        }
    }
}

/// A w × h rectangle [m] with its lower-left corner at (x, 0), counter-clockwise.
Panel box(const std::string& name, double x, double w, double h) {
    Panel p;
    p.name = name;
    const std::vector<Vec2> c{{x, 0}, {x + w, 0}, {x + w, h}, {x, h}};
    for (std::size_t i = 0; i < c.size(); ++i) {
        Segment s;
        s.start = c[i];
        s.end = c[(i + 1) % c.size()];
        p.outline.push_back(s);
    }
    return p;
}

TEST(DocumentEdits, SideBySidePlacesSeveralPanelsInOneEdit) {
    // Three rectangles 0.2, 0.3 (turned a quarter turn: 0.1 wide around) and 0.4 m wide.
    GarmentDocument d;
    std::vector<PanelId> ids;
    for (const auto& [name, w, h] : std::vector<std::tuple<std::string, double, double>>{
             {"a", 0.2, 0.5}, {"b", 0.3, 0.1}, {"c", 0.4, 0.5}}) {
        ASSERT_TRUE(addPanel(d, box(name, 1.0, w, h)).ok());
        ids.push_back(d.panels.back().id);
    }
    d.panels[1].placement.rotation = std::numbers::pi / 2;
    d.panels[2].side = PanelSide::Back;
    d.panels[2].placement.offset = Vec2(0.3, -0.15);
    d.panels[2].placement.clearance = 0.07;
    const std::string before = dumpDocument(d);
    const auto placements = sideBySide(d, {ids[2], PanelId{999}, ids[0], ids[1]}, "waist_front");
    ASSERT_EQ(placements.size(), 3U) << "the unknown panel is left out";
    // In the order given, 2 cm apart, the row (0.4 + 0.2 + 0.1 + 2 gaps = 0.74 m) centred.
    EXPECT_EQ(placements[0].first, ids[2]);
    EXPECT_NEAR(placements[0].second.offset.x(), -0.37 + 0.2, 1e-12);
    EXPECT_NEAR(placements[1].second.offset.x(), -0.37 + 0.42 + 0.1, 1e-12);
    EXPECT_NEAR(placements[2].second.offset.x(), -0.37 + 0.64 + 0.05, 1e-12);
    for (const auto& [id, placement] : placements) {
        EXPECT_EQ(placement.slot, "waist_front");
        EXPECT_EQ(placement.rotation, d.panel(id)->placement.rotation);
        EXPECT_EQ(placement.clearance, d.panel(id)->placement.clearance);
        EXPECT_EQ(placement.offset.y(), d.panel(id)->placement.offset.y());
    }
    auto edit = placePanels(d, placements);
    ASSERT_TRUE(edit.ok()) << edit.error().toString();
    EXPECT_EQ(edit.value().panels.size(), 3U);
    for (const auto& [id, placement] : placements) {
        EXPECT_EQ(d.panel(id)->placement.slot, "waist_front");
        EXPECT_EQ(d.panel(id)->placement.offset, placement.offset);
    }
    undo(d, edit.value());
    EXPECT_EQ(dumpDocument(d), before);
    // One refused placement refuses them all.
    auto bad = placements;
    bad[1].second.clearance = -1;
    EXPECT_FALSE(placePanels(d, bad).ok());
    EXPECT_FALSE(placePanels(d, {}).ok());
    EXPECT_EQ(dumpDocument(d), before);
}

TEST(DocumentEdits, RenameKeepsSeams) {
    GarmentDocument d = tshirt();
    const PanelId id = d.panels.front().id;
    const std::string oldName = d.panels.front().name;
    const auto edit = renamePanel(d, id, "renamed");
    ASSERT_TRUE(edit.ok());
    const Garment g = toGarment(d);
    const Garment original = test::sampleGarments().at("tshirt");
    ASSERT_EQ(g.seams.size(), original.seams.size());
    for (std::size_t s = 0; s < g.seams.size(); ++s) {
        for (std::size_t k = 0; k < g.seams[s].a.size(); ++k) {
            const SeamEdge& e = g.seams[s].a[k];
            EXPECT_EQ(e.panel, original.seams[s].a[k].panel == oldName
                                   ? "renamed"
                                   : original.seams[s].a[k].panel);
            EXPECT_EQ(e.segment, original.seams[s].a[k].segment);
        }
    }
    EXPECT_FALSE(renamePanel(d, id, d.panels.back().name).ok()); // taken
    EXPECT_FALSE(renamePanel(d, id, "").ok());
}

TEST(DocumentEdits, RemovePanelAndUndoRestoresSeamsWithTheirIds) {
    GarmentDocument d = tshirt();
    const std::string dump = dumpDocument(d);
    const PanelId id = d.panels.front().id;
    const std::size_t seamCount = d.seams.size();
    const auto edit = removePanel(d, id);
    ASSERT_TRUE(edit.ok());
    EXPECT_EQ(d.panel(id), nullptr);
    EXPECT_LT(d.seams.size(), seamCount);
    EXPECT_TRUE(checkDocument(d).ok());
    undo(d, edit.value());
    EXPECT_EQ(dumpDocument(d), dump);
    redo(d, edit.value());
    EXPECT_EQ(d.panel(id), nullptr);
}

TEST(DocumentEdits, RefusedEditsLeaveTheDocumentUntouched) {
    GarmentDocument d = tshirt();
    const std::string dump = dumpDocument(d);
    const doc::Panel& p = d.panels.front();
    const doc::SeamRange sewn = d.seams.front().a.front();
    const doc::Panel& sewnPanel = *d.panel(sewn.panel);
    const auto k = static_cast<std::size_t>(outlineEdgeIndex(sewnPanel, sewn.edge));
    EXPECT_FALSE(deletePoint(d, sewn.panel, sewnPanel.outline.points[k].id).ok()); // sewn edge
    EXPECT_FALSE(splitEdge(d, p.id, p.outline.edges[0].id, 1.0).ok());
    EXPECT_FALSE(splitEdge(d, PanelId{999999}, p.outline.edges[0].id, 0.5).ok());
    EXPECT_FALSE(
        addSeam(d, "x", {{p.id, EdgeId{999999}, 0, 1}}, {{p.id, p.outline.edges[0].id, 0, 1}})
            .ok());
    EXPECT_FALSE(duplicatePanel(d, p.id, p.name).ok());
    EXPECT_EQ(dumpDocument(d), dump);
}

TEST(DocumentEdits, FabricsAndTheirPanels) {
    GarmentDocument d = tshirt();
    const std::string start = dumpDocument(d);
    ASSERT_FALSE(d.materials.empty());
    const PanelId id = d.panels.front().id;

    GarmentMaterial denim;
    denim.name = "denim";
    denim.material.density = 0.4;
    denim.material.bending = 3e-5;
    const auto added = setMaterial(d, denim);
    ASSERT_TRUE(added.ok()) << added.error().toString();
    ASSERT_EQ(d.materials.back().name, "denim");
    EXPECT_EQ(d.materials.back().material.density, 0.4);
    const auto given = setPanelMaterial(d, id, "denim");
    ASSERT_TRUE(given.ok()) << given.error().toString();
    EXPECT_EQ(d.panel(id)->material, "denim");
    EXPECT_TRUE(checkDocument(d).ok());

    denim.material.density = 0.3; // the same fabric's new values: no second "denim"
    const auto changed = setMaterial(d, denim);
    ASSERT_TRUE(changed.ok());
    EXPECT_EQ(std::count_if(d.materials.begin(), d.materials.end(),
                            [](const GarmentMaterial& m) { return m.name == "denim"; }),
              1);
    EXPECT_EQ(d.materials.back().material.density, 0.3);

    const std::string edited = dumpDocument(d);
    for (const auto* e : {&changed, &given, &added}) {
        undo(d, e->value());
    }
    EXPECT_EQ(dumpDocument(d), start);
    for (const auto* e : {&added, &given, &changed}) {
        redo(d, e->value());
    }
    EXPECT_EQ(dumpDocument(d), edited);

    // Refused: unknown fabric, an empty name, a non-positive density, Poisson's ratio ≥ 1.
    EXPECT_FALSE(setPanelMaterial(d, id, "silk").ok());
    GarmentMaterial bad = denim;
    bad.name = "";
    EXPECT_FALSE(setMaterial(d, bad).ok());
    bad = denim;
    bad.material.density = 0;
    EXPECT_FALSE(setMaterial(d, bad).ok());
    bad = denim;
    bad.material.poisson = 1;
    EXPECT_FALSE(setMaterial(d, bad).ok());
    bad = denim;
    bad.material.bending = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(setMaterial(d, bad).ok());
    EXPECT_EQ(dumpDocument(d), edited);
}

// --- Marks: notches, internal lines, darts, grain -----------------------------------------

/// A document with one 0.3 × 0.4 m rectangle "r" (edges: bottom, right, top, left).
GarmentDocument rectangleDocument() {
    GarmentDocument d;
    d.materials.push_back({"cotton", {}});
    Panel drawn;
    drawn.name = "r";
    drawn.material = "cotton";
    const std::vector<Vec2> c{{0, 0}, {0.3, 0}, {0.3, 0.4}, {0, 0.4}};
    for (std::size_t i = 0; i < c.size(); ++i) {
        Segment s;
        s.start = c[i];
        s.end = c[(i + 1) % c.size()];
        drawn.outline.push_back(s);
    }
    EXPECT_TRUE(addPanel(d, drawn).ok());
    return d;
}

TEST(DocumentMarks, NotchesLinesAndGrainUndoExactly) {
    GarmentDocument d = rectangleDocument();
    const PanelId id = d.panels.front().id;
    const EdgeId bottom = d.panels.front().outline.edges[0].id;
    const std::string start = dumpDocument(d);
    std::vector<Edit> edits;

    auto notch = addNotch(d, id, bottom, 0.25);
    ASSERT_TRUE(notch.ok()) << notch.error().toString();
    edits.push_back(notch.value());
    auto line = addInternalLine(d, id, {{0.05, 0.2}, {0.15, 0.25}, {0.25, 0.2}}, 0.5);
    ASSERT_TRUE(line.ok()) << line.error().toString();
    edits.push_back(line.value());
    auto fold = setFoldAngle(d, id, LineId{line.value().created}, -1.0);
    ASSERT_TRUE(fold.ok());
    edits.push_back(fold.value());

    const doc::Panel& p = d.panels.front();
    ASSERT_EQ(p.notches.size(), 1U);
    EXPECT_EQ(p.notches[0].edge, bottom);
    EXPECT_DOUBLE_EQ(p.notches[0].t, 0.25);
    ASSERT_EQ(p.internalLines.size(), 1U);
    EXPECT_EQ(p.internalLines[0].points.size(), 3U);
    EXPECT_EQ(p.internalLines[0].edges.size(), 2U);
    EXPECT_DOUBLE_EQ(p.internalLines[0].foldAngle, -1.0);
    EXPECT_TRUE(checkDocument(d).ok());

    // The mesher puts a vertex on the notch and mesh edges along the line, folded as set.
    GarmentMesh mesh;
    MeshOptions options;
    options.particleDistance = 0.02;
    ASSERT_FALSE(meshGarment(toGarment(d), options, mesh).has_value());
    const PanelMesh& m = mesh.panels.front();
    ASSERT_EQ(m.notchVertices.size(), 1U);
    EXPECT_NEAR((m.rest.row(m.notchVertices[0]).transpose() - Vec2(0.075, 0)).norm(), 0, 1e-9);
    EXPECT_GE(m.lineEdges.size(), 8U); // ≈ 0.22 m of line at 20 mm
    for (const double a : m.lineFoldAngles) {
        EXPECT_DOUBLE_EQ(a, -1.0);
    }

    // The grain turns the mesh's rest frame (warp along y): set after the check above.
    auto grain = setGrainAngle(d, id, 3 * M_PI); // stored as π
    ASSERT_TRUE(grain.ok());
    edits.push_back(grain.value());
    EXPECT_NEAR(d.panels.front().grainAngle, M_PI, 1e-12);
    // Its place on the pattern sheet, the turn stored in (−π, π].
    auto sheet = setSheetPlace(d, id, doc::SheetPlace{Vec2(0.5, -0.25), -3 * M_PI});
    ASSERT_TRUE(sheet.ok());
    edits.push_back(sheet.value());
    ASSERT_TRUE(d.panels.front().sheet);
    EXPECT_EQ(d.panels.front().sheet->at, Vec2(0.5, -0.25));
    EXPECT_NEAR(d.panels.front().sheet->angle, M_PI, 1e-12);

    const auto removed = removeInternalLine(d, id, LineId{line.value().created});
    ASSERT_TRUE(removed.ok());
    edits.push_back(removed.value());
    const auto unnotched = removeNotch(d, id, NotchId{notch.value().created});
    ASSERT_TRUE(unnotched.ok());
    edits.push_back(unnotched.value());
    EXPECT_TRUE(d.panels.front().notches.empty());
    EXPECT_TRUE(d.panels.front().internalLines.empty());
    for (std::size_t k = edits.size(); k-- > 0;) {
        undo(d, edits[k]);
    }
    EXPECT_EQ(dumpDocument(d), start);
}

TEST(DocumentMarks, ADartCutsTheEdgeAndIsSewnWhenMeshed) {
    GarmentDocument d = rectangleDocument();
    const PanelId id = d.panels.front().id;
    const EdgeId bottom = d.panels.front().outline.edges[0].id;
    const std::string start = dumpDocument(d);

    auto dart = addDart(d, id, bottom, 0.5, 0.04, 0.12);
    ASSERT_TRUE(dart.ok()) << dart.error().toString();
    const doc::Panel& p = d.panels.front();
    ASSERT_EQ(p.outline.points.size(), 7U);
    ASSERT_EQ(p.darts.size(), 1U);
    EXPECT_TRUE(checkDocument(d).ok());
    // Base points 20 mm either side of the centre, the tip 120 mm above it.
    EXPECT_NEAR((p.outline.points[1].position - Vec2(0.13, 0)).norm(), 0, 1e-12);
    EXPECT_NEAR((p.outline.points[2].position - Vec2(0.15, 0.12)).norm(), 0, 1e-12);
    EXPECT_NEAR((p.outline.points[3].position - Vec2(0.17, 0)).norm(), 0, 1e-12);
    EXPECT_EQ(p.darts[0].leg1, p.outline.edges[1].id);
    EXPECT_EQ(p.darts[0].leg2, p.outline.edges[2].id);
    EXPECT_EQ(p.outline.edges[0].id, bottom);

    // Meshed, the legs are sewn pair by pair (darts' pairs carry −1 − panel index).
    GarmentMesh mesh;
    MeshOptions options;
    options.particleDistance = 0.02;
    ASSERT_FALSE(meshGarment(toGarment(d), options, mesh).has_value());
    const long dartPairs = std::count(mesh.seamOfPair.begin(), mesh.seamOfPair.end(), -1);
    EXPECT_GE(dartPairs, 5);

    // Refused: a cut part that is sewn or notched, a tip outside, too wide; nothing changes.
    const std::string cut = dumpDocument(d);
    EXPECT_FALSE(addDart(d, id, bottom, 0.5, 0.3, 0.05).ok());                // wider than the edge
    EXPECT_FALSE(addDart(d, id, p.outline.edges[4].id, 0.5, 0.04, 0.5).ok()); // tip outside
    EXPECT_FALSE(addDart(d, id, p.darts[0].leg1, 0.5, 0.01, 0.01).ok());      // on a leg
    EXPECT_FALSE(addDart(d, id, bottom, 0.5, 0.04, -0.1).ok());
    EXPECT_EQ(dumpDocument(d), cut);

    auto removed = removeDart(d, id, DartId{dart.value().created});
    ASSERT_TRUE(removed.ok()) << removed.error().toString();
    EXPECT_TRUE(d.panels.front().darts.empty());
    EXPECT_EQ(d.panels.front().outline.points.size(), 6U);
    EXPECT_TRUE(checkDocument(d).ok());
    undo(d, removed.value());
    EXPECT_EQ(dumpDocument(d), cut);
    undo(d, dart.value());
    EXPECT_EQ(dumpDocument(d), start);
}

TEST(DocumentMarks, ADartsWidthAndDepthAreSetUndoably) {
    GarmentDocument d = rectangleDocument();
    const PanelId id = d.panels.front().id;
    auto dart = addDart(d, id, d.panels.front().outline.edges[0].id, 0.5, 0.04, 0.12);
    ASSERT_TRUE(dart.ok()) << dart.error().toString();
    const DartId dartId{dart.value().created};
    const auto size = dartSize(d.panels.front(), dartId);
    ASSERT_TRUE(size);
    EXPECT_NEAR(size->width, 0.04, 1e-12);
    EXPECT_NEAR(size->depth, 0.12, 1e-12);
    EXPECT_FALSE(dartSize(d.panels.front(), DartId{999}));
    const std::string cut = dumpDocument(d);

    // 60 mm wide, 100 mm deep: the bases slide along the bottom edge about the same middle.
    auto resized = setDartSize(d, id, dartId, 0.06, 0.10);
    ASSERT_TRUE(resized.ok()) << resized.error().toString();
    const doc::Panel& p = d.panels.front();
    EXPECT_NEAR((p.outline.points[1].position - Vec2(0.12, 0)).norm(), 0, 1e-12);
    EXPECT_NEAR((p.outline.points[2].position - Vec2(0.15, 0.10)).norm(), 0, 1e-12);
    EXPECT_NEAR((p.outline.points[3].position - Vec2(0.18, 0)).norm(), 0, 1e-12);
    EXPECT_NEAR(dartSize(p, dartId)->width, 0.06, 1e-12);
    EXPECT_NEAR(dartSize(p, dartId)->depth, 0.10, 1e-12);
    EXPECT_TRUE(checkDocument(d).ok());
    const std::string wide = dumpDocument(d);
    undo(d, resized.value());
    EXPECT_EQ(dumpDocument(d), cut);
    redo(d, resized.value());
    EXPECT_EQ(dumpDocument(d), wide);

    // Refused, nothing changed: not positive, past the bottom edge's ends (0.3 m wide), the
    // tip out of the panel (0.4 m high), no such dart.
    EXPECT_FALSE(setDartSize(d, id, dartId, 0, 0.1).ok());
    EXPECT_FALSE(setDartSize(d, id, dartId, 0.05, -0.1).ok());
    EXPECT_FALSE(setDartSize(d, id, dartId, std::nan(""), 0.1).ok());
    const auto tooWide = setDartSize(d, id, dartId, 0.3, 0.1);
    ASSERT_FALSE(tooWide.ok());
    EXPECT_NE(tooWide.error().toString().find("wider than its edge"), std::string::npos);
    EXPECT_FALSE(setDartSize(d, id, dartId, 0.05, 0.45).ok());
    EXPECT_FALSE(setDartSize(d, id, DartId{999}, 0.05, 0.1).ok());
    EXPECT_EQ(dumpDocument(d), wide);
}

TEST(DocumentMarks, RefusedMarksLeaveTheDocumentUntouched) {
    GarmentDocument d = rectangleDocument();
    const PanelId id = d.panels.front().id;
    const EdgeId bottom = d.panels.front().outline.edges[0].id;
    const EdgeId right = d.panels.front().outline.edges[1].id;
    const auto notch = addNotch(d, id, bottom, 0.5);
    ASSERT_TRUE(notch.ok());
    doc::Pin pin;
    pin.notch = NotchId{notch.value().created};
    ASSERT_TRUE(addPin(d, id, pin).ok());
    const auto seam =
        addSeam(d, "s", {{id, right, 0, 1}}, {{id, d.panels.front().outline.edges[3].id, 1, 0}});
    ASSERT_TRUE(seam.ok());
    const std::string before = dumpDocument(d);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(addNotch(d, id, bottom, 1.5).ok());
    EXPECT_FALSE(addNotch(d, id, EdgeId{999}, 0.5).ok());
    EXPECT_FALSE(removeNotch(d, id, NotchId{notch.value().created}).ok()); // held by the pin
    EXPECT_FALSE(addInternalLine(d, id, {{0.1, 0.1}}).ok());               // one point
    EXPECT_FALSE(addInternalLine(d, id, {{0.1, 0.1}, {0.5, 0.1}}).ok());   // leaves the panel
    EXPECT_FALSE(addInternalLine(d, id, {{0.1, 0.1}, {0.2, nan}}).ok());
    EXPECT_FALSE(addInternalLine(d, id, {{0.1, 0.1}, {0.2, 0.1}}, 4.0).ok()); // fold ≥ π
    EXPECT_FALSE(setFoldAngle(d, id, LineId{999}, 0.1).ok());
    EXPECT_FALSE(addDart(d, id, right, 0.5, 0.04, 0.05).ok());  // the right edge is sewn
    EXPECT_FALSE(addDart(d, id, bottom, 0.5, 0.04, 0.05).ok()); // would cut the notch
    EXPECT_FALSE(removeDart(d, id, DartId{999}).ok());
    EXPECT_FALSE(setGrainAngle(d, id, nan).ok());
    EXPECT_FALSE(setGrainAngle(d, PanelId{999}, 0).ok());
    EXPECT_FALSE(setSheetPlace(d, id, doc::SheetPlace{Vec2(nan, 0), 0}).ok());
    EXPECT_FALSE(setSheetPlace(d, id, doc::SheetPlace{Vec2(2000, 0), 0}).ok());
    EXPECT_FALSE(setSheetPlace(d, id, doc::SheetPlace{Vec2(0, 0), nan}).ok());
    EXPECT_FALSE(setSheetPlace(d, PanelId{999}, std::nullopt).ok());
    EXPECT_EQ(dumpDocument(d), before);
}

// --- Random edit sequences --------------------------------------------------------------

struct RandomEditor {
    std::mt19937 rng;
    int names = 0;

    double uniform(double lo, double hi) {
        return std::uniform_real_distribution<double>(lo, hi)(rng);
    }
    std::size_t pick(std::size_t n) {
        return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng);
    }
    bool chance(double p) { return uniform(0, 1) < p; }

    PanelId panel(const GarmentDocument& d) {
        return d.panels.empty() || chance(0.05) ? PanelId{999999}
                                                : d.panels[pick(d.panels.size())].id;
    }
    const doc::Contour* contour(const GarmentDocument& d, PanelId id) {
        const doc::Panel* p = d.panel(id);
        if (p == nullptr) {
            return nullptr;
        }
        return p->holes.empty() || chance(0.7) ? &p->outline
                                               : &p->holes[pick(p->holes.size())].contour;
    }
    EdgeId edge(const GarmentDocument& d, PanelId id) {
        const doc::Contour* c = contour(d, id);
        return c == nullptr || chance(0.05) ? EdgeId{999999} : c->edges[pick(c->edges.size())].id;
    }
    PointId point(const GarmentDocument& d, PanelId id) {
        const doc::Contour* c = contour(d, id);
        return c == nullptr || chance(0.05) ? PointId{999999}
                                            : c->points[pick(c->points.size())].id;
    }
    std::string name(const GarmentDocument& d) {
        if (!d.panels.empty() && chance(0.3)) {
            return d.panels[pick(d.panels.size())].name; // taken: refused
        }
        return "piece " + std::to_string(names++);
    }
    double parameter() { return chance(0.1) ? uniform(-0.5, 1.5) : uniform(0.05, 0.95); }
    doc::SeamRange range(const GarmentDocument& d) {
        const PanelId p = panel(d);
        const doc::Panel* q = d.panel(p);
        const EdgeId e =
            q == nullptr ? EdgeId{} : q->outline.edges[pick(q->outline.edges.size())].id;
        return {p, e, parameter(), parameter()};
    }
    SeamId seam(const GarmentDocument& d) {
        return d.seams.empty() || chance(0.05) ? SeamId{999999} : d.seams[pick(d.seams.size())].id;
    }

    Result<Edit> edit(GarmentDocument& d) {
        const PanelId p = panel(d);
        switch (pick(23)) {
        case 0:
            return movePoint(d, p, point(d, p), Vec2(uniform(-0.3, 0.3), uniform(0, 0.6)));
        case 1:
        case 2:
            return splitEdge(d, p, edge(d, p), parameter());
        case 3:
            return addPoint(d, p, edge(d, p), parameter(),
                            Vec2(uniform(-0.3, 0.3), uniform(0, 0.6)));
        case 4:
            return deletePoint(d, p, point(d, p));
        case 5: {
            doc::Curve c;
            c.kind = static_cast<SegmentKind>(pick(4));
            c.control1 = Vec2(uniform(-0.3, 0.3), uniform(0, 0.6));
            c.control2 = Vec2(uniform(-0.3, 0.3), uniform(0, 0.6));
            c.bulge = uniform(-0.5, 0.5);
            return setCurve(d, p, edge(d, p), c);
        }
        case 6: {
            Panel drawn;
            drawn.name = name(d);
            drawn.material = d.materials.empty() ? "" : d.materials.front().name;
            const double s = uniform(0.1, 0.3);
            const auto segment = [](SegmentKind kind, Vec2 a, Vec2 b, double bulge) {
                Segment out; // handles zero (Eigen leaves a braced `{}` uninitialised)
                out.kind = kind;
                out.start = a;
                out.end = b;
                out.bulge = bulge;
                return out;
            };
            drawn.outline = {segment(SegmentKind::Line, {0, 0}, {s, 0}, 0),
                             segment(SegmentKind::Line, {s, 0}, {s, s}, 0),
                             segment(SegmentKind::Arc, {s, s}, {0, s}, 0.2),
                             segment(SegmentKind::Line, {0, s}, {0, 0}, 0)};
            drawn.notches = {{1, 0.5}};
            drawn.darts = {{1}};
            return addPanel(d, drawn);
        }
        case 7:
            return chance(0.3) ? removePanel(d, p) : reverseSeam(d, seam(d));
        case 8:
            return addSeam(d, "seam " + std::to_string(names++), {range(d)}, {range(d), range(d)});
        case 9:
            return removeSeam(d, seam(d));
        case 10:
            return mirrorPanel(d, p);
        case 11:
            return duplicatePanel(d, p, name(d));
        case 12:
            return renamePanel(d, p, name(d));
        case 13:
            return setPanelMaterial(d, p,
                                    d.materials.empty() || chance(0.2)
                                        ? "no such fabric"
                                        : d.materials[pick(d.materials.size())].name);
        case 14: {
            GarmentMaterial m;
            m.name = d.materials.empty() || chance(0.3)
                         ? "fabric " + std::to_string(names++)
                         : d.materials[pick(d.materials.size())].name;
            m.material.density = chance(0.1) ? -0.1 : uniform(0.05, 0.4);
            m.material.bending = uniform(1e-7, 1e-4);
            m.material.poisson = chance(0.05) ? 1.5 : uniform(0, 0.45);
            return setMaterial(d, m);
        }
        case 15:
            if (chance(0.3)) {
                return setPanelParticleDistance(d, p, chance(0.2) ? -0.01 : uniform(0, 0.03));
            }
            return addNotch(d, p, edge(d, p), parameter());
        case 16: {
            const doc::Panel* q = d.panel(p);
            if (q != nullptr && !q->notches.empty() && chance(0.8)) {
                return removeNotch(d, p, q->notches[pick(q->notches.size())].id);
            }
            if (q != nullptr && !q->internalLines.empty() && chance(0.8)) {
                return removeInternalLine(d, p, q->internalLines[pick(q->internalLines.size())].id);
            }
            if (chance(0.5)) {
                return setGrainAngle(d, p, uniform(-7, 7));
            }
            if (chance(0.2)) {
                return setSheetPlace(d, p, std::nullopt);
            }
            return setSheetPlace(
                d, p,
                doc::SheetPlace{Vec2(uniform(-2, 2),
                                     chance(0.05) ? std::numeric_limits<double>::quiet_NaN() : 0.3),
                                uniform(-7, 7)});
        }
        case 17: {
            // A line across the middle of the panel's outline points (often inside it).
            const doc::Panel* q = d.panel(p);
            Vec2 mid = Vec2::Zero();
            if (q != nullptr) {
                for (const doc::Point& pt : q->outline.points) {
                    mid += pt.position / static_cast<double>(q->outline.points.size());
                }
            }
            const Vec2 step(uniform(-0.03, 0.03), uniform(-0.03, 0.03));
            return addInternalLine(d, p, {mid - step, mid, mid + 2 * step}, uniform(-1, 1));
        }
        case 18: {
            const doc::Panel* q = d.panel(p);
            const LineId line = q != nullptr && !q->internalLines.empty()
                                    ? q->internalLines[pick(q->internalLines.size())].id
                                    : LineId{999999};
            return setFoldAngle(d, p, line, uniform(-4, 4));
        }
        case 19:
            return addDart(d, p, edge(d, p), uniform(0.2, 0.8), uniform(0.005, 0.05),
                           uniform(0.01, 0.1));
        case 20: {
            const doc::Panel* q = d.panel(p);
            const DartId dart = q != nullptr && !q->darts.empty()
                                    ? q->darts[pick(q->darts.size())].id
                                    : DartId{999999};
            return removeDart(d, p, dart);
        }
        case 21: // out of range a third of the time
            return setSeamBending(d, seam(d), uniform(-4, 4), uniform(-1, 5));
        default: {
            Placement placement;
            placement.slot = chance(0.5) ? "torso_front" : "torso_back";
            placement.offset = Vec2(uniform(-0.1, 0.1), uniform(-0.1, 0.1));
            placement.rotation = uniform(-1, 1);
            placement.clearance = chance(0.1) ? -1.0 : 0.02;
            return placePanel(d, p, placement);
        }
        }
    }
};

TEST(DocumentUndo, RandomEditSequencesUndoToTheSameBytes) {
    int applied = 0, refused = 0;
    unsigned seed = 1;
    for (const auto& [name, garment] : test::sampleGarments()) {
        SCOPED_TRACE(name);
        GarmentDocument d = fromGarment(garment);
        RandomEditor editor{std::mt19937(seed++)};
        const std::string start = dumpDocument(d);
        std::vector<Edit> edits;
        std::vector<std::string> befores, afters;
        for (int step = 0; step < 150; ++step) {
            const std::string before = dumpDocument(d);
            const auto edit = editor.edit(d);
            if (!edit.ok()) {
                ++refused;
                ASSERT_EQ(dumpDocument(d), before)
                    << "refused edit changed the document: " << edit.error().toString();
                continue;
            }
            ++applied;
            const auto check = checkDocument(d);
            ASSERT_TRUE(check.ok()) << edit.value().description << ": " << check.error().toString();
            edits.push_back(edit.value());
            befores.push_back(before);
            afters.push_back(dumpDocument(d));
        }
        for (std::size_t k = edits.size(); k-- > 0;) {
            undo(d, edits[k]);
            ASSERT_EQ(dumpDocument(d), befores[k]) << "undo of " << edits[k].description;
        }
        EXPECT_EQ(dumpDocument(d), start);
        for (std::size_t k = 0; k < edits.size(); ++k) {
            redo(d, edits[k]);
            ASSERT_EQ(dumpDocument(d), afters[k]) << "redo of " << edits[k].description;
        }
    }
    EXPECT_GT(applied, 300);
    EXPECT_GT(refused, 30);
}

} // namespace
} // namespace atelier::patterns
