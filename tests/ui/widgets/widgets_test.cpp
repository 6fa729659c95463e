// The desktop application's widgets without a display (QT_QPA_PLATFORM=offscreen): the drape
// controller on its worker thread, the pattern view, the viewport's picture.
#include "ui/render/headless_context.h"
#include "ui/widgets/drape_controller.h"
#include "ui/widgets/main_window.h"
#include "ui/widgets/pattern_view.h"
#include "ui/widgets/viewport.h"

#include <QApplication>
#include <QElapsedTimer>
#include <QSignalSpy>
#include <QTest>
#include <gtest/gtest.h>

namespace atelier::ui {
namespace {

const QString GARMENTS = QStringLiteral(ATELIER_SOURCE_DIR "/assets/garments");

/// Runs the event loop until `done` or `seconds` have passed; returns done().
template <class Done> bool waitFor(Done done, double seconds) {
    QElapsedTimer clock;
    clock.start();
    while (!done()) {
        if (clock.elapsed() > seconds * 1000) {
            return false;
        }
        QCoreApplication::processEvents(QEventLoop::AllEvents, 20);
    }
    return true;
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
                onCloth = QPoint(x, y) / window.viewport().devicePixelRatioF();
                break;
            }
        }
    }
    ASSERT_GE(onCloth.x(), 0);
    EXPECT_FALSE(window.drape().running());
    QTest::mousePress(&window.viewport(), Qt::LeftButton, {}, onCloth);
    ASSERT_TRUE(waitFor([&] { return window.drape().progress().steps >= 3; }, 120));
    QTest::mouseMove(&window.viewport(), onCloth + QPoint(30, -20));
    waitFor([] { return false; }, 0.3);
    QTest::mouseRelease(&window.viewport(), Qt::LeftButton, {}, onCloth + QPoint(30, -20));
    waitFor([] { return false; }, 0.3);
    window.drape().pause();
    ASSERT_TRUE(waitFor([&] { return !window.drape().running(); }, 5));
    sim::Snapshot s;
    ASSERT_TRUE(window.drape().snapshot(s));
    EXPECT_TRUE(s.clothPositions.allFinite());
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
                onCloth = QPoint(x, y) / window.viewport().devicePixelRatioF();
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
}

} // namespace
} // namespace atelier::ui

int main(int argc, char** argv) {
    qputenv("QT_QPA_PLATFORM", "offscreen");
    QApplication app(argc, argv);
    ::testing::InitGoogleTest(&argc, argv);
    return RUN_ALL_TESTS();
}
