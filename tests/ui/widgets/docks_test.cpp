// The window's docks, arrangement and file additions without a display
// (QT_QPA_PLATFORM=offscreen): each dock's change is one undoable document edit that reaches
// the drape, slots are placed on from the dock and from the 3D view, the live plot follows a
// drape, the pattern exports as the CLI's SVG, and the very first start opens the tshirt.
#include "ui/render/headless_context.h"
#include "ui/widgets/body_dock.h"
#include "ui/widgets/body_preview.h"
#include "ui/widgets/drape_plot.h"
#include "ui/widgets/fabric_dock.h"
#include "ui/widgets/main_window.h"
#include "ui/widgets/panel_dock.h"
#include "ui/widgets/pattern_view.h"
#include "ui/widgets/seam_dock.h"
#include "ui/widgets/simulation_dock.h"
#include "ui/widgets/viewport.h"
#include "ui/widgets/widget_test_support.h"

#include "io/pattern_svg.h"

#include "patterns/curve.h"
#include "patterns/cusick.h"
#include "patterns/document_edit.h"
#include "patterns/mannequin.h"

#include <QApplication>
#include <QComboBox>
#include <QDir>
#include <QDoubleSpinBox>
#include <QFileInfo>
#include <QImage>
#include <QLineEdit>
#include <QMouseEvent>
#include <QPushButton>
#include <QSettings>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QTest>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <sstream>

namespace atelier::ui {
namespace {

using test::openAndWait;
using test::QuietPrompts;
using test::waitFor;

using test::GARMENTS;

/// A window on the skirt, placed, its front panel selected.
struct SkirtWindow {
    QTemporaryDir dir;
    MainWindow window{GARMENTS};
    QuietPrompts prompts;
    patterns::PanelId front;

