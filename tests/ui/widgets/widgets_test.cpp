// The desktop application's widgets without a display (QT_QPA_PLATFORM=offscreen): the drape
// controller on its worker thread, the pattern view, the viewport's picture.
#include "ui/render/headless_context.h"
#include "ui/widgets/body_dock.h"
#include "ui/widgets/drape_controller.h"
#include "ui/widgets/main_window.h"
#include "ui/widgets/pattern_view.h"
#include "ui/widgets/viewport.h"
#include "ui/widgets/widget_test_support.h"

#include "io/atomic_file.h"
#include "io/body_file.h"
#include "io/garmentcode.h"
#include "io/obj.h"
#include "io/project_file.h"

#include "patterns/curve.h"
#include "patterns/document_edit.h"

#include <QAction>
#include <QApplication>
#include <QComboBox>
#include <QDir>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QMimeData>
#include <QProcess>
#include <QSettings>
#include <QSignalSpy>
#include <QSplitter>
#include <QStandardPaths>
#include <QStatusBar>
#include <QTemporaryDir>
#include <QTest>
#include <QToolButton>
#include <QUndoStack>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <fstream>
#include <memory>
#include <sstream>

namespace atelier::ui {
namespace {

using test::GARMENTS;

using test::openAndWait;
using test::waitFor;

/// Drags `file` onto the window and drops it there: whether the window took the drag and the
/// drop.
std::pair<bool, bool> dragAndDrop(MainWindow& window, const QString& file) {
    QMimeData data;
    data.setUrls({QUrl::fromLocalFile(file)});
    QDragEnterEvent enter(QPoint(50, 50), Qt::CopyAction, &data, Qt::LeftButton, {});
    QApplication::sendEvent(&window, &enter);
    QDropEvent drop(QPointF(50, 50), Qt::CopyAction, &data, Qt::LeftButton, {});
    QApplication::sendEvent(&window, &drop);
    return {enter.isAccepted(), drop.isAccepted()};
}

/// The bytes of a file.
std::string bytesOf(const QString& path) {
    std::ifstream in(path.toStdString(), std::ios::binary);
    std::ostringstream out;
    out << in.rdbuf();
    return out.str();
}

/// Prompts that never block and record what they were asked: errors are collected, unsaved
/// changes get `answer`, recovery files are restored.
struct RecordingPrompts {
    QStringList errors;
    QStringList restoreOffers;
    QMessageBox::StandardButton answer = QMessageBox::Discard;

