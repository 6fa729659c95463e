// What the 3D view draws over the cloth (QT_QPA_PLATFORM=offscreen): the strain map (View >
// Strain map) and the seam lines (View > Seam lines), both following the drape.
#include "ui/render/headless_context.h"
#include "ui/render/overlays.h"
#include "ui/render/scene.h"
#include "ui/widgets/main_window.h"
#include "ui/widgets/panel_dock.h"
#include "ui/widgets/pattern_view.h"
#include "ui/widgets/viewport.h"
#include "ui/widgets/widget_test_support.h"

#include "patterns/curve.h"
#include "patterns/document.h"

#include <QAction>
#include <QImage>
#include <QSignalSpy>
#include <QTemporaryDir>
#include <QTest>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

namespace atelier::ui {
namespace {

using test::openAndWait;
using test::QuietPrompts;
using test::waitFor;

using test::GARMENTS;

bool haveEgl() {
    return render::HeadlessContext::create().ok();
}

/// A window on the skirt, placed, draped a few steps and paused, drawn.
struct DrapedSkirt {
    QTemporaryDir dir;
    MainWindow window{GARMENTS};
    QuietPrompts prompts;

    bool open() {
        prompts.install(window);
        window.setRecoveryDirectory(dir.filePath("recovery"));
        window.resize(900, 600);
        window.show();
        if (!openAndWait(window, GARMENTS + "/skirt.atelier")) {
            return false;
        }
        window.drape().start();
        if (!waitFor([&] { return window.drape().progress().steps >= 10; }, 120)) {
            return false;
        }
        window.drape().pause();
        return waitFor([&] { return !window.drape().running(); }, 30) && draw();
    }
    /// Draws the latest snapshot now (once the view has polled it: the same one 0.2 s apart);
    /// false when there is none or the view cannot draw.
    bool draw() {
        sim::Snapshot later;
        for (int tries = 0; tries < 50; ++tries) {
            if (!window.drape().snapshot(snapshot)) {
                return false;
            }
            waitFor([] { return false; }, 0.2); // the view polls 30 times a second
            if (window.drape().snapshot(later) && later.version == snapshot.version) {
                break;
            }
        }
        window.viewport().drawNow();
        return !window.viewport().picture().isNull();
    }
    sim::Snapshot snapshot;
};

/// Pixels of `picture` within `tolerance` of `colour` in every channel (0–255).
int pixelsNear(const QImage& picture, const render::Colour& colour, int tolerance, int fromX = 0) {
    const QImage rgb = picture.convertToFormat(QImage::Format_RGB32);
    int n = 0;
    for (int y = 0; y < rgb.height(); ++y) {
        for (int x = fromX; x < rgb.width(); ++x) {
            const QColor c = rgb.pixelColor(x, y);
            n += std::abs(c.red() - int(colour.r * 255)) <= tolerance &&
                         std::abs(c.green() - int(colour.g * 255)) <= tolerance &&
                         std::abs(c.blue() - int(colour.b * 255)) <= tolerance
                     ? 1
                     : 0;
        }
    }
    return n;
}

TEST(Viewport, TheStrainMapColoursTheClothByItsStrainWithItsLegend) {
    if (!haveEgl()) {
        GTEST_SKIP() << "no EGL context here";
    }
    DrapedSkirt s;
    ASSERT_TRUE(s.open()) << s.window.viewport().rendererError().toStdString();
    Viewport& view = s.window.viewport();
    const auto scene = s.window.drape().staticScene();
    QAction* strain = s.window.strainMapAction();
    EXPECT_TRUE(strain->isCheckable());
    EXPECT_FALSE(strain->isChecked()) << "off by default";
    EXPECT_FALSE(view.strainShown());
    // Off: each triangle in its panel's colour.
    ASSERT_EQ(std::ssize(view.garmentColours()), scene->garmentTriangles.rows());
    const auto [backFirst, backCount] = scene->panelTriangles.at(1);
    EXPECT_EQ(view.garmentColours().front().r, render::panelColour(0).r);
    EXPECT_EQ(view.garmentColours()[static_cast<std::size_t>(backFirst)].b,
              render::panelColour(1).b);
    const QImage plain = view.picture();

    strain->trigger();
    EXPECT_TRUE(view.strainShown());
    ASSERT_TRUE(s.draw());
    // On: the strain of the snapshot drawn against the pattern, at ±10%.
    const std::vector<render::Colour> expected =
        render::strainColours(render::triangleStrain(s.snapshot.clothPositions,
                                                     scene->garmentTriangles, scene->patternUvs),
                              Viewport::STRAIN_RANGE);
    ASSERT_EQ(view.garmentColours().size(), expected.size());
    int differ = 0;
    for (std::size_t t = 0; t < expected.size(); ++t) {
        EXPECT_EQ(view.garmentColours()[t].r, expected[t].r) << "triangle " << t;
        EXPECT_EQ(view.garmentColours()[t].b, expected[t].b) << "triangle " << t;
        differ += view.garmentColours()[t].g != render::panelColour(0).g ? 1 : 0;
    }
    EXPECT_GT(differ, std::ssize(expected) / 2) << "the colours are no longer the panels'";
    // The picture: the front panel's brick is gone, and the legend's saturated ends are drawn
    // on the right (none in the plain picture).
    const QImage mapped = view.picture();
    EXPECT_GT(pixelsNear(plain, render::panelColour(0), 25), 1000);
    EXPECT_LT(pixelsNear(mapped, render::panelColour(0), 25),
              pixelsNear(plain, render::panelColour(0), 25) / 10);
    // The legend's bar is drawn flat (its colours exact); the lit cloth's pixels rarely are.
    const int right = mapped.width() * 3 / 5;
    const render::Colour red = render::strainColours(sim::VecX::Constant(1, 1.0), 0.1).front();
    const render::Colour blue = render::strainColours(sim::VecX::Constant(1, -1.0), 0.1).front();
    EXPECT_GT(pixelsNear(mapped, red, 3, right), 20);
    EXPECT_GT(pixelsNear(mapped, blue, 3, right), 20);
    EXPECT_EQ(pixelsNear(plain, red, 3, right), 0);
    EXPECT_EQ(pixelsNear(plain, blue, 3, right), 0);

    // Off again: the panels' colours come back.
    strain->trigger();
    ASSERT_TRUE(s.draw());
    EXPECT_EQ(view.garmentColours().front().g, render::panelColour(0).g);
    EXPECT_GT(pixelsNear(view.picture(), render::panelColour(0), 25), 1000);
}

TEST(Viewport, SeamLinesFollowTheClothInTheirSeamsColours) {
    if (!haveEgl()) {
        GTEST_SKIP() << "no EGL context here";
    }
    DrapedSkirt s;
    ASSERT_TRUE(s.open()) << s.window.viewport().rendererError().toStdString();
    Viewport& view = s.window.viewport();
    const auto scene = s.window.drape().staticScene();
    const patterns::GarmentDocument& document = s.window.project().document;
    EXPECT_TRUE(s.window.seamLinesAction()->isChecked()) << "on by default";
    ASSERT_EQ(scene->seamLines.size(), document.seams.size()) << "every seam has its lines";
    ASSERT_EQ(view.seamLines().size(), scene->seamLines.size());

    std::set<std::pair<int, int>> edges;
    for (Eigen::Index t = 0; t < scene->garmentTriangles.rows(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const int a = scene->garmentTriangles(t, k);
            const int b = scene->garmentTriangles(t, (k + 1) % 3);
            edges.emplace(std::min(a, b), std::max(a, b));
        }
    }
    const auto panelOf = [&](int vertex) {
        for (std::size_t p = 0; p < scene->panelTriangles.size(); ++p) {
            const auto [first, count] = scene->panelTriangles[p];
            if ((scene->garmentTriangles.middleRows(first, count).array() == vertex).any()) {
                return static_cast<int>(p);
            }
        }
        return -1;
    };
    for (std::size_t k = 0; k < scene->seamLines.size(); ++k) {
        const SeamLine& seam = scene->seamLines[k];
        const render::DrawLines& drawn = view.seamLines()[k];
        const patterns::doc::Seam& documentSeam =
            document.seams.at(static_cast<std::size_t>(seam.seam));
        const render::Colour colour = render::seamColour(seam.seam);
        EXPECT_EQ(drawn.colour.r, colour.r) << "the pattern view's colour of the seam";
        EXPECT_EQ(drawn.colour.g, colour.g);
        // Both sides, each a chain of cloth edges along its sewn vertices: as many segments as
        // vertices less one per side's range.
        const auto ranges =
            static_cast<Eigen::Index>(documentSeam.a.size() + documentSeam.b.size());
        EXPECT_GE(drawn.segments.rows(), std::ssize(seam.vertices) - ranges);
        EXPECT_GT(drawn.segments.rows(), 10);
        std::set<int> panels;
        for (Eigen::Index i = 0; i < drawn.segments.rows(); ++i) {
            const int a = seam.vertices[static_cast<std::size_t>(drawn.segments(i, 0))];
            const int b = seam.vertices[static_cast<std::size_t>(drawn.segments(i, 1))];
            EXPECT_TRUE(edges.contains({std::min(a, b), std::max(a, b)}))
                << "segment " << i << " is an edge of the cloth";
            panels.insert(panelOf(a));
        }
        EXPECT_EQ(panels.size(), 2u) << "the skirt's side seams join front and back";
        // The lines lie on the cloth as drawn: the paused drape, not where it was placed.
        ASSERT_EQ(drawn.positions.rows(), std::ssize(seam.vertices));
        double moved = 0;
        for (std::size_t i = 0; i < seam.vertices.size(); ++i) {
            const auto row = static_cast<Eigen::Index>(i);
            EXPECT_EQ(drawn.positions.row(row), s.snapshot.clothPositions.row(seam.vertices[i]));
            moved = std::max(
                moved,
                (drawn.positions.row(row) - scene->startPositions.row(seam.vertices[i])).norm());
        }
        EXPECT_GT(moved, 1e-4) << "the drape moved the seams since they were placed [m]";
    }
    // Drawn in the picture in the first seam's colour; hidden, they are gone.
    const render::Colour first = render::seamColour(scene->seamLines.front().seam);
    const int shown = pixelsNear(view.picture(), first, 40);
    EXPECT_GT(shown, 30);
    s.window.seamLinesAction()->trigger();
    ASSERT_TRUE(s.draw());
    EXPECT_TRUE(view.seamLines().empty());
    EXPECT_LT(pixelsNear(view.picture(), first, 40), shown / 4);
}

TEST(Viewport, TheSelectionIsMirroredBetweenThePatternAndTheCloth) {
    if (!haveEgl()) {
        GTEST_SKIP() << "no EGL context here";
    }
    DrapedSkirt s;
    ASSERT_TRUE(s.open()) << s.window.viewport().rendererError().toStdString();
    Viewport& view = s.window.viewport();
    const auto scene = s.window.drape().staticScene();
    const patterns::PanelId front = s.window.project().document.panels.at(0).id;
    const patterns::PanelId back = s.window.project().document.panels.at(1).id;
    const auto colourOf = [&](int panel) {
        return view.garmentColours().at(static_cast<std::size_t>(
            scene->panelTriangles.at(static_cast<std::size_t>(panel)).first));
    };
    // Selected in the pattern: lighter on the cloth, the other panel as it was.
    s.window.patternView().selectPanel(front);
    QCoreApplication::processEvents();
    EXPECT_EQ(view.selectedPanel(), "front");
    ASSERT_TRUE(s.draw());
    const render::Colour lighter = Viewport::selectedColour(render::panelColour(0));
    EXPECT_EQ(colourOf(0).r, lighter.r);
    EXPECT_EQ(colourOf(0).b, lighter.b);
    EXPECT_GT(lighter.g, render::panelColour(0).g);
    EXPECT_EQ(colourOf(1).g, render::panelColour(1).g);

    // A press on the back panel's cloth in 3D selects it in the pattern and the Panel dock.
    view.setView(render::View::Back);
    ASSERT_TRUE(s.draw());
    const QImage picture = view.picture().convertToFormat(QImage::Format_RGB32);
    const render::Colour denim = render::panelColour(1);
    QPoint onBack(-1, -1);
    for (int y = picture.height() / 3; y < picture.height() && onBack.x() < 0; ++y) {
        for (int x = picture.width() / 3; x < 2 * picture.width() / 3; ++x) {
            const QColor c = picture.pixelColor(x, y);
            if (std::abs(c.redF() - denim.r) + std::abs(c.greenF() - denim.g) +
                    std::abs(c.blueF() - denim.b) <
                0.2) {
                onBack = QPoint(x + 2, y + 2) / view.devicePixelRatioF();
                break;
            }
        }
    }
    ASSERT_GE(onBack.x(), 0) << "the back panel is in the back view";
    QTest::mousePress(&view, Qt::LeftButton, {}, onBack);
    QTest::mouseRelease(&view, Qt::LeftButton, {}, onBack);
    EXPECT_EQ(s.window.patternView().selectedPanel(), back);
    EXPECT_EQ(s.window.panelDock().panel(), back);
    EXPECT_EQ(view.selectedPanel(), "back");
    s.window.drape().pause(); // the press grabbed the cloth too
    ASSERT_TRUE(waitFor([&] { return !s.window.drape().running(); }, 30));
    ASSERT_TRUE(s.draw());
    EXPECT_EQ(colourOf(0).g, render::panelColour(0).g) << "the front is no longer selected";
    EXPECT_EQ(colourOf(1).g, Viewport::selectedColour(denim).g);

    // With the Seam tool, a press on the cloth picks the outline edge nearest it, as a click on
    // that edge in the pattern would, and grabs nothing: here in a triangle at the back panel's
    // lowest vertex in the pattern (on its hem).
    PatternView& pattern = s.window.patternView();
    pattern.setTool(PatternView::Tool::Seam);
    EXPECT_TRUE(view.seamPicking());
    const auto [first, count] = scene->panelTriangles.at(1);
    int lowest = -1;
    for (int t = first; t < first + count; ++t) {
        for (int k = 0; k < 3; ++k) {
            const int v = scene->garmentTriangles(t, k);
            if (lowest < 0 || scene->patternUvs(v, 1) < scene->patternUvs(lowest, 1)) {
                lowest = v;
            }
        }
    }
    int atHem = -1;
    for (int t = first; t < first + count && atHem < 0; ++t) {
        for (int k = 0; k < 3; ++k) {
            atHem = scene->garmentTriangles(t, k) == lowest ? t : atHem;
        }
    }
    ASSERT_GE(atHem, 0);
    QPointF inside(0, 0);
    for (int k = 0; k < 3; ++k) {
        const auto drawn = view.drawnAt(scene->garmentTriangles(atHem, k));
        ASSERT_TRUE(drawn);
        inside += *drawn / 3;
    }
    const auto under = view.patternPointAt(inside);
    ASSERT_TRUE(under);
    EXPECT_EQ(under->first, "back");
    const patterns::doc::Panel& backPanel = *s.window.project().document.panel(back);
    QSignalSpy picked(&view, &Viewport::panelPicked); // emitted with every grab
    QTest::mousePress(&view, Qt::LeftButton, {}, inside.toPoint());
    QTest::mouseRelease(&view, Qt::LeftButton, {}, inside.toPoint());
    EXPECT_EQ(picked.count(), 0) << "nothing grabbed";
    const auto& side = pattern.seamPick(0);
    ASSERT_EQ(side.size(), 1U);
    EXPECT_EQ(side.front().panel, back);
    // The edge through the lowest vertex's pattern point: the one nearest it.
    const patterns::Vec2 low = scene->patternUvs.row(lowest).transpose();
    double nearest = INFINITY;
    patterns::EdgeId expected;
    for (std::size_t e = 0; e < backPanel.outline.edges.size(); ++e) {
        const patterns::Segment seg = patterns::contourSegment(backPanel.outline, e);
        for (int k = 0; k <= 100; ++k) {
            if (const double d = (patterns::pointAt(seg, k / 100.0) - low).norm(); d < nearest) {
                nearest = d;
                expected = backPanel.outline.edges[e].id;
            }
        }
    }
    EXPECT_LT(nearest, 0.005) << "the lowest vertex is on the outline (as the mesher flattens it)";
    EXPECT_EQ(side.front().edge, expected);
    EXPECT_EQ(side.front().t0, 0.0) << "the whole edge, as a plain click picks it";
    EXPECT_EQ(side.front().t1, 1.0);
    // Another tool: the press grabs again.
    pattern.setTool(PatternView::Tool::Select);
    EXPECT_FALSE(view.seamPicking());
}

} // namespace
} // namespace atelier::ui