    bool open() {
        prompts.install(window);
        window.setRecoveryDirectory(dir.filePath("recovery"));
        window.resize(1200, 700);
        window.show();
        if (!openAndWait(window, GARMENTS + "/skirt.atelier")) {
            return false;
        }
        front = window.project().document.panels.front().id;
        window.patternView().selectPanel(front);
        QCoreApplication::processEvents();
        return window.panelDock().panel() == front;
    }
    const patterns::doc::Panel& frontPanel() const {
        return *window.project().document.panel(front);
    }
    /// The drape holds the window's document (every edit reached the worker).
    bool drapeFollows() {
        return waitFor(
            [&] {
                return patterns::dumpDocument(window.drape().document()) ==
                       patterns::dumpDocument(window.project().document);
            },
            120);
    }
};

TEST(PanelDock, RenamesThePanelUndoably) {
    SkirtWindow s;
    ASSERT_TRUE(s.open());
    const std::string before = patterns::dumpDocument(s.window.project().document);
    QLineEdit* name = s.window.panelDock().nameField();
    EXPECT_EQ(name->text(), "front");
    name->setText("skirt front");
    Q_EMIT name->editingFinished();
    EXPECT_EQ(s.frontPanel().name, "skirt front");
    EXPECT_EQ(s.window.undoStack().count(), 1);
    EXPECT_TRUE(s.window.undoStack().undoText().contains("rename"));
    EXPECT_TRUE(s.drapeFollows());
    ASSERT_TRUE(waitFor(
        [&] { return s.window.drape().staticScene()->panelNames[0] == "skirt front"; }, 120))
        << "the garment is placed again with the new name";

    // A name another panel has is refused, with a message, and the field shows the name again.
    name->setText("back");
    Q_EMIT name->editingFinished();
    EXPECT_EQ(s.window.undoStack().count(), 1);
    ASSERT_EQ(s.prompts.errors.size(), 1);
    EXPECT_TRUE(s.prompts.errors.front().contains("back"))
        << s.prompts.errors.front().toStdString();
    EXPECT_EQ(name->text(), "skirt front");

    s.window.undoStack().undo();
    EXPECT_EQ(patterns::dumpDocument(s.window.project().document), before);
    EXPECT_EQ(name->text(), "front") << "the dock shows the document after the undo";
    EXPECT_TRUE(s.drapeFollows());
}

TEST(PanelDock, PlacesThePanelOnAnotherSlotUndoably) {
    SkirtWindow s;
    ASSERT_TRUE(s.open());
    const patterns::Placement was = s.frontPanel().placement;
    QComboBox* slot = s.window.panelDock().slotChooser();
    ASSERT_GT(slot->count(), 2) << "the body's slots";
    EXPECT_EQ(slot->currentText().toStdString(), was.slot);
    const int other = slot->findText("torso_front");
    ASSERT_GE(other, 0);
    const auto scene = s.window.drape().staticScene();
    QSignalSpy rebuilt(&s.window.drape(), &DrapeController::rebuilt);
    slot->setCurrentIndex(other);
    Q_EMIT slot->activated(other);
    EXPECT_EQ(s.frontPanel().placement.slot, "torso_front");
    EXPECT_EQ(s.frontPanel().placement.offset, was.offset) << "offset, rotation kept";
    EXPECT_EQ(s.frontPanel().placement.rotation, was.rotation);
    ASSERT_TRUE(waitFor([&] { return rebuilt.count() >= 1; }, 120));
    EXPECT_TRUE(rebuilt.front().front().toBool()) << "the other panel stays where it was";
    EXPECT_TRUE(s.drapeFollows());
    // The front panel starts somewhere else; the back stays exactly where it was.
    const auto placed = s.window.drape().staticScene();
    ASSERT_EQ(placed->startPositions.rows(), scene->startPositions.rows());
    const auto [first, count] = placed->panelTriangles.front();
    const int frontVertices =
        placed->garmentTriangles.middleRows(first, count).maxCoeff() + 1; // panel 0's range
    const auto rest = placed->startPositions.rows() - frontVertices;
    EXPECT_GT((placed->startPositions.topRows(frontVertices) -
               scene->startPositions.topRows(frontVertices))
                  .rowwise()
                  .norm()
                  .maxCoeff(),
              0.01);
    EXPECT_EQ(placed->startPositions.bottomRows(rest), scene->startPositions.bottomRows(rest));

    // An offset field: 25 mm along the slot, one more edit.
    s.window.panelDock().alongField()->setValue(was.offset.y() * 1000 + 25);
    EXPECT_NEAR(s.frontPanel().placement.offset.y(), was.offset.y() + 0.025, 1e-9);
    EXPECT_EQ(s.window.undoStack().count(), 2);

    s.window.undoStack().undo();
    s.window.undoStack().undo();
    EXPECT_EQ(s.frontPanel().placement.slot, was.slot);
    EXPECT_EQ(s.frontPanel().placement.offset, was.offset);
    EXPECT_EQ(slot->currentText().toStdString(), was.slot);
    EXPECT_TRUE(s.drapeFollows());
    EXPECT_TRUE(s.prompts.errors.isEmpty()) << s.prompts.errors.join("; ").toStdString();
}

TEST(PanelDock, ConsecutiveChangesOfOneFieldAreOneUndoEntry) {
    SkirtWindow s;
    ASSERT_TRUE(s.open());
    const std::string before = patterns::dumpDocument(s.window.project().document);
    const patterns::Placement was = s.frontPanel().placement;
    PanelDock& dock = s.window.panelDock();
    const double turned = (dock.rotationField()->value() + 3) * std::numbers::pi / 180; // [rad]
    const double clear = (dock.clearanceField()->value() + 2) / 1000;                   // [m]
    // Three arrow clicks on the rotation: one entry, three degrees.
    for (int k = 0; k < 3; ++k) {
        dock.rotationField()->stepUp();
    }
    EXPECT_EQ(s.window.undoStack().count(), 1);
    EXPECT_NEAR(s.frontPanel().placement.rotation, turned, 1e-9);
    // Another field is another entry, and the rotation after it another again.
    dock.clearanceField()->stepUp();
    dock.clearanceField()->stepUp();
    EXPECT_EQ(s.window.undoStack().count(), 2);
    EXPECT_NEAR(s.frontPanel().placement.clearance, clear, 1e-9);
    dock.rotationField()->stepUp();
    EXPECT_EQ(s.window.undoStack().count(), 3);

    s.window.undoStack().undo();
    EXPECT_NEAR(s.frontPanel().placement.rotation, turned, 1e-9);
    EXPECT_NEAR(s.frontPanel().placement.clearance, clear, 1e-9);
    s.window.undoStack().undo();
    EXPECT_EQ(s.frontPanel().placement.clearance, was.clearance);
    s.window.undoStack().undo();
    EXPECT_EQ(patterns::dumpDocument(s.window.project().document), before)
        << "the three rotation steps undone at once";
    s.window.undoStack().redo();
    EXPECT_NEAR(s.frontPanel().placement.rotation, turned, 1e-9) << "redone at once too";
    EXPECT_TRUE(s.drapeFollows());
}

TEST(PanelDock, SetsTheSelectedDartsWidthAndDepthUndoably) {
    SkirtWindow s;
    ASSERT_TRUE(s.open());
    // A dart 30 mm wide and 90 mm deep in the middle of the front's waist (edge 3).
    const patterns::EdgeId waist = s.frontPanel().outline.edges.at(3).id;
    ASSERT_TRUE(s.window.edit([&](patterns::GarmentDocument& d) {
        return patterns::addDart(d, s.front, waist, 0.5, 0.03, 0.09);
    }));
    const patterns::doc::Dart dart = s.frontPanel().darts.at(0);
    PanelDock& dock = s.window.panelDock();
    EXPECT_FALSE(dock.dartWidthField()->isEnabled()) << "no dart selected";
    // A click on the dart's first leg in the pattern selects it, and the dock shows its size.
    const patterns::doc::Panel& p = s.frontPanel();
    const auto leg = static_cast<std::size_t>(patterns::outlineEdgeIndex(p, dart.leg1));
    const patterns::Vec2 onLeg = patterns::pointAt(patterns::contourSegment(p.outline, leg), 0.5);
    PatternView& pattern = s.window.patternView();
    QTest::mouseClick(pattern.viewport(), Qt::LeftButton, {}, pattern.viewPoint(s.front, onLeg));
    ASSERT_EQ(pattern.selectedEdge(), dart.leg1);
    ASSERT_TRUE(dock.dartWidthField()->isEnabled());
    EXPECT_NEAR(dock.dartWidthField()->value(), 30, 0.05);
    EXPECT_NEAR(dock.dartDepthField()->value(), 90, 0.05);
    const std::string cut = patterns::dumpDocument(s.window.project().document);

    // 40 then 41 mm wide (one undo entry), then 100 mm deep (another).
    dock.dartWidthField()->setValue(40);
    dock.dartWidthField()->setValue(41);
    EXPECT_EQ(s.window.undoStack().count(), 2);
    auto size = patterns::dartSize(s.frontPanel(), dart.id);
    ASSERT_TRUE(size);
    EXPECT_NEAR(size->width, 0.041, 1e-9);
    EXPECT_NEAR(size->depth, 0.09, 1e-9);
    dock.dartDepthField()->setValue(100);
    EXPECT_EQ(s.window.undoStack().count(), 3);
    EXPECT_NEAR(patterns::dartSize(s.frontPanel(), dart.id)->depth, 0.1, 1e-9);
    EXPECT_TRUE(s.drapeFollows());

    // Wider than the waist: refused with one message saying so; the field shows the dart as is.
    const std::string resized = patterns::dumpDocument(s.window.project().document);
    dock.dartWidthField()->setValue(1500);
    ASSERT_EQ(s.prompts.errors.size(), 1);
    EXPECT_TRUE(s.prompts.errors.front().contains("wider than its edge allows"))
        << s.prompts.errors.front().toStdString();
    EXPECT_NEAR(dock.dartWidthField()->value(), 41, 0.05);
    EXPECT_EQ(patterns::dumpDocument(s.window.project().document), resized);
    EXPECT_EQ(s.window.undoStack().count(), 3);
    s.window.undoStack().undo();
    s.window.undoStack().undo();
    EXPECT_EQ(patterns::dumpDocument(s.window.project().document), cut);
    EXPECT_NEAR(dock.dartWidthField()->value(), 30, 0.05);
}

TEST(BodyDock, AMeasurementIsPreviewedAndLandsAsOneUndoableBodyChange) {
    SkirtWindow s;
    ASSERT_TRUE(s.open());
    const patterns::BodySource was = s.window.project().body;
    const auto placed = s.window.drape().staticScene();
    BodyDock& dock = s.window.bodyDock();
    QDoubleSpinBox* waist = dock.field("waist");
    ASSERT_NE(waist, nullptr);
    EXPECT_DOUBLE_EQ(waist->value(), patterns::BodyMeasurements{}.waist * 100) << "[cm]";
    EXPECT_TRUE(dock.meshText().isEmpty()) << "the mannequin";
    // Each body built is drawn at once (before the drape has placed the garment on it).
    std::vector<Eigen::Index> previewed;
    QObject::connect(&s.window.bodyPreview(), &BodyPreview::built, &s.window,
                     [&](const patterns::BodySource&, const patterns::Body& body) {
                         EXPECT_EQ(s.window.viewport().previewBodyVertices(), body.vertices.rows());
                         previewed.push_back(body.vertices.rows());
                     });
    QSignalSpy edited(&dock, &BodyDock::bodyEdited);
    // Three arrow clicks in a row: announced once, built once, one undo entry.
    for (int k = 0; k < 3; ++k) {
        waist->stepUp();
    }
    ASSERT_TRUE(waitFor([&] { return s.window.undoStack().count() == 1; }, 60))
        << dock.problem().toStdString();
    EXPECT_EQ(edited.count(), 1);
    EXPECT_EQ(previewed.size(), 1u);
    const auto waistOf = [](const patterns::BodySource& body) {
        for (const auto& [name, value] : body.measurements) {
            if (name == "waist") {
                return value;
            }
        }
        return -1.0;
    };
    EXPECT_NEAR(waistOf(s.window.project().body), patterns::BodyMeasurements{}.waist + 0.03, 1e-12);
    // The garment is placed again on the new body.
    ASSERT_TRUE(waitFor(
        [&] {
            const auto now = s.window.drape().staticScene();
            return now && now != placed && now->bodyPositions.rows() > 0 &&
                   !now->bodyPositions.isApprox(placed->bodyPositions);
        },
        60));
    // The same field again: the same entry.
    waist->stepUp();
    ASSERT_TRUE(
        waitFor([&] { return s.window.bodyPreview().idle() && previewed.size() == 2; }, 60));
    EXPECT_EQ(s.window.undoStack().count(), 1);
    EXPECT_NEAR(waistOf(s.window.project().body), patterns::BodyMeasurements{}.waist + 0.04, 1e-12);

    const int built = s.window.drape().bodiesBuilt();
    s.window.undoStack().undo();
    EXPECT_EQ(s.window.project().body, was);
    EXPECT_DOUBLE_EQ(waist->value(), patterns::BodyMeasurements{}.waist * 100);
    ASSERT_TRUE(waitFor(
        [&] {
            const auto now = s.window.drape().staticScene();
            return now && now->bodyPositions.rows() == placed->bodyPositions.rows() &&
                   now->bodyPositions == placed->bodyPositions;
        },
        60))
        << "the first body again, to the bit";
    EXPECT_EQ(s.window.drape().bodiesBuilt(), built) << "the first body is not built again";
    EXPECT_TRUE(s.prompts.errors.isEmpty()) << s.prompts.errors.join("; ").toStdString();
}

TEST(PanelDock, APanelsOwnParticleDistanceRemeshesItUndoably) {
    SkirtWindow s;
    ASSERT_TRUE(s.open());
    PanelDock& dock = s.window.panelDock();
    EXPECT_EQ(dock.particleDistanceField()->value(), 0.0) << "the drape's distance";
    ASSERT_TRUE(s.drapeFollows());
    const auto frontTriangles = [&] {
        const auto scene = s.window.drape().staticScene();
        return scene == nullptr ? -1 : scene->panelTriangles.front().second;
    };
    const int atDrapes = frontTriangles();
    const int undoBefore = s.window.undoStack().count();
    dock.particleDistanceField()->setValue(25);
    dock.particleDistanceField()->setValue(20);
    EXPECT_DOUBLE_EQ(s.frontPanel().particleDistance, 0.02);
    EXPECT_EQ(s.window.undoStack().count(), undoBefore + 1) << "one field's changes in a row";
    ASSERT_TRUE(s.drapeFollows());
    // The front re-meshed at 20 mm: about a quarter of its triangles at the skirt's 10 mm.
    ASSERT_TRUE(
        waitFor([&] { return frontTriangles() > 0 && frontTriangles() < atDrapes / 2; }, 120))
        << frontTriangles() << " against " << atDrapes;
    s.window.undoStack().undo();
    EXPECT_EQ(s.frontPanel().particleDistance, 0.0);
    EXPECT_EQ(dock.particleDistanceField()->value(), 0.0);
    EXPECT_TRUE(s.drapeFollows());
    EXPECT_TRUE(s.prompts.errors.isEmpty()) << s.prompts.errors.join("; ").toStdString();
}

TEST(Viewport, ASlotMarkerClickAndThePlacementHandlePlaceTheSelectedPanels) {
    SkirtWindow s;
    ASSERT_TRUE(s.open());
    Viewport& view = s.window.viewport();
    EXPECT_FALSE(view.slotMarker("torso_front")) << "slots are hidden by default";
    view.setSlotsShown(true);
    view.setView(render::View::Front);
    QCoreApplication::processEvents();
    const auto marker = view.slotMarker("torso_front");
    ASSERT_TRUE(marker);
    ASSERT_TRUE(view.rect().contains(marker->toPoint()));
    EXPECT_EQ(view.slotAt(*marker), "torso_front");
    EXPECT_EQ(view.highlightedSlot().toStdString(), s.frontPanel().placement.slot)
        << "the selected panel's slot";
    QMouseEvent press(QEvent::MouseButtonPress, *marker, view.mapToGlobal(*marker), Qt::LeftButton,
                      Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(&view, &press);
    EXPECT_EQ(s.frontPanel().placement.slot, "torso_front");
    EXPECT_EQ(view.highlightedSlot(), "torso_front");
    EXPECT_EQ(s.window.undoStack().count(), 1);
    EXPECT_TRUE(s.drapeFollows());

    // The selected panel's handle, at its cloth's centre as placed: dragged 40 pixels right and
    // 30 up in the front view, the panel moves around the slot (towards +x, the slot's right)
    // and up along it, in one undoable step; the slot and the turn stay.
    QCoreApplication::processEvents();
    const auto handle = view.placementHandle();
    ASSERT_TRUE(handle);
    ASSERT_TRUE(view.rect().contains(handle->toPoint()));
    const patterns::Placement placed = s.frontPanel().placement;
    const QPointF to = *handle + QPointF(40, -30);
    // A left-button drag in the view: press, one move, release.
    const auto dragIn = [&view](const QPointF& from, const QPointF& to) {
        QMouseEvent press(QEvent::MouseButtonPress, from, view.mapToGlobal(from), Qt::LeftButton,
                          Qt::LeftButton, Qt::NoModifier);
        QApplication::sendEvent(&view, &press);
        QMouseEvent move(QEvent::MouseMove, to, view.mapToGlobal(to), Qt::NoButton, Qt::LeftButton,
                         Qt::NoModifier);
        QApplication::sendEvent(&view, &move);
        QMouseEvent release(QEvent::MouseButtonRelease, to, view.mapToGlobal(to), Qt::LeftButton,
                            Qt::NoButton, Qt::NoModifier);
        QApplication::sendEvent(&view, &release);
    };
    dragIn(*handle, to);
    EXPECT_EQ(s.window.undoStack().count(), 2);
    const patterns::Placement moved = s.frontPanel().placement;
    EXPECT_EQ(moved.slot, placed.slot);
    EXPECT_EQ(moved.rotation, placed.rotation);
    EXPECT_GT(moved.offset.x() - placed.offset.x(), 0.01);
    EXPECT_GT(moved.offset.y() - placed.offset.y(), 0.01);
    EXPECT_FALSE(s.window.drape().running()) << "the handle does not grab the cloth";
    EXPECT_TRUE(s.drapeFollows());
    s.window.undoStack().undo();
    EXPECT_EQ(s.frontPanel().placement.offset, placed.offset);
    ASSERT_TRUE(s.drapeFollows());
    // Its rotation knob above it, dragged a quarter turn counter-clockwise round it.
    QCoreApplication::processEvents();
    const auto centre = view.placementHandle();
    const auto knob = view.rotationKnob();
    ASSERT_TRUE(centre && knob);
    const double arm = centre->y() - knob->y();
    const QPointF left = *centre - QPointF(arm, 0);
    dragIn(*knob, left);
    EXPECT_EQ(s.window.undoStack().count(), 2);
    EXPECT_NEAR(s.frontPanel().placement.rotation, placed.rotation + std::numbers::pi / 2, 1e-6);
    EXPECT_EQ(s.frontPanel().placement.offset, placed.offset);
    EXPECT_TRUE(s.drapeFollows());

    // Ctrl+click on the back panel in the pattern adds it to the selection; a click on the
    // torso_front marker then places both there side by side (patterns::sideBySide, the front,
    // selected first, on the left), one undo entry that undo takes back whole.
    const patterns::PanelId back = s.window.project().document.panels.at(1).id;
    const patterns::doc::Panel& backPanel = *s.window.project().document.panel(back);
    patterns::Vec2 inside = patterns::Vec2::Zero();
    for (const patterns::doc::Point& p : backPanel.outline.points) {
        inside += p.position / static_cast<double>(backPanel.outline.points.size());
    }
    inside = 0.7 * inside + 0.3 * backPanel.outline.points.front().position;
    PatternView& pattern = s.window.patternView();
    const QPoint onBack = pattern.viewPoint(back, inside);
    QTest::mouseClick(pattern.viewport(), Qt::LeftButton, Qt::ControlModifier, onBack);
    ASSERT_EQ(pattern.selectedPanels(), (std::vector<patterns::PanelId>{s.front, back}));
    EXPECT_EQ(pattern.selectedPanel(), back) << "the last one selected is shown in the docks";
    const patterns::GarmentDocument single = s.window.project().document;
    const auto expected = patterns::sideBySide(single, {s.front, back}, "torso_front");
    QCoreApplication::processEvents();
    const auto front = view.slotMarker("torso_front");
    ASSERT_TRUE(front);
    QTest::mouseClick(&view, Qt::LeftButton, {}, front->toPoint());
    EXPECT_EQ(s.window.undoStack().count(), 3);
    for (const auto& [id, placement] : expected) {
        EXPECT_EQ(s.window.project().document.panel(id)->placement.slot, "torso_front");
        EXPECT_EQ(s.window.project().document.panel(id)->placement.offset, placement.offset);
    }
    EXPECT_LT(expected[0].second.offset.x(), expected[1].second.offset.x());
    EXPECT_EQ(pattern.selectedPanels().size(), 2U) << "the selection survives the edit";
    EXPECT_TRUE(s.drapeFollows());
    s.window.undoStack().undo();
    EXPECT_EQ(patterns::dumpDocument(s.window.project().document), patterns::dumpDocument(single));
    EXPECT_TRUE(s.drapeFollows());
    // Ctrl+click on it again takes it out of the selection.
    QTest::mouseClick(pattern.viewport(), Qt::LeftButton, Qt::ControlModifier, onBack);
    EXPECT_EQ(pattern.selectedPanels(), (std::vector<patterns::PanelId>{s.front}));

    // Another project: no panel shown, so a click on a marker places nothing.
    ASSERT_TRUE(openAndWait(s.window, GARMENTS + "/tshirt.atelier"));
    EXPECT_FALSE(s.window.panelDock().panel());
    EXPECT_TRUE(view.highlightedSlot().isEmpty());
    QCoreApplication::processEvents();
    const auto torso = view.slotMarker("torso_front");
    ASSERT_TRUE(torso);
    const std::string opened = patterns::dumpDocument(s.window.project().document);
    QMouseEvent again(QEvent::MouseButtonPress, *torso, view.mapToGlobal(*torso), Qt::LeftButton,
                      Qt::LeftButton, Qt::NoModifier);
    QApplication::sendEvent(&view, &again);
    EXPECT_EQ(patterns::dumpDocument(s.window.project().document), opened);
    EXPECT_EQ(s.window.undoStack().count(), 0);
}

TEST(PanelDock, GivesThePanelAPresetFabricInOneUndoableStep) {
    SkirtWindow s;
    ASSERT_TRUE(s.open());
    const std::string before = patterns::dumpDocument(s.window.project().document);
    QComboBox* fabric = s.window.panelDock().fabricChooser();
    EXPECT_EQ(fabric->currentText(), "fabric");
    const int denim = fabric->findData("denim");
    ASSERT_GE(denim, 0) << "presets not in the document are offered";
    QSignalSpy rebuilt(&s.window.drape(), &DrapeController::rebuilt);
    fabric->setCurrentIndex(denim);
    Q_EMIT fabric->activated(denim);
    const patterns::GarmentDocument& d = s.window.project().document;
    EXPECT_EQ(s.frontPanel().material, "denim");
    ASSERT_EQ(d.materials.size(), 2U);
    EXPECT_EQ(d.materials.back().name, "denim");
    EXPECT_EQ(d.materials.back().material.name, "denim");
    EXPECT_EQ(d.panels.back().material, "fabric") << "the other panel keeps its fabric";
    EXPECT_EQ(s.window.undoStack().count(), 1) << "adding the fabric and giving it: one step";
    EXPECT_EQ(s.window.fabricDock().fabric(), "denim");
    EXPECT_TRUE(s.drapeFollows());
    ASSERT_TRUE(waitFor([&] { return rebuilt.count() >= 2; }, 120)) << "two edits, two rebuilds";
    EXPECT_TRUE(rebuilt.at(0).front().toBool() && rebuilt.at(1).front().toBool())
        << "the new fabric is added to the drape, which goes on";

    // Back to the document's first fabric: a second, plain edit.
    const int first = fabric->findData("fabric");
    fabric->setCurrentIndex(first);
    Q_EMIT fabric->activated(first);
    EXPECT_EQ(s.frontPanel().material, "fabric");
    EXPECT_EQ(s.window.undoStack().count(), 2);
    s.window.undoStack().undo();
    s.window.undoStack().undo();
    EXPECT_EQ(patterns::dumpDocument(s.window.project().document), before);
    EXPECT_TRUE(s.drapeFollows());
}

TEST(FabricDock, EditsTheFabricAndShowsItsBendingLength) {
    SkirtWindow s;
    ASSERT_TRUE(s.open());
    FabricDock& dock = s.window.fabricDock();
    EXPECT_EQ(dock.fabric(), "fabric");
    const sim::Material was = s.window.project().document.materials.front().material;
    // The figure is the cantilever's: ρ g c³ = B.
    const double c = bendingLength(was.bending, was.density);
    EXPECT_NEAR(was.density * GRAVITY * c * c * c, was.bending, 1e-12 * was.bending);
    EXPECT_TRUE(dock.figuresText().contains(QString::number(c * 1000, 'f', 1)))
        << dock.figuresText().toStdString();

    dock.densityField()->setValue(was.density * 1000 * 2); // twice as heavy
    const sim::Material now = s.window.project().document.materials.front().material;
    EXPECT_NEAR(now.density, 2 * was.density, 1e-4);
    EXPECT_EQ(now.bending, was.bending) << "fields left alone keep their exact values";
    EXPECT_EQ(now.stretchWeft, was.stretchWeft);
    const double shorter = bendingLength(now.bending, now.density);
    EXPECT_NEAR(shorter, c / std::cbrt(2.0), 1e-3 * c);
    EXPECT_TRUE(dock.figuresText().contains(QString::number(shorter * 1000, 'f', 1)));
    EXPECT_TRUE(s.drapeFollows());

    // A preset's values.
    const int silk = dock.presetChooser()->findText("silk");
    ASSERT_GT(silk, 0);
    dock.presetChooser()->setCurrentIndex(silk);
    Q_EMIT dock.presetChooser()->activated(silk);
    EXPECT_EQ(s.window.project().document.materials.front().material.name, "silk");
    EXPECT_EQ(s.window.project().document.materials.front().name, "fabric");
    EXPECT_EQ(s.window.undoStack().count(), 2);
    s.window.undoStack().undo();
    s.window.undoStack().undo();
    EXPECT_EQ(s.window.project().document.materials.front().material.density, was.density);
    EXPECT_TRUE(s.drapeFollows());
    EXPECT_TRUE(s.prompts.errors.isEmpty()) << s.prompts.errors.join("; ").toStdString();
}

TEST(FabricDock, MeasuresTheDrapeCoefficientOfTheValuesShown) {
    SkirtWindow s;
    ASSERT_TRUE(s.open());
    FabricDock& dock = s.window.fabricDock();
    EXPECT_TRUE(dock.figuresText().contains("not measured")) << dock.figuresText().toStdString();
    QSignalSpy shown(&dock, &FabricDock::drapeCoefficientShown);
    dock.measureDrapeButton()->click();
    EXPECT_TRUE(dock.figuresText().contains("measuring"));
    ASSERT_TRUE(waitFor([&] { return shown.count() >= 1; }, 120));
    // The figure is the Cusick test's, run here the same way.
    patterns::CusickOptions test = FabricDock::drapeTest();
    test.material = s.window.project().document.materials.front().material;
    const patterns::CusickResult r = patterns::runCusick(test);
    ASSERT_TRUE(r.error.empty()) << r.error;
    EXPECT_TRUE(dock.figuresText().contains(QString::number(r.drapeCoefficient, 'f', 3) + ", " +
                                            QString::number(r.nodes) + " nodes"))
        << dock.figuresText().toStdString();
    // Other values: the figure no longer applies until measured again.
    dock.bendingField()->setValue(dock.bendingField()->value() * 3);
    EXPECT_TRUE(dock.figuresText().contains("not measured")) << dock.figuresText().toStdString();
    EXPECT_TRUE(s.prompts.errors.isEmpty()) << s.prompts.errors.join("; ").toStdString();
}

TEST(SeamDock, ShowsASeamsSidesAndMismatchAndReversesAndDeletesIt) {
    SkirtWindow s;
    ASSERT_TRUE(s.open());
    SeamDock& dock = s.window.seamDock();
    const patterns::GarmentDocument& d = s.window.project().document;
    ASSERT_FALSE(d.seams.empty());
    const patterns::doc::Seam seam = d.seams.front();
    const std::string before = patterns::dumpDocument(d);
    EXPECT_FALSE(dock.seam());
    EXPECT_FALSE(dock.reverseButton()->isEnabled());
    dock.showSeam(seam.id);
    ASSERT_EQ(dock.seam(), seam.id);
    const double a = seamSideLength(d, seam.a);
    const double b = seamSideLength(d, seam.b);
    EXPECT_GT(a, 0.05);
    EXPECT_TRUE(dock.sideText(0).contains(QString::number(a * 1000, 'f', 1)))
        << dock.sideText(0).toStdString();
    EXPECT_TRUE(dock.sideText(0).contains("front")) << dock.sideText(0).toStdString();
    EXPECT_TRUE(dock.sideText(1).contains(QString::number(b * 1000, 'f', 1)));
    EXPECT_TRUE(dock.sideText(1).contains("back"));
    EXPECT_TRUE(dock.mismatchText().contains(QString::number((a - b) * 1000, 'f', 1)))
        << dock.mismatchText().toStdString();
    dock.showSeam(patterns::SeamId{999999});
    EXPECT_FALSE(dock.seam()) << "an unknown seam shows nothing";
    dock.showSeam(seam.id);

    // How it bends once sewn: flat and as stiff as the cloth until told otherwise.
    EXPECT_EQ(dock.foldBox()->value(), 0.0);
    EXPECT_EQ(dock.bendingScaleBox()->value(), 1.0);
    dock.foldBox()->setValue(30.0);
    Q_EMIT dock.foldBox()->editingFinished();
    dock.bendingScaleBox()->setValue(3.0);
    Q_EMIT dock.bendingScaleBox()->editingFinished();
    Q_EMIT dock.bendingScaleBox()->editingFinished(); // nothing changed: no edit
    const patterns::doc::Seam* bent = s.window.project().document.seam(seam.id);
    EXPECT_NEAR(bent->foldAngle, std::numbers::pi / 6, 1e-12);
    EXPECT_EQ(bent->bendingScale, 3.0);

    dock.reverseButton()->click();
    const patterns::doc::Seam reversed = *s.window.project().document.seam(seam.id);
    ASSERT_EQ(reversed.b.size(), seam.b.size());
    EXPECT_EQ(reversed.b.front().t0, seam.b.back().t1);
    EXPECT_TRUE(s.drapeFollows());
    dock.deleteButton()->click();
    EXPECT_EQ(s.window.project().document.seam(seam.id), nullptr);
    EXPECT_FALSE(dock.seam()) << "the deleted seam is no longer shown";
    EXPECT_EQ(s.window.undoStack().count(), 4);
    for (int k = 0; k < 4; ++k) {
        s.window.undoStack().undo();
    }
    EXPECT_EQ(patterns::dumpDocument(s.window.project().document), before);
    ASSERT_NE(s.window.project().document.seam(seam.id), nullptr);
    EXPECT_EQ(s.window.project().document.seam(seam.id)->b.front().t0, seam.b.front().t0);
    EXPECT_TRUE(s.drapeFollows());
}

TEST(SimulationDock, ThePlotFollowsTheDrapeAndSettingsAreUndoable) {
    SkirtWindow s;
    ASSERT_TRUE(s.open());
    SimulationDock& dock = s.window.simulationDock();
    DrapePlot& plot = dock.plot();
    EXPECT_TRUE(plot.samples().empty());
    s.window.drape().start();
    ASSERT_TRUE(waitFor([&] { return plot.samples().size() >= 3; }, 240))
        << "the status timer feeds the plot while the drape runs";
    s.window.drape().pause();
    ASSERT_TRUE(waitFor([&] { return !s.window.drape().running(); }, 10));
    const auto& samples = plot.samples();
    for (std::size_t i = 1; i < samples.size(); ++i) {
        EXPECT_GT(samples[i].time, samples[i - 1].time);
        EXPECT_TRUE(std::isfinite(samples[i].energy));
    }
    EXPECT_GT(samples.back().energy, 0);
    EXPECT_EQ(samples.back().phase, s.window.drape().progress().phase);

    // The time step: continues the drape; undo gives the old one back.
    const double dt = s.window.project().drape.dt;
    QSignalSpy continued(&s.window.drape(), &DrapeController::rebuilt);
    dock.timeStepField()->setValue(2.0);
    EXPECT_EQ(s.window.project().drape.dt, 0.002);
    EXPECT_EQ(s.window.project().drape.particleDistance, 0.01) << "left alone, exactly";
    EXPECT_TRUE(s.window.isModified());
    s.window.undoStack().undo();
    EXPECT_EQ(s.window.project().drape.dt, dt);
    EXPECT_NEAR(dock.timeStepField()->value(), dt * 1000, 1e-3);
    ASSERT_TRUE(waitFor([&] { return continued.count() >= 2; }, 120));
    EXPECT_TRUE(continued.at(0).front().toBool()) << "a new time step continues the drape";
    EXPECT_TRUE(continued.at(1).front().toBool());

    // The particle distance: re-meshed and placed again, the plot starts over on the reset.
    QSignalSpy rebuilt(&s.window.drape(), &DrapeController::rebuilt);
    const auto triangles = s.window.drape().staticScene()->garmentTriangles.rows();
    dock.particleDistanceField()->setValue(20);
    EXPECT_EQ(s.window.project().drape.particleDistance, 0.02);
    ASSERT_TRUE(waitFor([&] { return rebuilt.count() >= 1; }, 120));
    EXPECT_FALSE(rebuilt.front().front().toBool()) << "placed again";
    EXPECT_LT(s.window.drape().staticScene()->garmentTriangles.rows(), triangles / 2);
    s.window.undoStack().undo();
    ASSERT_TRUE(waitFor([&] { return rebuilt.count() >= 2; }, 120));
    EXPECT_EQ(s.window.drape().staticScene()->garmentTriangles.rows(), triangles);
    EXPECT_TRUE(s.prompts.errors.isEmpty()) << s.prompts.errors.join("; ").toStdString();
}

TEST(MainWindow, ExportsThePatternAsTheCliDoes) {
    SkirtWindow s;
    ASSERT_TRUE(s.open());
    const QString path = s.dir.filePath("skirt.svg");
    ASSERT_TRUE(s.window.exportPatternSvg(path));
    std::ifstream in(path.toStdString(), std::ios::binary);
    std::ostringstream bytes;
    bytes << in.rdbuf();
    // The library function atelier-cli export-pattern calls, with its defaults.
    const auto expected = io::patternSvg(s.window.project().garment, {});
    ASSERT_TRUE(expected.ok());
    EXPECT_EQ(bytes.str(), expected.value().text);
    EXPECT_NE(bytes.str().find("front"), std::string::npos);

    // A folder that does not exist: a message, no crash, nothing written.
    EXPECT_FALSE(s.window.exportPatternSvg(s.dir.filePath("missing/skirt.svg")));
    EXPECT_EQ(s.prompts.errors.size(), 1);
}

TEST(MainWindow, RendersTheViewAtTheSizeAsked) {
    {
        auto context = render::HeadlessContext::create();
        if (!context.ok()) {
            GTEST_SKIP() << "no EGL context here: " << context.error().toString();
        }
    }
    SkirtWindow s;
    ASSERT_TRUE(s.open());
    const QString path = s.dir.filePath("skirt.png");
    ASSERT_TRUE(s.window.renderImage(path, 320, 200)) << s.prompts.errors.join("; ").toStdString();
    const QImage image = QImage(path).convertToFormat(QImage::Format_RGB32);
    ASSERT_EQ(image.size(), QSize(320, 200));
    // The background in a corner, the garment or body in the middle.
    EXPECT_NE(image.pixel(160, 100), image.pixel(0, 0));
    EXPECT_FALSE(s.window.renderImage(path, 0, 200)) << "no pixels: refused";
}

TEST(MainWindow, TheVeryFirstStartOpensTheTshirt) {
    // Settings of this test alone, empty: a first start.
    const QString settingsFile = QSettings().fileName();
    const QString previous = QFileInfo(QFileInfo(settingsFile).absolutePath()).absolutePath();
    const QTemporaryDir fresh;
    QSettings::setPath(QSettings::NativeFormat, QSettings::UserScope, fresh.path());
    ASSERT_TRUE(QSettings().allKeys().isEmpty());
    {
        QTemporaryDir dir;
        MainWindow window(GARMENTS);
        QuietPrompts prompts;
        prompts.install(window);
        window.setRecoveryDirectory(dir.filePath("recovery"));
        QSignalSpy ready(&window, &MainWindow::projectReady);
        ASSERT_TRUE(window.openFirstRunSample());
        EXPECT_EQ(QFileInfo(window.projectPath()).fileName(), "tshirt.atelier");
        EXPECT_EQ(window.project().name, "tshirt");
        EXPECT_TRUE(waitFor([&] { return ready.count() >= 1; }, 120));
        EXPECT_FALSE(window.openFirstRunSample()) << "only the first start";
    }
    {
        MainWindow again(GARMENTS);
        EXPECT_FALSE(again.openFirstRunSample()) << "the settings remember the first start";
        EXPECT_TRUE(again.projectPath().isEmpty());
    }
    QSettings::setPath(QSettings::NativeFormat, QSettings::UserScope, previous);
}

} // namespace
} // namespace atelier::ui