    void install(MainWindow& window) {
        Prompts p;
        p.error = [this](const QString& message) { errors << message; };
        p.saveChanges = [this](const QString&) { return answer; };
        p.restore = [this](const QString& recovery, const QString&) {
            restoreOffers << recovery;
            return true;
        };
        p.saveFileName = [] { return QString(); };
        window.setPrompts(std::move(p));
    }
};

void sendMouse(QWidget* widget, QEvent::Type type, QPoint at, Qt::MouseButton button,
               Qt::MouseButtons buttons, Qt::KeyboardModifiers modifiers = {}) {
    QMouseEvent event(type, QPointF(at), widget->mapToGlobal(QPointF(at)), button, buttons,
                      modifiers);
    QApplication::sendEvent(widget, &event);
}

TEST(DrapeController, OpensStartsPausesAndResets) {
    DrapeController drape;
    QSignalSpy opened(&drape, &DrapeController::opened);
    drape.open(GARMENTS + "/skirt.atelier");
    ASSERT_TRUE(waitFor([&] { return opened.count() == 1; }, 120));
    const auto scene = drape.staticScene();
    ASSERT_TRUE(scene);
    EXPECT_EQ(scene->panelNames.size(), 2U);
    EXPECT_GT(scene->garmentTriangles.rows(), 500);
    EXPECT_EQ(scene->startPositions.rows(), scene->patternUvs.rows());
    EXPECT_GT(scene->bodyTriangles.rows(), 10000);
    EXPECT_EQ(drape.progress().phase, patterns::DrapePhase::Placing);
    sim::Snapshot s;
    EXPECT_FALSE(drape.snapshot(s)) << "nothing stepped yet";

    drape.start();
    ASSERT_TRUE(waitFor([&] { return drape.progress().steps >= 5; }, 120));
    drape.pause();
    ASSERT_TRUE(waitFor([&] { return !drape.running(); }, 5));
    QCoreApplication::processEvents();
    const long steps = drape.progress().steps;
    // Paused: a step already under way may finish, no more after it.
    waitFor([] { return false; }, 0.5);
    EXPECT_LE(drape.progress().steps, steps + 1);
    ASSERT_TRUE(drape.snapshot(s));
    EXPECT_EQ(s.clothPositions.rows(), scene->startPositions.rows());
    EXPECT_TRUE(s.clothPositions.allFinite());
    EXPECT_GT(s.time, 0);

    drape.reset();
    ASSERT_TRUE(waitFor([&] { return opened.count() == 2; }, 120));
    EXPECT_EQ(drape.progress().phase, patterns::DrapePhase::Placing);
    EXPECT_FALSE(drape.snapshot(s)) << "the reset garment is back where it was placed";
}

TEST(DrapeController, AGrabPullsTheClothAndStartsTheDrape) {
    DrapeController drape;
    QSignalSpy opened(&drape, &DrapeController::opened);
    drape.open(GARMENTS + "/skirt.atelier");
    ASSERT_TRUE(waitFor([&] { return opened.count() == 1; }, 120));
    const auto scene = drape.staticScene();
    const int t = 10;
    const auto corner = [&](const sim::MatX3& x, int k) {
        return sim::Vec3(x.row(scene->garmentTriangles(t, k)));
    };
    const sim::Vec3 start = (corner(scene->startPositions, 0) + corner(scene->startPositions, 1) +
                             corner(scene->startPositions, 2)) /
                            3;
    const sim::Vec3 target = start + sim::Vec3(0, 0, 0.05);
    drape.grab(sim::ClothPoint{t, sim::Vec3::Constant(1.0 / 3)}, target);
    ASSERT_TRUE(waitFor([&] { return drape.progress().steps >= 15; }, 120))
        << "a grab starts the drape";
    drape.pause();
    ASSERT_TRUE(waitFor([&] { return !drape.running(); }, 5));
    sim::Snapshot s;
    ASSERT_TRUE(drape.snapshot(s));
    const sim::Vec3 now =
        (corner(s.clothPositions, 0) + corner(s.clothPositions, 1) + corner(s.clothPositions, 2)) /
        3;
    EXPECT_LT((now - target).norm(), 0.5 * (start - target).norm())
        << "the grabbed point went more than half way to the target";
    drape.release();
    drape.start();
    ASSERT_TRUE(waitFor([&] { return drape.progress().steps >= 25; }, 120));
    drape.pause();
}

TEST(DrapeController, AProjectThatCannotBeReadIsAnErrorNamingIt) {
    DrapeController drape;
    QSignalSpy failed(&drape, &DrapeController::failed);
    drape.open(QStringLiteral("/nonexistent/shirt.atelier"));
    ASSERT_TRUE(waitFor([&] { return failed.count() == 1; }, 30));
    EXPECT_TRUE(failed.front().front().toString().contains("shirt.atelier"))
        << failed.front().front().toString().toStdString();
    EXPECT_FALSE(drape.staticScene());
}

TEST(PatternView, DrawsEveryPanel) {
    MainWindow window(GARMENTS);
    QSignalSpy ready(&window, &MainWindow::projectReady);
    window.openProject(GARMENTS + "/tshirt.atelier");
    ASSERT_TRUE(waitFor([&] { return ready.count() == 1; }, 120));
    EXPECT_EQ(window.patternView().panelCount(),
              static_cast<int>(window.drape().staticScene()->garment.panels.size()));
    EXPECT_GE(window.patternView().panelCount(), 4);
}

TEST(Viewport, DrawsTheGarmentOnItsBody) {
    {
        auto context = render::HeadlessContext::create();
        if (!context.ok()) {
            GTEST_SKIP() << "no EGL context here: " << context.error().toString();
        }
    }
    MainWindow window(GARMENTS);
    window.resize(900, 600);
    window.show();
    QSignalSpy ready(&window, &MainWindow::projectReady);
    window.openProject(GARMENTS + "/skirt.atelier");
    ASSERT_TRUE(waitFor([&] { return ready.count() == 1; }, 120));
    ASSERT_TRUE(waitFor([&] { return !window.viewport().picture().isNull(); }, 30))
        << window.viewport().rendererError().toStdString();
    const QImage picture = window.viewport().picture().convertToFormat(QImage::Format_RGB32);
    // The skirt's front panel (reddish, render::panelColour(0)), and the background.
    int garment = 0;
    int background = 0;
    for (int y = 0; y < picture.height(); ++y) {
        for (int x = 0; x < picture.width(); ++x) {
            const QColor c = picture.pixelColor(x, y);
            garment += c.red() > c.green() + 40 && c.red() > c.blue() + 40 ? 1 : 0;
            background += std::abs(c.red() - 237) < 3 && std::abs(c.blue() - 240) < 3 ? 1 : 0;
        }
    }
    const double total = double(picture.width()) * picture.height();
    EXPECT_GT(garment / total, 0.01) << "the red front panel covers some of the view";
    EXPECT_GT(background / total, 0.3);
    EXPECT_LT(background / total, 0.98);

    // Pressing on the cloth grabs it: the drape starts; dragging and letting go keep it finite.
    QPoint onCloth(-1, -1);
    for (int y = picture.height() / 2; y < picture.height() && onCloth.x() < 0; ++y) {
        for (int x = 0; x < picture.width(); ++x) {
            const QColor c = picture.pixelColor(x, y);
            if (c.red() > c.green() + 40 && c.red() > c.blue() + 40) {
                // A few pixels in from the panel's edge, where the pixel's ray surely hits it.
                onCloth = QPoint(x + 3, y) / window.viewport().devicePixelRatioF();
                break;
            }
        }
    }
    ASSERT_GE(onCloth.x(), 0);
    EXPECT_FALSE(window.drape().running());
    QTest::mousePress(&window.viewport(), Qt::LeftButton, {}, onCloth);
    ASSERT_TRUE(waitFor([&] { return window.drape().progress().steps >= 3; }, 120));
    // While it runs, the render thread draws drafts (0.6 of the resolution) that arrive
    // through the event loop, one per new snapshot.
    const long framesBefore = window.viewport().framesDrawn();
    ASSERT_TRUE(waitFor([&] { return window.viewport().framesDrawn() >= framesBefore + 2; }, 60));
    const qreal ratio = window.viewport().devicePixelRatioF();
    EXPECT_NEAR(window.viewport().picture().width(), window.viewport().width() * ratio * 0.6, 1);
    QTest::mouseMove(&window.viewport(), onCloth + QPoint(30, -20));
    waitFor([] { return false; }, 0.3);
    QTest::mouseRelease(&window.viewport(), Qt::LeftButton, {}, onCloth + QPoint(30, -20));
    waitFor([] { return false; }, 0.3);
    window.drape().pause();
    ASSERT_TRUE(waitFor([&] { return !window.drape().running(); }, 5));
    sim::Snapshot s;
    ASSERT_TRUE(window.drape().snapshot(s));
    EXPECT_TRUE(s.clothPositions.allFinite());
    // Paused, a paint draws at once, at full resolution.
    window.viewport().drawNow();
    EXPECT_NEAR(window.viewport().picture().width(), window.viewport().width() * ratio, 1);
}

TEST(Viewport, AltClickPinsTheClothAndUnpinsAPinhead) {
    {
        auto context = render::HeadlessContext::create();
        if (!context.ok()) {
            GTEST_SKIP() << "no EGL context here: " << context.error().toString();
        }
    }
    MainWindow window(GARMENTS);
    window.resize(900, 600);
    window.show();
    QSignalSpy ready(&window, &MainWindow::projectReady);
    window.openProject(GARMENTS + "/skirt.atelier");
    ASSERT_TRUE(waitFor([&] { return ready.count() == 1; }, 120));
    ASSERT_TRUE(waitFor([&] { return !window.viewport().picture().isNull(); }, 30))
        << window.viewport().rendererError().toStdString();
    DrapeController& drape = window.drape();
    EXPECT_TRUE(drape.pinnedVertices().empty());
    const auto scene = drape.staticScene();

    // Alt+click in the middle of the picture, on the cloth, pins the nearest vertex there.
    QSignalSpy pinsChanged(&drape, &DrapeController::pinsChanged);
    const QImage before = window.viewport().picture().convertToFormat(QImage::Format_RGB32);
    QPoint onCloth(-1, -1);
    for (int y = before.height() / 2; y < before.height() && onCloth.x() < 0; ++y) {
        for (int x = 0; x < before.width(); ++x) {
            const QColor c = before.pixelColor(x, y);
            if (c.red() > c.green() + 40 && c.red() > c.blue() + 40) {
                // A few pixels in from the panel's edge, where the pixel's ray surely hits it.
                onCloth = QPoint(x + 3, y) / window.viewport().devicePixelRatioF();
                break;
            }
        }
    }
    ASSERT_GE(onCloth.x(), 0);
    QTest::mouseClick(&window.viewport(), Qt::LeftButton, Qt::AltModifier, onCloth);
    ASSERT_TRUE(waitFor([&] { return pinsChanged.count() >= 1; }, 30));
    const std::vector<int> pinned = drape.pinnedVertices();
    ASSERT_EQ(pinned.size(), 1U);
    const int vertex = pinned.front();
    EXPECT_FALSE(drape.running()) << "pinning alone does not start the drape";
    int documentPins = 0;
    for (const patterns::doc::Panel& p : drape.document().panels) {
        documentPins += static_cast<int>(p.pins.size());
    }
    EXPECT_EQ(documentPins, 1) << "the pin is in the document";

    // The viewport draws its pinhead where the vertex is.
    window.viewport().update();
    ASSERT_TRUE(waitFor(
        [&] {
            const auto at = window.viewport().drawnAt(vertex);
            if (!at) {
                return false;
            }
            const QImage picture =
                window.viewport().picture().convertToFormat(QImage::Format_RGB32);
            const QPoint px = (*at * window.viewport().devicePixelRatioF()).toPoint();
            const QColor c = picture.pixelColor(px);
            return c.red() > 170 && c.green() < 60 && c.blue() < 70;
        },
        10))
        << "a pinhead at the pinned vertex";

    // The drape runs; the pinned vertex stays exactly where it was pinned.
    drape.start();
    ASSERT_TRUE(waitFor([&] { return drape.progress().steps >= 10; }, 120));
    drape.pause();
    ASSERT_TRUE(waitFor([&] { return !drape.running(); }, 5));
    sim::Snapshot s;
    ASSERT_TRUE(drape.snapshot(s));
    EXPECT_EQ(s.clothPositions.row(vertex), scene->startPositions.row(vertex));
    EXPECT_TRUE(s.clothPositions.allFinite());

    // Alt+click on the pinhead unpins it, in the drape and the document.
    window.viewport().update();
    waitFor([] { return false; }, 0.2);
    const auto head = window.viewport().drawnAt(vertex);
    ASSERT_TRUE(head.has_value());
    QTest::mouseClick(&window.viewport(), Qt::LeftButton, Qt::AltModifier, head->toPoint());
    ASSERT_TRUE(waitFor([&] { return drape.pinnedVertices().empty(); }, 30));
    documentPins = 0;
    for (const patterns::doc::Panel& p : drape.document().panels) {
        documentPins += static_cast<int>(p.pins.size());
    }
    EXPECT_EQ(documentPins, 0);
    drape.pause();

    // Both went on the window's undo stack: undoing the unpin pins it again, undoing the pin
    // leaves none.
    // (The edit reaches the window by a queued call after the drape published the pins.)
    ASSERT_TRUE(waitFor([&] { return window.undoStack().count() == 2; }, 10));
    EXPECT_EQ(patterns::dumpDocument(window.project().document),
              patterns::dumpDocument(drape.document()));
    QSignalSpy rebuilt(&drape, &DrapeController::rebuilt);
    window.undoStack().undo();
    ASSERT_TRUE(waitFor([&] { return rebuilt.count() >= 1; }, 120));
    EXPECT_EQ(drape.pinnedVertices().size(), 1U);
    window.undoStack().undo();
    ASSERT_TRUE(waitFor([&] { return rebuilt.count() >= 2; }, 120));
    EXPECT_TRUE(drape.pinnedVertices().empty());
    EXPECT_FALSE(window.isModified());
}

TEST(MainWindow, UndoOfAPointMoveAndOfAMirrorGivesTheSavedBytesBack) {
    QTemporaryDir dir;
    MainWindow window(GARMENTS);
    RecordingPrompts prompts;
    prompts.install(window);
    window.setRecoveryDirectory(dir.filePath("recovery"));
    window.resize(1000, 600);
    window.show();
    ASSERT_TRUE(openAndWait(window, GARMENTS + "/skirt.atelier"));
    const QString original = dir.filePath("original.atelier");
    ASSERT_TRUE(window.saveAs(original));
    EXPECT_FALSE(window.isModified());
    const std::string saved = bytesOf(original);
    ASSERT_FALSE(saved.empty());

    // Drag the front panel's first outline point 23 mm right and 12 mm up with Shift held:
    // it lands on the 5 mm grid.
    PatternView& view = window.patternView();
    const patterns::doc::Panel front = window.project().document.panels.front();
    view.selectPanel(front.id);
    QCoreApplication::processEvents();
    ASSERT_EQ(view.selectedPanel(), front.id);
    const patterns::doc::Point point = front.outline.points.front();
    const patterns::Vec2 target = point.position + patterns::Vec2(0.023, 0.012);
    QWidget* surface = view.viewport();
    const QPoint from = view.viewPoint(front.id, point.position);
    const QPoint to = view.viewPoint(front.id, target);
    ASSERT_NE(from, to);
    QSignalSpy rebuilt(&window.drape(), &DrapeController::rebuilt);
    sendMouse(surface, QEvent::MouseButtonPress, from, Qt::LeftButton, Qt::LeftButton);
    EXPECT_EQ(view.selectedPoint(), point.id) << "pressing on a handle selects its point";
    sendMouse(surface, QEvent::MouseMove, to, Qt::NoButton, Qt::LeftButton, Qt::ShiftModifier);
    EXPECT_TRUE(view.dragLengths().contains("mm")) << view.dragLengths().toStdString();
    sendMouse(surface, QEvent::MouseButtonRelease, to, Qt::LeftButton, Qt::NoButton,
              Qt::ShiftModifier);
    ASSERT_EQ(window.undoStack().count(), 1);
    EXPECT_TRUE(window.undoStack().undoText().contains("move"))
        << window.undoStack().undoText().toStdString();
    const patterns::Vec2 moved =
        window.project().document.panel(front.id)->outline.points.front().position;
    for (int k = 0; k < 2; ++k) {
        const double mm = moved[k] * 1000;
        EXPECT_NEAR(mm / 5, std::round(mm / 5), 1e-6) << "on the 5 mm grid: " << mm;
        EXPECT_NEAR(moved[k], target[k], 0.005) << "the grid point near the mouse";
    }
    EXPECT_TRUE(window.isModified());
    EXPECT_TRUE(window.isWindowModified());
    EXPECT_TRUE(window.windowTitle().contains("[*]"));
    // The drape re-meshed the panel and went on from where it was.
    ASSERT_TRUE(waitFor([&] { return rebuilt.count() >= 1; }, 120));
    EXPECT_TRUE(rebuilt.front().front().toBool());
    EXPECT_EQ(patterns::dumpDocument(window.drape().document()),
              patterns::dumpDocument(window.project().document));

    const QString edited = dir.filePath("edited.atelier");
    ASSERT_TRUE(window.saveAs(edited));
    EXPECT_NE(bytesOf(edited), saved);
    window.undoStack().undo();
    EXPECT_TRUE(window.isModified()) << "clean is the edited file now";
    const QString undone = dir.filePath("undone.atelier");
    ASSERT_TRUE(window.saveAs(undone));
    EXPECT_EQ(bytesOf(undone), saved) << "undo gives the original bytes back";
    window.undoStack().redo();
    EXPECT_EQ(window.project().document.panel(front.id)->outline.points.front().position, moved);
    window.undoStack().undo();

    // Mirror the selected panel, then undo it.
    ASSERT_TRUE(window.mirrorSelectedPanel());
    const QString mirrored = dir.filePath("mirrored.atelier");
    ASSERT_TRUE(window.saveAs(mirrored));
    EXPECT_NE(bytesOf(mirrored), saved);
    window.undoStack().undo();
    ASSERT_TRUE(window.saveAs(undone));
    EXPECT_EQ(bytesOf(undone), saved) << "undoing the mirror gives the original bytes back";
    EXPECT_TRUE(prompts.errors.isEmpty()) << prompts.errors.join("; ").toStdString();
}

TEST(MainWindow, ADoubleClickAddsAPointAndDeleteRemovesIt) {
    QTemporaryDir dir;
    MainWindow window(GARMENTS);
    RecordingPrompts prompts;
    prompts.install(window);
    window.setRecoveryDirectory(dir.filePath("recovery"));
    window.resize(1000, 600);
    window.show();
    ASSERT_TRUE(openAndWait(window, GARMENTS + "/skirt.atelier"));
    PatternView& view = window.patternView();
    const patterns::doc::Panel front = window.project().document.panels.front();
    const std::size_t points = front.outline.points.size();
    view.selectPanel(front.id);
    QCoreApplication::processEvents();
    // The middle of the first outline edge.
    const patterns::Vec2 middle =
        patterns::pointAt(patterns::contourSegment(front.outline, 0), 0.5);
    QTest::mouseDClick(view.viewport(), Qt::LeftButton, {}, view.viewPoint(front.id, middle));
    ASSERT_EQ(window.undoStack().count(), 1) << prompts.errors.join("; ").toStdString();
    const patterns::doc::Panel added = *window.project().document.panel(front.id);
    ASSERT_EQ(added.outline.points.size(), points + 1);
    const patterns::doc::Point inserted = added.outline.points[1];
    EXPECT_LT((inserted.position - middle).norm(), 0.01) << "the point is on the edge";

    // Click its handle, press Delete: the point goes; undo twice gives the panel back.
    QTest::mouseClick(view.viewport(), Qt::LeftButton, {},
                      view.viewPoint(front.id, inserted.position));
    ASSERT_EQ(view.selectedPoint(), inserted.id);
    QTest::keyClick(&view, Qt::Key_Delete);
    ASSERT_EQ(window.undoStack().count(), 2) << prompts.errors.join("; ").toStdString();
    EXPECT_EQ(window.project().document.panel(front.id)->outline.points.size(), points);
    window.undoStack().undo();
    window.undoStack().undo();
    patterns::GarmentDocument only;
    only.panels.push_back(front);
    patterns::GarmentDocument now;
    now.panels.push_back(*window.project().document.panel(front.id));
    EXPECT_EQ(patterns::dumpDocument(now), patterns::dumpDocument(only));
    EXPECT_FALSE(window.isModified());
}

TEST(MainWindow, SaveAndOpenRoundTripAndRecentFiles) {
    QTemporaryDir dir;
    MainWindow window(GARMENTS);
    RecordingPrompts prompts;
    prompts.install(window);
    window.setRecoveryDirectory(dir.filePath("recovery"));
    ASSERT_TRUE(openAndWait(window, GARMENTS + "/tshirt.atelier"));
    ASSERT_TRUE(window.duplicateSelectedPanel() == false) << "nothing selected";
    window.patternView().selectPanel(window.project().document.panels.front().id);
    ASSERT_TRUE(window.duplicateSelectedPanel());
    const std::string edited = patterns::dumpDocument(window.project().document);
    const QString file = dir.filePath("shirt.atelier");
    ASSERT_TRUE(window.saveAs(file));
    EXPECT_EQ(window.projectPath(), file);
    EXPECT_FALSE(window.isModified());
    EXPECT_EQ(window.recentFiles().value(0), QFileInfo(file).absoluteFilePath());

    MainWindow other(GARMENTS);
    prompts.install(other);
    other.setRecoveryDirectory(dir.filePath("recovery"));
    ASSERT_TRUE(openAndWait(other, file));
    EXPECT_EQ(patterns::dumpDocument(other.project().document), edited);
    EXPECT_FALSE(other.isModified());
    const QString again = dir.filePath("again.atelier");
    ASSERT_TRUE(other.saveAs(again));
    EXPECT_EQ(bytesOf(again), bytesOf(file));
    EXPECT_EQ(other.recentFiles().value(0), QFileInfo(again).absoluteFilePath());
    EXPECT_EQ(other.recentFiles().value(1), QFileInfo(file).absoluteFilePath());
}

TEST(MainWindow, AMissingRecentFileIsRemovedWithAMessage) {
    QTemporaryDir dir;
    const QString kept = dir.filePath("kept.atelier");
    const QString gone = dir.filePath("gone.atelier");
    QSettings().setValue("files/recent", QStringList{gone, kept});
    MainWindow window(GARMENTS);
    RecordingPrompts prompts;
    prompts.install(window);
    window.setRecoveryDirectory(dir.filePath("recovery"));
    EXPECT_FALSE(window.openRecent(gone));
    ASSERT_EQ(prompts.errors.size(), 1);
    EXPECT_TRUE(prompts.errors.front().contains(gone));
    EXPECT_EQ(window.recentFiles(), QStringList{kept});
}

TEST(MainWindow, WindowGeometryAndSplitterSizesAreRemembered) {
    QTemporaryDir dir;
    QList<int> sizes;
    {
        MainWindow window(GARMENTS);
        window.setRecoveryDirectory(dir.filePath("recovery"));
        window.resize(1100, 700);
        window.show();
        auto* splitter = window.findChild<QSplitter*>();
        ASSERT_NE(splitter, nullptr);
        splitter->setSizes({300, 700});
        QCoreApplication::processEvents();
        sizes = splitter->sizes();
        ASSERT_TRUE(window.close());
    }
    MainWindow again(GARMENTS);
    again.show();
    QCoreApplication::processEvents();
    EXPECT_EQ(again.size(), QSize(1100, 700));
    EXPECT_EQ(again.findChild<QSplitter*>()->sizes(), sizes);
}

TEST(MainWindow, UnsavedChangesAreAskedAboutBeforeANewProject) {
    QTemporaryDir dir;
    MainWindow window(GARMENTS);
    RecordingPrompts prompts;
    prompts.install(window);
    window.setRecoveryDirectory(dir.filePath("recovery"));
    ASSERT_TRUE(openAndWait(window, GARMENTS + "/skirt.atelier"));
    window.patternView().selectPanel(window.project().document.panels.front().id);
    ASSERT_TRUE(window.mirrorSelectedPanel());
    prompts.answer = QMessageBox::Cancel;
    EXPECT_FALSE(window.newProject());
    EXPECT_FALSE(window.openProject(GARMENTS + "/tshirt.atelier"));
    window.show();
    EXPECT_FALSE(window.close()) << "closing is cancelled too";
    EXPECT_TRUE(window.isVisible());
    EXPECT_TRUE(window.isModified());
    EXPECT_EQ(window.project().document.panels.size(), 2U);
    prompts.answer = QMessageBox::Discard;
    QSignalSpy ready(&window, &MainWindow::projectReady);
    ASSERT_TRUE(window.newProject());
    EXPECT_FALSE(window.isModified());
    EXPECT_TRUE(window.project().document.panels.empty());
    EXPECT_TRUE(window.projectPath().isEmpty());
    EXPECT_EQ(window.undoStack().count(), 0);
    ASSERT_TRUE(waitFor([&] { return ready.count() >= 1; }, 60));
    EXPECT_FALSE(window.drape().staticScene()) << "nothing to drape";
}

TEST(MainWindow, ACorruptProjectIsAnErrorAndTheWindowKeepsItsProject) {
    QTemporaryDir dir;
    MainWindow window(GARMENTS);
    RecordingPrompts prompts;
    prompts.install(window);
    window.setRecoveryDirectory(dir.filePath("recovery"));
    ASSERT_TRUE(openAndWait(window, GARMENTS + "/skirt.atelier"));
    const std::string before = patterns::dumpDocument(window.project().document);
    std::string text = bytesOf(GARMENTS + "/skirt.atelier");
    const std::size_t at = text.find("\"fabric\": \"cotton\"");
    ASSERT_NE(at, std::string::npos);
    text.replace(at, 18, "\"fabric\": 12");
    const QString corrupt = dir.filePath("corrupt.atelier");
    ASSERT_TRUE(io::writeFileAtomically(corrupt.toStdString(), text).ok());
    EXPECT_FALSE(window.openProject(corrupt));
    ASSERT_EQ(prompts.errors.size(), 1);
    EXPECT_TRUE(prompts.errors.front().contains("corrupt.atelier"));
    EXPECT_TRUE(prompts.errors.front().contains("/materials/0/fabric"))
        << prompts.errors.front().toStdString();
    EXPECT_EQ(window.projectPath(), GARMENTS + "/skirt.atelier");
    EXPECT_EQ(patterns::dumpDocument(window.project().document), before);

    // Not JSON at all: an error too.
    ASSERT_TRUE(io::writeFileAtomically(corrupt.toStdString(), "{\"format\": ").ok());
    EXPECT_FALSE(window.openProject(corrupt));
    EXPECT_EQ(prompts.errors.size(), 2);

    // The window still edits and drapes.
    QSignalSpy rebuilt(&window.drape(), &DrapeController::rebuilt);
    window.patternView().selectPanel(window.project().document.panels.front().id);
    ASSERT_TRUE(window.mirrorSelectedPanel());
    ASSERT_TRUE(waitFor([&] { return rebuilt.count() >= 1; }, 120));
    EXPECT_TRUE(window.drape().staticScene());
}

// Trousers on the fit matrix's small female body: the leg slots place the fronts through each
// other at the crotch and the drape lifts one off its slot. The window says which, as the
// command line's report does.
TEST(MainWindow, PanelsPlacedThroughEachOtherAreNamedWhenPlaced) {
    QTemporaryDir dir;
    auto project = nlohmann::json::parse(bytesOf(GARMENTS + "/trousers.atelier"));
    const auto matrix = nlohmann::json::parse(
        bytesOf(QStringLiteral(ATELIER_SOURCE_DIR "/assets/batch/fit-matrix.json")));
    project["body"] = matrix["bodies"]["female-S"];
    project["simulation"]["particle_distance_mm"] = 20;
    const QString file = dir.filePath("trousers.atelier");
    ASSERT_TRUE(io::writeFileAtomically(file.toStdString(), project.dump(1)).ok());
    MainWindow window(GARMENTS);
    RecordingPrompts prompts;
    prompts.install(window);
    ASSERT_TRUE(openAndWait(window, file));
    const auto scene = window.drape().staticScene();
    ASSERT_EQ(scene->placementLifts.size(), 1U);
    const patterns::PlacementLift& lift = scene->placementLifts.front();
    EXPECT_EQ(lift.panel.rfind("front_", 0), 0U) << lift.panel;
    EXPECT_GT(lift.lift, 0.0);
    EXPECT_GT(scene->placedCrossings, 0);
    const QString message = window.statusBar()->currentMessage();
    EXPECT_TRUE(message.startsWith("Placed, panels placed through each other ("))
        << message.toStdString();
    EXPECT_TRUE(message.contains(QString::fromStdString(patterns::liftText(lift))))
        << message.toStdString();
    EXPECT_TRUE(prompts.errors.isEmpty());
}

TEST(MainWindow, ADroppedProjectFileIsOpened) {
    QTemporaryDir dir;
    MainWindow window(GARMENTS);
    RecordingPrompts prompts;
    prompts.install(window);
    window.setRecoveryDirectory(dir.filePath("recovery"));
    window.show();
    const QString file = GARMENTS + "/skirt.atelier";
    QSignalSpy ready(&window, &MainWindow::projectReady);
    const auto [entered, dropped] = dragAndDrop(window, file);
    EXPECT_TRUE(entered);
    EXPECT_TRUE(dropped);
    EXPECT_EQ(window.projectPath(), file);
    ASSERT_TRUE(waitFor([&] { return ready.count() >= 1; }, 120));
    EXPECT_EQ(window.drape().staticScene()->panelNames.size(), 2U);

    // Something else is refused.
    QMimeData text;
    text.setUrls({QUrl::fromLocalFile(dir.filePath("notes.txt"))});
    QDragEnterEvent other(QPoint(50, 50), Qt::CopyAction, &text, Qt::LeftButton, {});
    QApplication::sendEvent(&window, &other);
    EXPECT_FALSE(other.isAccepted());
}

TEST(MainWindow, ADroppedDxfPatternOpensItsPiecesAsANewProject) {
    QTemporaryDir dir;
    MainWindow window(GARMENTS);
    RecordingPrompts prompts;
    prompts.install(window);
    window.setRecoveryDirectory(dir.filePath("recovery"));
    window.show();
    const QString file = QStringLiteral(ATELIER_SOURCE_DIR "/tests/fuzz/corpus/three-pieces.dxf");
    QSignalSpy ready(&window, &MainWindow::projectReady);
    const auto [entered, dropped] = dragAndDrop(window, file);
    EXPECT_TRUE(entered);
    EXPECT_TRUE(dropped);
    // An import is a new project: no path yet, modified, its pieces placed and drawn.
    EXPECT_TRUE(window.projectPath().isEmpty());
    EXPECT_TRUE(window.isModified());
    ASSERT_EQ(window.project().garment.panels.size(), 3U);
    EXPECT_EQ(window.project().garment.panels[0].name, "FRONT");
    EXPECT_EQ(window.project().garment.panels[0].notches.size(), 2U);
    ASSERT_TRUE(waitFor([&] { return ready.count() >= 1; }, 120));
    EXPECT_EQ(window.drape().staticScene()->panelNames.size(), 3U);
}

TEST(MainWindow, ADroppedBodyMeshBecomesTheBodyUndoably) {
    QTemporaryDir dir;
    MainWindow window(GARMENTS);
    RecordingPrompts prompts;
    prompts.install(window);
    window.setRecoveryDirectory(dir.filePath("recovery"));
    ASSERT_TRUE(openAndWait(window, GARMENTS + "/skirt.atelier"));
    // The default mannequin written as an OBJ mesh: a body file.
    const auto mannequin = io::loadBody(patterns::BodySource{}, {}, {});
    ASSERT_TRUE(mannequin.ok());
    const QString mesh = dir.filePath("body.obj");
    ASSERT_TRUE(
        io::writeObj(mesh.toStdString(), mannequin.value().vertices, mannequin.value().triangles)
            .ok());
    QSignalSpy ready(&window, &MainWindow::projectReady);
    const auto [entered, dropped] = dragAndDrop(window, mesh);
    EXPECT_TRUE(entered);
    EXPECT_TRUE(dropped);
    ASSERT_EQ(window.project().body.meshPath, QFileInfo(mesh).absoluteFilePath().toStdString());
    EXPECT_EQ(window.undoStack().count(), 1);
    EXPECT_TRUE(window.isModified());
    ASSERT_TRUE(waitFor([&] { return ready.count() >= 1; }, 120))
        << prompts.errors.join("; ").toStdString();
    ASSERT_TRUE(window.drape().staticScene()) << prompts.errors.join("; ").toStdString();
    EXPECT_EQ(window.drape().staticScene()->bodyTriangles.rows(),
              mannequin.value().triangles.rows());
    // The Body dock shows the imported mesh (its unit and up axis detected), not measurements.
    BodyDock& dock = window.bodyDock();
    EXPECT_TRUE(dock.meshText().contains("body.obj")) << dock.meshText().toStdString();
    EXPECT_TRUE(dock.meshText().contains("unit: detected, up axis: detected"));
    EXPECT_FALSE(dock.field("waist")->isEnabled());
    EXPECT_FALSE(dock.baseChooser()->isEnabled());
    ASSERT_NE(dock.importButton()->defaultAction(), nullptr);
    EXPECT_TRUE(dock.importButton()->defaultAction()->text().contains("Import"));
    window.undoStack().undo();
    EXPECT_TRUE(dock.meshText().isEmpty()) << "the mannequin again";
    EXPECT_TRUE(dock.field("waist")->isEnabled());
    EXPECT_TRUE(window.project().body.meshPath.empty());
    EXPECT_FALSE(window.isModified());

    // A file that is no mesh is refused with a message naming it.
    const QString broken = dir.filePath("broken.obj");
    ASSERT_TRUE(io::writeFileAtomically(broken.toStdString(), "v 1 2\nf 1 2 3\n").ok());
    EXPECT_FALSE(window.openFile(broken));
    ASSERT_FALSE(prompts.errors.isEmpty());
    EXPECT_TRUE(prompts.errors.back().contains("broken.obj"));
    EXPECT_EQ(window.undoStack().count(), 1) << "nothing new on the stack";
}

/// The child of the recovery test: opens `project`, edits it (a point moved, a panel
/// mirrored), writes the edited project's text to `expected`, autosaves every second into
/// `recoveryDir`, says "autosaved" once the recovery file is there, and waits to be killed.
int autosaveChild(const QString& recoveryDir, const QString& project, const QString& expected) {
    MainWindow window(GARMENTS);
    RecordingPrompts prompts;
    prompts.install(window);
    window.setRecoveryDirectory(recoveryDir);
    window.setAutosaveSeconds(1);
    if (!openAndWait(window, project)) {
        return 1;
    }
    const patterns::doc::Panel& front = window.project().document.panels.front();
    const patterns::PanelId id = front.id;
    const patterns::PointId point = front.outline.points.front().id;
    const patterns::Vec2 to = front.outline.points.front().position + patterns::Vec2(0.01, 0);
    if (!window.edit(
            [&](patterns::GarmentDocument& d) { return patterns::movePoint(d, id, point, to); }) ||
        !window.edit([&](patterns::GarmentDocument& d) {
            return patterns::mirrorPanel(d, d.panels.back().id);
        })) {
        return 1;
    }
    if (!io::writeFileAtomically(expected.toStdString(), io::formatProject(window.project()))
             .ok()) {
        return 1;
    }
    if (!waitFor([&] { return QFileInfo::exists(window.recoveryFile()); }, 60)) {
        return 1;
    }
    std::puts("autosaved");
    std::fflush(stdout);
    waitFor([] { return false; }, 600);
    return 1;
}

TEST(MainWindow, AutosaveRecoversTheEditsOfAKilledProcess) {
    QTemporaryDir dir;
    const QString project = dir.filePath("skirt.atelier");
    ASSERT_TRUE(QFile::copy(GARMENTS + "/skirt.atelier", project));
    const QString recovery = dir.filePath("recovery");
    const QString expected = dir.filePath("expected.atelier");

    QProcess child;
    child.start(QCoreApplication::applicationFilePath(),
                {"--autosave-child", recovery, project, expected});
    ASSERT_TRUE(child.waitForStarted(30000));
    ASSERT_TRUE(waitFor(
        [&] {
            child.waitForReadyRead(50);
            return child.state() != QProcess::Running || child.peek(4096).contains("autosaved");
        },
        240))
        << child.readAllStandardError().toStdString();
    ASSERT_EQ(child.state(), QProcess::Running) << child.readAllStandardError().toStdString();
    child.kill(); // SIGKILL: no clean close, no chance to remove the recovery file
    ASSERT_TRUE(child.waitForFinished(30000));
    EXPECT_EQ(child.exitStatus(), QProcess::CrashExit);
    ASSERT_FALSE(QDir(recovery).entryList({"*.atelier"}, QDir::Files).isEmpty())
        << "the killed process left its recovery file";

    auto edited = io::loadProject(expected.toStdString());
    ASSERT_TRUE(edited.ok()) << edited.error().toString();

    // Start again: the recovery file is newer than the project; it is offered and restored.
    MainWindow window(GARMENTS);
    RecordingPrompts prompts;
    prompts.install(window);
    window.setRecoveryDirectory(recovery);
    QSignalSpy ready(&window, &MainWindow::projectReady);
    ASSERT_TRUE(window.offerRecovery());
    EXPECT_EQ(prompts.restoreOffers.size(), 1);
    EXPECT_EQ(patterns::dumpDocument(window.project().document),
              patterns::dumpDocument(edited.value().document));
    EXPECT_EQ(window.projectPath(), QFileInfo(project).absoluteFilePath());
    EXPECT_TRUE(window.isModified());
    ASSERT_TRUE(waitFor([&] { return ready.count() >= 1; }, 120));

    // Saving makes the project newer: the recovery file goes and nothing is offered again.
    ASSERT_TRUE(window.save());
    EXPECT_TRUE(QDir(recovery).entryList({"*.atelier"}, QDir::Files).isEmpty());
    MainWindow later(GARMENTS);
    RecordingPrompts laterPrompts;
    laterPrompts.install(later);
    later.setRecoveryDirectory(recovery);
    EXPECT_FALSE(later.offerRecovery());
    EXPECT_TRUE(laterPrompts.restoreOffers.isEmpty());
}

TEST(MainWindow, TwoWindowsOnOneProjectAutosaveToTwoFilesAndALostOneIsRecovered) {
    QTemporaryDir dir;
    const QString project = dir.filePath("skirt.atelier");
    ASSERT_TRUE(QFile::copy(GARMENTS + "/skirt.atelier", project));
    const QString recovery = dir.filePath("recovery");
    // Two windows on the same file, each renaming the front panel its own way.
    RecordingPrompts prompts[2];
    std::unique_ptr<MainWindow> windows[2];
    const char* names[2] = {"front of the first", "front of the second"};
    for (int k = 0; k < 2; ++k) {
        windows[k] = std::make_unique<MainWindow>(GARMENTS);
        prompts[k].install(*windows[k]);
        windows[k]->setRecoveryDirectory(recovery);
        ASSERT_TRUE(windows[k]->openProject(project));
        const patterns::PanelId front = windows[k]->project().document.panels.front().id;
        ASSERT_TRUE(windows[k]->edit([&](patterns::GarmentDocument& d) {
            return patterns::renamePanel(d, front, names[k]);
        }));
        ASSERT_TRUE(windows[k]->autosave());
    }
    const QString files[2] = {windows[0]->recoveryFile(), windows[1]->recoveryFile()};
    EXPECT_NE(files[0], files[1]);
    EXPECT_EQ(QDir(recovery).entryList({"*.atelier"}, QDir::Files).size(), 2);
    for (int k = 0; k < 2; ++k) {
        auto saved = io::loadProject(files[k].toStdString());
        ASSERT_TRUE(saved.ok()) << saved.error().toString();
        EXPECT_EQ(saved.value().document.panels.front().name, names[k]);
    }

    // The second window is gone without a clean close (as when its program is killed): a new
    // window is offered its file alone (the first window's is in use) and restores it.
    windows[1].reset();
    MainWindow next(GARMENTS);
    RecordingPrompts nextPrompts;
    nextPrompts.install(next);
    next.setRecoveryDirectory(recovery);
    ASSERT_TRUE(next.offerRecovery());
    ASSERT_EQ(nextPrompts.restoreOffers.size(), 1);
    EXPECT_EQ(QFileInfo(nextPrompts.restoreOffers.front()).fileName(),
              QFileInfo(files[1]).fileName());
    EXPECT_EQ(next.project().document.panels.front().name, names[1]);
    EXPECT_TRUE(QFileInfo::exists(files[0])) << "the open window's file is left alone";
    EXPECT_FALSE(QFileInfo::exists(files[1])) << "the restored file gives way to the new window's";
    EXPECT_TRUE(QFileInfo::exists(next.recoveryFile()));
}

TEST(MainWindow, TheProgramKilledAfterAnImportLeavesARecoveryFileThatRestoresIt) {
    // The real program: a GarmentCode import is an unsaved project; autosaved each second into
    // --recovery-dir, then the process is killed.
    const QString program = QStringLiteral(ATELIER_GUI);
    ASSERT_TRUE(QFileInfo(program).isExecutable()) << "not built: " << program.toStdString();
    const QString spec =
        QStringLiteral(ATELIER_SOURCE_DIR "/tests/fuzz/corpus/two-panels.garmentcode.json");
    QTemporaryDir dir;
    const QString recovery = dir.filePath("recovery");
    QProcess atelier;
    atelier.start(program, {"--recovery-dir", recovery, "--autosave-seconds", "1", spec});
    ASSERT_TRUE(atelier.waitForStarted(30000));
    ASSERT_TRUE(waitFor(
        [&] {
            atelier.waitForFinished(50);
            return atelier.state() != QProcess::Running ||
                   !QDir(recovery).entryList({"*.atelier"}, QDir::Files).isEmpty();
        },
        240));
    ASSERT_EQ(atelier.state(), QProcess::Running) << atelier.readAllStandardError().toStdString();
    atelier.kill();
    ASSERT_TRUE(atelier.waitForFinished(30000));
    EXPECT_EQ(atelier.exitStatus(), QProcess::CrashExit);

    // What the import gives, read back as the recovery file is.
    const auto mannequin = io::loadBody(patterns::BodySource{}, {}, {});
    ASSERT_TRUE(mannequin.ok());
    const auto imported = io::importGarmentCode(spec.toStdString(), mannequin.value());
    ASSERT_TRUE(imported.ok());
    const auto expected = io::parseProject(io::formatProject(imported.value().project), "x");
    ASSERT_TRUE(expected.ok());

    MainWindow window(GARMENTS);
    RecordingPrompts prompts;
    prompts.install(window);
    window.setRecoveryDirectory(recovery);
    ASSERT_TRUE(window.offerRecovery());
    EXPECT_EQ(patterns::dumpDocument(window.project().document),
              patterns::dumpDocument(expected.value().document));
    EXPECT_TRUE(window.projectPath().isEmpty()) << "an import has no file yet";
    EXPECT_TRUE(window.isModified());
}

} // namespace
} // namespace atelier::ui

int main(int argc, char** argv) {
    qputenv("QT_QPA_PLATFORM", "offscreen");
    // Settings, recent files and default recovery folders go to a test location.
    QStandardPaths::setTestModeEnabled(true);
    QApplication app(argc, argv);
    QApplication::setOrganizationName("AtelierTests");
    QApplication::setApplicationName("atelier_widget_tests");
    // Settings (recent files, geometry) of this process alone: none from an earlier run or a
    // test program running beside it.
    const QTemporaryDir settings;
    QSettings::setPath(QSettings::NativeFormat, QSettings::UserScope, settings.path());
    if (argc == 5 && std::string(argv[1]) == "--autosave-child") {
        return atelier::ui::autosaveChild(argv[2], argv[3], argv[4]);
    }
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
